/// \file
/// Octree fusion of simulated views with ground-truth poses: outliers
/// injected in space other views see through are dropped, surface points
/// are kept, each with its view and viewpoint.

#include "simulated_recordings.hpp"
#include "synthetic_scans.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/ray_caster.hpp>
#include <icrkit/reconstruction/fusion/octree_fusion.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace icrkit::reconstruction {
namespace {

using testing_support::simulatedRecording;

// How many of `scans` (other than `except`) measure beyond `q` by `margin`
// at the pixel q projects to, i.e. see through q.
int seenThrough(const std::vector<RangeScan>& raw, std::size_t except, const Eigen::Vector3d& q, double margin) {
  int n = 0;
  for (std::size_t j = 0; j < raw.size(); ++j) {
    if (j == except) continue;
    const RangeScan& s = raw[j];
    const Eigen::Vector3d o = mrptSensorAxesInOptical() * (s.sensor_pose.inverse() * q);
    if (o.z() <= 0) continue;
    const int c = static_cast<int>(std::lround(s.camera.fx * o.x() / o.z() + s.camera.cx));
    const int r = static_cast<int>(std::lround(s.camera.fy * o.y() / o.z() + s.camera.cy));
    if (c < 0 || r < 0 || c >= s.width || r >= s.height) continue;
    const float depth = s.range[static_cast<std::size_t>(r) * s.width + c];
    n += depth > o.z() + margin;
  }
  return n;
}

TEST(OctreeFusion, DropsOutliersInFreeSpaceKeepsTheSurface) {
  const std::string dir = simulatedRecording(6, true);
  const TriangleMesh object = io::readTriangleMesh(dir + "/object.ply");
  Eigen::AlignedBox3d object_box;
  for (const auto& v : object.vertices.positions) object_box.extend(v);
  const std::vector<RangeScan> raw = readAllScans(dir + "/scans.rawlog");
  ASSERT_EQ(raw.size(), 6u);

  // Only the object: above the support plate, around the object's box.
  const Eigen::AlignedBox3d crop(object_box.min() - Eigen::Vector3d(0.01, 0.01, -0.003),
                                 object_box.max() + Eigen::Vector3d(0.01, 0.01, 0.01));
  // Whole scans go in: rays ending on the plate or the post carve the space
  // around the object too.
  std::vector<RangeScan> scans = raw;
  std::size_t surface_points = 0, all_points = 0;
  for (const RangeScan& s : scans) {
    all_points += s.points.size();
    for (const auto& p : s.points) surface_points += crop.contains(p);
  }
  ASSERT_GT(surface_points, 10000u);

  // Outliers for scan 0 where at least three other views see through.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(crop.min().x(), crop.max().x()), uy(crop.min().y(), crop.max().y()),
      uz(crop.min().z(), crop.max().z());
  std::vector<Eigen::Vector3d> outliers;
  for (int i = 0; i < 20000 && outliers.size() < 200; ++i) {
    const Eigen::Vector3d q(ux(rng), uy(rng), uz(rng));
    if (seenThrough(raw, 0, q, 0.02) >= 3) outliers.push_back(q);
  }
  ASSERT_GE(outliers.size(), 50u);
  const std::size_t real0 = scans[0].points.size();
  for (const auto& q : outliers) {
    scans[0].points.push_back(q);
    scans[0].pixels.push_back(0);
  }

  OctreeFusionParameters params;
  params.bounds = crop;
  const OctreeFusionResult result = fuseScans(scans, params);
  const auto& report = result.report;
  EXPECT_EQ(report.points_in, all_points + outliers.size());
  EXPECT_EQ(report.kept + report.dropped_free + report.dropped_outside, report.points_in);
  ASSERT_EQ(result.points.size(), report.kept);

  // Which outliers survived: scan 0's points past its real ones.
  const auto& view = result.points.attributes.get("view").values;
  std::size_t kept_outliers = 0;
  {
    std::vector<Eigen::Vector3d> kept0;
    for (std::size_t k = 0; k < result.points.size(); ++k)
      if (view[k] == 0) kept0.push_back(result.points.positions[k]);
    for (const auto& q : outliers) kept_outliers += std::find(kept0.begin(), kept0.end(), q) != kept0.end();
  }
  EXPECT_LE(kept_outliers, outliers.size() / 10) << kept_outliers << " of " << outliers.size() << " outliers kept";

  const double kept_fraction =
      static_cast<double>(report.kept - kept_outliers) / static_cast<double>(surface_points);
  RecordProperty("outliers", static_cast<int>(outliers.size()));
  RecordProperty("kept_outliers", static_cast<int>(kept_outliers));
  RecordProperty("kept_surface_permille", static_cast<int>(1000 * kept_fraction));
  EXPECT_GT(kept_fraction, 0.85) << "kept " << report.kept << " dropped free " << report.dropped_free;

  const RayCaster caster(object);
  std::vector<double> d;
  for (std::size_t k = 0; k < result.points.size(); k += 5)
    d.push_back(caster.closestPoint(result.points.positions[k]).distance);
  std::sort(d.begin(), d.end());
  RecordProperty("p95_distance_um", static_cast<int>(1e6 * d[d.size() * 95 / 100]));
  EXPECT_LT(d[d.size() * 95 / 100], 0.003);

  // Attributes: the view and its sensor origin.
  const auto& vx = result.points.attributes.get("viewpoint_x").values;
  const auto& vz = result.points.attributes.get("viewpoint_z").values;
  EXPECT_EQ(result.points.attributes.get("view").type, ScalarType::Int32);
  for (std::size_t k = 0; k < result.points.size(); k += 101) {
    const auto s = static_cast<std::size_t>(view[k]);
    ASSERT_LT(s, scans.size());
    EXPECT_EQ(vx[k], scans[s].sensor_pose.translation().x());
    EXPECT_EQ(vz[k], scans[s].sensor_pose.translation().z());
  }
  EXPECT_LE(report.kept_per_scan[0], real0 + kept_outliers);
  EXPECT_GT(report.occupied_leaves, 0u);
}

TEST(OctreeFusion, DoubleLayerInFrontIsCarved) {
  // Three views of a wall; a fourth view's copy of the wall sits 3 cm in
  // front (a misregistered view). Three views see through it (OctoMap's
  // default hit 0.7 outweighs two misses of 0.4): it goes.
  using testing_support::blankScan;
  using testing_support::castRays;
  using testing_support::lookAt;
  auto wall = [](double x) {
    return [x](const Eigen::Vector3d& o, const Eigen::Vector3d& d) { return d.x() > 1e-9 ? (x - o.x()) / d.x() : -1.0; };
  };
  std::vector<RangeScan> scans;
  const Eigen::Vector3d eyes[4] = {{-0.6, 0.0, 0.0}, {-0.6, 0.1, 0.05}, {-0.6, -0.1, -0.05}, {-0.6, -0.05, 0.1}};
  for (int i = 0; i < 4; ++i) {
    scans.push_back(blankScan(160, 120, 200.0, lookAt(eyes[i], Eigen::Vector3d(0, 0, 0))));
    castRays(scans.back(), wall(i == 0 ? -0.03 : 0.0));
    scans.back().index = static_cast<std::size_t>(i);
  }
  OctreeFusionParameters params;
  params.bounds = Eigen::AlignedBox3d(Eigen::Vector3d(-0.1, -0.15, -0.15), Eigen::Vector3d(0.05, 0.15, 0.15));
  const OctreeFusionResult result = fuseScans(scans, params);
  std::size_t front = 0, back = 0;
  for (const auto& p : result.points.positions) (p.x() < -0.015 ? front : back) += 1;
  EXPECT_GT(back, 0u);
  EXPECT_LT(static_cast<double>(front), 0.1 * static_cast<double>(back)) << front << " in front, " << back << " on the wall";

  // Deterministic: the same scans give the same points.
  const OctreeFusionResult again = fuseScans(scans, params);
  EXPECT_EQ(again.points.positions, result.points.positions);
  EXPECT_EQ(again.report.occupied_leaves, result.report.occupied_leaves);
}

TEST(OctreeFusion, ScansInsertedTogetherGiveTheTreeOfOneByOne) {
  // The batch traces rays in parallel and updates in order: the same
  // points, leaves and report as inserting each scan in turn, masks too.
  using testing_support::blankScan;
  using testing_support::castRays;
  using testing_support::lookAt;
  auto ball = [](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    // A sphere of 5 cm at the origin (d is a unit direction).
    const double b = o.dot(d), c = o.squaredNorm() - 0.05 * 0.05, disc = b * b - c;
    return disc < 0 ? -1.0 : -b - std::sqrt(disc);
  };
  std::vector<RangeScan> scans;
  std::vector<std::vector<std::uint8_t>> masks;
  for (int i = 0; i < 5; ++i) {
    const double a = 1.2 * i;
    scans.push_back(blankScan(120, 90, 250.0, lookAt(Eigen::Vector3d(0.5 * std::cos(a), 0.5 * std::sin(a), 0.1 * i),
                                                     Eigen::Vector3d(0, 0, 0))));
    castRays(scans.back(), ball);
    scans.back().index = static_cast<std::size_t>(i);
    std::vector<std::uint8_t> mask(scans.back().points.size());
    for (std::size_t k = 0; k < mask.size(); ++k) mask[k] = (k + static_cast<std::size_t>(i)) % 3 != 0;
    masks.push_back(mask);
  }
  ASSERT_GT(scans.front().points.size(), 1000u);
  OctreeFusionParameters params;
  params.bounds = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.1), Eigen::Vector3d::Constant(0.1));
  OctreeFusion one_by_one(params), together(params);
  for (std::size_t i = 0; i < scans.size(); ++i) one_by_one.insert(scans[i], masks[i]);
  together.insert(std::vector<RangeScan>(scans.begin(), scans.begin() + 2),
                  std::vector<std::vector<std::uint8_t>>(masks.begin(), masks.begin() + 2));
  together.insert(std::vector<RangeScan>(scans.begin() + 2, scans.end()),
                  std::vector<std::vector<std::uint8_t>>(masks.begin() + 2, masks.end()));
  const OctreeFusionResult a = one_by_one.finish(), b = together.finish();
  ASSERT_GT(a.points.size(), 1000u);
  EXPECT_EQ(a.points.positions, b.points.positions);
  EXPECT_EQ(a.points.attributes.get("view").values, b.points.attributes.get("view").values);
  EXPECT_EQ(a.report.dropped_free, b.report.dropped_free);
  EXPECT_EQ(a.report.kept_per_scan, b.report.kept_per_scan);
  EXPECT_EQ(a.report.leaves, b.report.leaves);
  EXPECT_EQ(a.report.occupied_leaves, b.report.occupied_leaves);

  OctreeFusion wrong(params);
  EXPECT_THROW(wrong.insert(scans, std::vector<std::vector<std::uint8_t>>(1)), InputError);
}

TEST(OctreeFusion, RejectsBadParameters) {
  OctreeFusionParameters params;
  params.resolution = 0;
  EXPECT_THROW(fuseScans({}, params), InputError);
  params.resolution = 0.01;
  params.prob_hit = 1.5;
  EXPECT_THROW(fuseScans({}, params), InputError);
}

}  // namespace
}  // namespace icrkit::reconstruction
