// The smoothing layer on real range data: a Stanford bunny scan measured
// against the zippered reference mesh, and two PCL sensor views. Every test
// skips (with the missing path) when the shared data is absent.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/ndt/smoothing.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace icrkit::ndt {
namespace {

std::string sharedData(const std::string& relative) { return std::string(ICRKIT_SHARED_DATA_DIR) + "/" + relative; }

#define REQUIRE_SHARED_FILE(path)                                                                 \
  do {                                                                                            \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found: " << (path); \
  } while (0)

// Distance from p to the closed triangle (a, b, c): to the plane when the
// foot of the perpendicular falls inside, else to the nearest side.
double pointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (area2 > 0) {
    // Barycentric coordinates of the foot via the signed sub-triangle areas.
    const Eigen::Vector3d foot = p - n * ((p - a).dot(n) / area2);
    const double u = (c - b).cross(foot - b).dot(n);
    const double v = (a - c).cross(foot - c).dot(n);
    const double w = (b - a).cross(foot - a).dot(n);
    if (u >= 0 && v >= 0 && w >= 0) return (p - foot).norm();
  }
  return std::min({pointSegmentDistance(p, a, b), pointSegmentDistance(p, b, c), pointSegmentDistance(p, c, a)});
}

// Distance to a mesh surface: the exact distance to every face incident to
// the k nearest vertices. On a mesh whose triangles are not much larger than
// the query distances (bun_zipper: ~1 mm edges, errors of a few tenths) the
// nearest face almost always touches one of them, and when it does not the
// answer is an upper bound off by a fraction of an edge length.
class MeshDistance {
public:
  explicit MeshDistance(const TriangleMesh& mesh) : mesh_(mesh), tree_(mesh_.vertices.positions) {
    incident_.resize(mesh_.vertexCount());
    for (std::size_t f = 0; f < mesh_.faceCount(); ++f)
      for (int k = 0; k < 3; ++k) incident_[static_cast<std::size_t>(mesh_.faces[f](k))].push_back(f);
  }

  double operator()(const Eigen::Vector3d& p, std::size_t k = 8) const {
    double best = std::numeric_limits<double>::infinity();
    const auto& v = mesh_.vertices.positions;
    for (const Neighbour& nb : tree_.nearest(p, k)) {
      best = std::min(best, nb.distance);  // a vertex with no face still counts
      for (std::size_t f : incident_[nb.index]) {
        const Triangle& t = mesh_.faces[f];
        best = std::min(best, pointTriangleDistance(p, v[static_cast<std::size_t>(t(0))], v[static_cast<std::size_t>(t(1))],
                                                    v[static_cast<std::size_t>(t(2))]));
      }
    }
    return best;
  }

  double nearestVertex(const Eigen::Vector3d& p) const { return tree_.nearest(p, 1).front().distance; }

private:
  TriangleMesh mesh_;
  KdTree tree_;  // refers to mesh_'s positions, declared after it
  std::vector<std::vector<std::size_t>> incident_;
};

TEST(MeshDistanceHelper, KnownAnswersOnATriangle) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_DOUBLE_EQ(pointTriangleDistance(Eigen::Vector3d(0.2, 0.2, 0.5), a, b, c), 0.5);   // above the inside
  EXPECT_DOUBLE_EQ(pointTriangleDistance(Eigen::Vector3d(0.5, -1.0, 0.0), a, b, c), 1.0);  // beside edge ab
  EXPECT_DOUBLE_EQ(pointTriangleDistance(Eigen::Vector3d(-3, -4, 0), a, b, c), 5.0);       // beyond vertex a
  EXPECT_NEAR(pointTriangleDistance(Eigen::Vector3d(1, 1, 0), a, b, c), std::sqrt(0.5), 1e-15);  // beyond edge bc
}

struct Pose {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  // The data README's convention: a scan point p maps to R(q)^T p + t.
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return q.toRotationMatrix().transpose() * p + t; }
};

std::optional<Pose> bunConfPose(const std::string& conf, const std::string& scan) {
  std::ifstream in(conf);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string kind, file;
    Pose pose;
    double qx, qy, qz, qw;
    if (words >> kind >> file >> pose.t.x() >> pose.t.y() >> pose.t.z() >> qx >> qy >> qz >> qw && kind == "bmesh" &&
        file == scan) {
      pose.q = Eigen::Quaterniond(qw, qx, qy, qz).normalized();
      return pose;
    }
  }
  return std::nullopt;
}

double meanDistance(const MeshDistance& distance, const std::vector<Eigen::Vector3d>& points, bool to_vertices = false) {
  double sum = 0;
  for (const Eigen::Vector3d& p : points) sum += to_vertices ? distance.nearestVertex(p) : distance(p);
  return sum / static_cast<double>(points.size());
}

// The bun000 laser scan moved into bun_zipper's frame by its bun.conf pose.
// Leaves `scan` empty after a skip (shared data absent) or a failure; a
// void function so that GTEST_SKIP and ASSERT can end it.
void readBun000InReferenceFrame(PointCloud& scan) {
  const std::string scan_path = sharedData("stanford-bunny/bun000.ply");
  const std::string conf_path = sharedData("stanford-bunny/bun.conf");
  REQUIRE_SHARED_FILE(scan_path);
  REQUIRE_SHARED_FILE(conf_path);
  const std::optional<Pose> pose = bunConfPose(conf_path, "bun000.ply");
  ASSERT_TRUE(pose) << "no bmesh line for bun000.ply in " << conf_path;
  scan = io::readPointCloud(scan_path);
  for (Eigen::Vector3d& p : scan.positions) p = pose->apply(p);
}

TEST(SmoothingRealData, BunnyScanWithAddedNoiseMovesCloserToTheReferenceMesh) {
  const std::string mesh_path = sharedData("stanford-bunny/bun_zipper.ply");
  REQUIRE_SHARED_FILE(mesh_path);
  PointCloud scan;
  readBun000InReferenceFrame(scan);
  if (scan.empty()) return;  // skipped or failed inside
  const MeshDistance distance(io::readTriangleMesh(mesh_path));

  // Noise of sigma 0.5 mm, each point along its own random direction (a
  // normalised 3D Gaussian is uniform on the sphere).
  const double sigma = 0.0005;
  std::mt19937_64 rng(4242);
  std::normal_distribution<double> gauss;
  PointCloud noisy = scan;
  for (Eigen::Vector3d& p : noisy.positions) {
    const Eigen::Vector3d direction = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    p += sigma * gauss(rng) * direction;
  }
  PointCloud smoothed = noisy;
  SmoothingParameters params;
  params.radius = Length::spacings(4.0);
  const SmoothingReport summary = smoothPointCloud(smoothed, params);

  const double raw = meanDistance(distance, scan.positions);
  const double before = meanDistance(distance, noisy.positions);
  const double after = meanDistance(distance, smoothed.positions);
  const double before_vertex = meanDistance(distance, noisy.positions, true);
  const double after_vertex = meanDistance(distance, smoothed.positions, true);
  ::testing::Test::RecordProperty("scan_mm", std::to_string(raw * 1e3));
  ::testing::Test::RecordProperty("noisy_mm", std::to_string(before * 1e3));
  ::testing::Test::RecordProperty("smoothed_mm", std::to_string(after * 1e3));
  std::printf("[ bun000 ] %zu points, spacing %.3f mm, r = %.3f mm, excluded %.1f %%; mean distance to bun_zipper "
              "surface: scan %.4f, noisy %.4f, smoothed %.4f mm (to the nearest vertex: noisy %.4f, smoothed %.4f mm)\n",
              summary.points, summary.median_spacing_m * 1e3, summary.radius_m * 1e3,
              100.0 * static_cast<double>(summary.preselection.excluded) / static_cast<double>(summary.points), raw * 1e3, before * 1e3,
              after * 1e3, before_vertex * 1e3, after_vertex * 1e3);

  // The added noise must be visible over the scan's own registration error,
  // or the comparison below says nothing.
  ASSERT_GT(before, raw + 0.1e-3);
  EXPECT_LT(after, before) << "smoothing moved the noisy scan away from the reference surface";
  // Most of the added noise goes: the smoothed scan is much nearer to the raw
  // scan's own distance than to the noisy one.
  EXPECT_LT(after - raw, 0.5 * (before - raw));
  // The same sanity as for the PCL views: preselection keeps a part of a
  // real scan.
  EXPECT_LT(static_cast<double>(summary.preselection.excluded), 0.95 * static_cast<double>(summary.points))
      << "mean flatness " << summary.preselection.mean_flatness << ", mean cardinality " << summary.preselection.mean_cardinality;
}

TEST(SmoothingRealData, RecordedUncertaintyOnTheNoisyBunnyScanMatchesWhatTheReferenceShows) {
  // The bun000 laser scan in the reference frame with Gaussian noise of
  // 0.5 mm in random directions (0.29 mm along any normal), then the raw
  // normal estimation and the smoothing: their recorded sigmas against the
  // errors measured on the zippered reference mesh (its surface, its
  // area-weighted face normals at the nearest vertex).
  const std::string mesh_path = sharedData("stanford-bunny/bun_zipper.ply");
  REQUIRE_SHARED_FILE(mesh_path);
  PointCloud cloud;
  readBun000InReferenceFrame(cloud);
  if (cloud.empty()) return;  // skipped or failed inside
  std::mt19937_64 rng(77);
  std::normal_distribution<double> gauss;
  for (Eigen::Vector3d& p : cloud.positions)
    p += 0.0005 * gauss(rng) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  TriangleMesh reference = io::readTriangleMesh(mesh_path);
  computeVertexNormals(reference);
  const KdTree reference_vertices(reference.vertices.positions);
  const MeshDistance distance(reference);

  PointCloud raw = cloud;
  estimateNormals(raw);
  PointCloud smoothed = cloud;
  SmoothingParameters params;
  params.preselection.rule = PreselectionRule::None;
  smoothPointCloud(smoothed, params);

  for (const PointCloud* fitted : {&raw, &smoothed}) {
    const Attribute& normal_sigma = fitted->attributes.get("normal_sigma");
    const Attribute& position_sigma = fitted->attributes.get("position_sigma");
    double angle2 = 0, recorded_angle2 = 0, offset2 = 0, recorded_offset2 = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < fitted->size(); i += 7) {  // a sample keeps the test quick
      ASSERT_TRUE(std::isfinite(normal_sigma.values[i]) && normal_sigma.values[i] > 0 && normal_sigma.values[i] <= M_PI / 2 + 1e-6);
      ASSERT_TRUE(std::isfinite(position_sigma.values[i]) && position_sigma.values[i] > 0);
      const Neighbour nearest = reference_vertices.nearest(fitted->positions[i], 1).front();
      const double cosine = std::abs(fitted->normals[i].dot(reference.vertices.normals[nearest.index]));
      const double angle = std::acos(std::min(1.0, cosine));
      angle2 += angle * angle;
      recorded_angle2 += normal_sigma.values[i] * normal_sigma.values[i];
      const double d = distance(fitted->positions[i]);
      offset2 += d * d;
      recorded_offset2 += position_sigma.values[i] * position_sigma.values[i];
      ++n;
    }
    const double angle = std::sqrt(angle2 / n), recorded_angle = std::sqrt(recorded_angle2 / n);
    const double offset = std::sqrt(offset2 / n), recorded_offset = std::sqrt(recorded_offset2 / n);
    std::printf("[ bun000 + 0.5 mm, %s ] normal: recorded %.2f deg, against the reference %.2f deg; position: "
                "recorded %.3f mm, against the reference %.3f mm\n",
                fitted == &raw ? "raw" : "smoothed", recorded_angle * 180 / M_PI, angle * 180 / M_PI,
                recorded_offset * 1e3, offset * 1e3);
    // The reference itself is a reconstruction (registration error about
    // 0.5 mm median, its own normals a few degrees off), so the measured
    // errors hold the reference's too: the recorded sigmas may fall short,
    // but not by more than that, and must not overstate the error.
    EXPECT_LT(recorded_angle, 1.2 * angle);
    EXPECT_GT(recorded_angle, 0.4 * angle);
    EXPECT_LT(recorded_offset, 1.2 * offset);
    EXPECT_GT(recorded_offset, 0.3 * offset);
  }
}

// The share of `cloud`'s points that `rule` excludes, from the attributes
// the smoothing wrote (as `icrkit evaluate --preselection` recomputes them).
double excludedShare(const PointCloud& cloud, PreselectionRule rule) {
  PreselectionParameters params;
  params.rule = rule;
  const Preselection p = preselect(cloud.attributes.get("cardinality").values, cloud.attributes.get("flatness").values,
                                   params);
  return static_cast<double>(p.summary.excluded) / static_cast<double>(cloud.size());
}

void checkPclView(const std::string& file) {
  const std::string path = sharedData("pcl-views/" + file);
  REQUIRE_SHARED_FILE(path);
  PointCloud cloud = io::readPointCloud(path);
  ASSERT_GT(cloud.size(), 1000u);
  SmoothingParameters params;
  params.viewpoint = Eigen::Vector3d::Zero();  // both files: VIEWPOINT 0 0 0, the camera at the origin
  const SmoothingReport summary = smoothPointCloud(cloud, params);
  const double excluded = static_cast<double>(summary.preselection.excluded) / static_cast<double>(summary.points);
  std::size_t towards = 0, unit = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (std::abs(cloud.normals[i].norm() - 1.0) < 1e-9) ++unit;
    if (cloud.normals[i].dot(-cloud.positions[i]) >= 0) ++towards;
  }
  std::printf("[ %s ] %zu points, spacing %.3f mm, r = %.3f mm, mean cardinality %.1f, mean flatness %.2f, "
              "excluded %.1f %% (cardinality only %zu, flatness only %zu, both %zu), small windows %zu, "
              "mean displacement %.3f mm, %.0f ms\n",
              file.c_str(), summary.points, summary.median_spacing_m * 1e3, summary.radius_m * 1e3,
              summary.preselection.mean_cardinality, summary.preselection.mean_flatness, 100 * excluded, summary.preselection.excluded_cardinality_only,
              summary.preselection.excluded_flatness_only, summary.preselection.excluded_both, summary.small_windows,
              summary.mean_displacement_m * 1e3, summary.time_ms);
  const double paper = excludedShare(cloud, PreselectionRule::PaperMean);
  std::printf("[ %s ] preselection: default excludes %.1f %%, paper-mean %.1f %%\n", file.c_str(), 100 * excluded,
              100 * paper);
  // Issue 18's bound for the default rule on real single views; it still
  // finds something to exclude (flying points, depth edges).
  EXPECT_GT(excluded, 0.0);
  EXPECT_LE(excluded, 0.20);
  EXPECT_GT(paper, excluded) << "the paper's literal rule excludes more than the default";
  EXPECT_GT(summary.preselection.mean_cardinality, 3.0);
  EXPECT_GT(summary.radius_m, 0.0);
  EXPECT_LT(summary.mean_displacement_m, summary.radius_m) << "a projection onto the window plane moves less than r";
  EXPECT_EQ(unit + summary.small_windows, cloud.size()) << "every smoothed point has a unit normal";
  EXPECT_EQ(towards, cloud.size()) << "normals face the camera";
}

TEST(SmoothingRealData, PclMilkCartonView) { checkPclView("milk.pcd"); }

// A whole stereo scene: a large, flat table with quantised depth next to
// sparse far points. Its flatness is heavy-tailed and two-moded (near table
// F ~ 10, far background F ~ 2.4, whose stereo noise grows with range): the
// paper's mean thresholds keep only a few dozen points, the default's
// median and spread of ln F keep most of both.
TEST(SmoothingRealData, PclTableSceneStereoView) { checkPclView("table_scene_mug_stereo_textured.pcd"); }

// The Stanford laser scan as it is: clean, curved surface. The paper's rule
// excludes three quarters of it (two "below the mean" tests), the default
// a few per cent (its curved rims and depth edges).
TEST(SmoothingRealData, PreselectionRulesOnTheBunnyLaserScan) {
  const std::string path = sharedData("stanford-bunny/bun000.ply");
  REQUIRE_SHARED_FILE(path);
  PointCloud cloud = io::readPointCloud(path);
  const SmoothingReport summary = smoothPointCloud(cloud);
  const double excluded = static_cast<double>(summary.preselection.excluded) / static_cast<double>(summary.points);
  const double paper = excludedShare(cloud, PreselectionRule::PaperMean);
  std::printf("[ bun000 as scanned ] %zu points, default excludes %.1f %% (F < %.2f or |W| < %.1f), paper-mean %.1f %%\n",
              summary.points, 100 * excluded, summary.preselection.flatness_threshold,
              summary.preselection.cardinality_threshold, 100 * paper);
  EXPECT_EQ(summary.preselection.rule, PreselectionRule::Robust);
  EXPECT_GT(excluded, 0.0);
  EXPECT_LE(excluded, 0.20);
  EXPECT_GE(paper, 0.5);
}

}  // namespace
}  // namespace icrkit::ndt
