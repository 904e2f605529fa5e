// 3D-NDT registration: known answers on a synthetic object (a box and a
// sphere, moved by a known transform), the analytic derivatives against
// finite differences, determinism over thread counts, bad input, and real
// Stanford bunny scan pairs against the bun.conf poses (skipped when the
// shared data is absent).

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/ndt/ndt_registration.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace icrkit::ndt {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// An object-sized, asymmetric shape: the surface of a 12 x 8 x 6 cm box and
// of a 3 cm sphere touching one side, ~2 mm spacing, optional Gaussian noise.
PointCloud makeBoxAndSphere(double sigma, std::uint64_t seed) {
  PointCloud cloud;
  const Eigen::Vector3d half(0.06, 0.04, 0.03);
  const double spacing = 0.002;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double side : {-1.0, 1.0})
      for (double a = -half(u); a <= half(u) + 1e-12; a += spacing)
        for (double b = -half(v); b <= half(v) + 1e-12; b += spacing) {
          Eigen::Vector3d p;
          p(axis) = side * half(axis);
          p(u) = a;
          p(v) = b;
          cloud.positions.push_back(p);
        }
  }
  const Eigen::Vector3d centre(0.03, 0.0, 0.06);
  const double radius = 0.03;
  const int n = static_cast<int>(4 * kPi * radius * radius / (spacing * spacing));
  for (int i = 0; i < n; ++i) {  // Fibonacci sphere: even spacing, no randomness
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    const double phi = i * kPi * (3.0 - std::sqrt(5.0));
    cloud.positions.push_back(centre + radius * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z));
  }
  // Off the grid: faces on cell boundaries would put half of every face in
  // each of two cells, the worst case for NDT's piecewise score.
  for (auto& p : cloud.positions) p += Eigen::Vector3d(0.0037, 0.0021, -0.0013);
  if (sigma > 0) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    for (auto& p : cloud.positions) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  }
  return cloud;
}

PointCloud transformedCloud(const PointCloud& cloud, const Eigen::Isometry3d& pose) {
  PointCloud out = cloud;
  for (auto& p : out.positions) p = pose * p;
  return out;
}

Eigen::Isometry3d makePose(const Eigen::Vector3d& translation, const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

struct PoseError {
  double translation_m, rotation_rad;
};

PoseError poseError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3d delta = truth.inverse() * estimate;
  return {(estimate.translation() - truth.translation()).norm(), Eigen::AngleAxisd(delta.rotation()).angle()};
}

TEST(NdtConstants, ScaleInvariantConstantsAvoidTheDegenerateMetreForm) {
  NdtParameters params;
  params.scale_invariant_constants = false;
  // Magnusson's constants at 1 m: a usable mixture.
  const NdtConstants metre = ndtConstants(1.0, params);
  EXPECT_LT(metre.d1, -1.0);
  EXPECT_GT(metre.d2, 0.0);
  EXPECT_LT(metre.d2, 1.0);
  // At 1 cm the uniform density swamps c1: d1 collapses towards 0 (the PCL pitfall).
  const NdtConstants centimetre = ndtConstants(0.01, params);
  EXPECT_GT(centimetre.d1, -1e-4);
  params.scale_invariant_constants = true;
  const NdtConstants invariant = ndtConstants(0.01, params);
  EXPECT_DOUBLE_EQ(invariant.d1, metre.d1);
  EXPECT_DOUBLE_EQ(invariant.d2, metre.d2);
}

TEST(NdtRegistration, GradientAndHessianMatchFiniteDifferences) {
  const PointCloud target_cloud = makeBoxAndSphere(0.0005, 1);
  NdtParameters params;
  params.resolutions = {0.02};
  const NdtTarget target(target_cloud, params);
  const Eigen::Isometry3d pose = makePose({0.004, -0.003, 0.002}, {1, 2, 3}, 3 * kDeg);
  Vector6d x;
  x << 0.001, -0.002, 0.0015, 0.02, -0.03, 0.025;  // away from 0: every term of the derivatives matters
  // The score jumps where a point changes cell; finite differences across a
  // jump measure the jump, so keep only points 0.4 mm or more inside a cell.
  PointCloud source;
  const Eigen::Isometry3d moved = ndtPoseFromParameters(x) * pose;
  for (const Eigen::Vector3d& p : makeBoxAndSphere(0.0005, 2).positions) {
    const Eigen::Vector3d cell = (moved * p) / 0.02;
    const Eigen::Vector3d inside = cell - cell.array().floor().matrix();
    if ((inside.array() > 0.02).all() && (inside.array() < 0.98).all()) source.positions.push_back(p);
  }
  for (NdtNeighbourhood nb : {NdtNeighbourhood::Single, NdtNeighbourhood::Face7, NdtNeighbourhood::All27}) {
    params.neighbourhood = nb;
    const NdtEvaluation at = evaluateNdt(source, target, 0.02, pose, x, params);
    ASSERT_GT(at.points_scored, source.size() / 2);
    const double h = 1e-6;
    Vector6d numeric_gradient;
    Matrix6d numeric_hessian;
    for (int i = 0; i < 6; ++i) {
      Vector6d plus = x, minus = x;
      plus(i) += h;
      minus(i) -= h;
      const NdtEvaluation ep = evaluateNdt(source, target, 0.02, pose, plus, params);
      const NdtEvaluation em = evaluateNdt(source, target, 0.02, pose, minus, params);
      numeric_gradient(i) = (ep.value - em.value) / (2 * h);
      numeric_hessian.col(i) = (ep.gradient - em.gradient) / (2 * h);
    }
    EXPECT_LT((numeric_gradient - at.gradient).norm(), 1e-5 * at.gradient.norm())
        << "analytic " << at.gradient.transpose() << "\nnumeric  " << numeric_gradient.transpose();
    EXPECT_LT((numeric_hessian - at.hessian).norm(), 1e-5 * at.hessian.norm())
        << "analytic\n" << at.hessian << "\nnumeric\n" << numeric_hessian;
  }
}

TEST(NdtRegistration, RecoversAKnownTransformOnASyntheticObject) {
  const PointCloud target_cloud = makeBoxAndSphere(0.0, 0);
  const NdtTarget target(target_cloud);
  const std::vector<Eigen::Isometry3d> truths{
      makePose({0.02, -0.01, 0.015}, {1, 0.5, -0.2}, 5 * kDeg),
      makePose({-0.015, 0.02, -0.01}, {-0.3, 1, 0.4}, -4 * kDeg),
      makePose({0.01, 0.01, -0.02}, {0.2, -0.4, 1}, 6 * kDeg),
  };
  for (const Eigen::Isometry3d& truth : truths) {
    // source -> target is `truth`: the source is the target moved by its inverse.
    const PointCloud source = transformedCloud(target_cloud, truth.inverse());
    const NdtResult r = registerNdt(source, target, Eigen::Isometry3d::Identity());
    const PoseError e = poseError(r.pose, truth);
    std::printf("[ synthetic ] error %.5f mm, %.5f deg, iterations %d/%d/%d, score %.4f, %.1f ms\n",
                e.translation_m * 1e3, e.rotation_rad / kDeg, r.iterations[0], r.iterations[1], r.iterations[2],
                r.normalized_score, r.time_ms);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(e.translation_m, 1e-4);
    EXPECT_LT(e.rotation_rad, 0.01 * kDeg);
    // At the optimum the Hessian of -score is positive definite.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(r.hessian).eigenvalues().minCoeff(), 0.0);
  }
}

TEST(NdtRegistration, SameResultWithOneAndTwoThreads) {
  const PointCloud target_cloud = makeBoxAndSphere(0.0005, 3);
  const NdtTarget target(target_cloud);
  const PointCloud source = transformedCloud(makeBoxAndSphere(0.0005, 4), makePose({0.01, 0.005, -0.01}, {1, 1, 0}, 3 * kDeg));
  NdtResult one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = registerNdt(source, target, Eigen::Isometry3d::Identity());
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = registerNdt(source, target, Eigen::Isometry3d::Identity());
  }
  EXPECT_TRUE(one.pose.matrix() == two.pose.matrix());
  EXPECT_EQ(one.score, two.score);
  EXPECT_TRUE(one.hessian == two.hessian);
  EXPECT_EQ(one.iterations, two.iterations);
}

TEST(NdtRegistration, FarCellsDoNotChangeTheResult) {
  // A cluster 3 m away makes the occupied cells' box too sparse for the
  // dense cell table at the fine resolutions (the hash serves them) while
  // the coarse ones stay dense: every Gaussian near the object is found
  // alike, so the registration is the same, bit for bit.
  const PointCloud object = makeBoxAndSphere(0.0005, 7);
  PointCloud with_far = object;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> jitter(0.0, 0.004);
  for (int i = 0; i < 400; ++i)
    with_far.positions.push_back(Eigen::Vector3d(3.0, 0.0, 0.0) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  NdtParameters params;
  params.resolutions = {0.02, 0.01, 0.005};
  const NdtTarget near_only(object, params), both(with_far, params);
  const PointCloud source =
      transformedCloud(makeBoxAndSphere(0.0005, 8), makePose({0.01, -0.008, 0.006}, {1, -1, 0.5}, 3 * kDeg));
  const NdtResult a = registerNdt(source, near_only, Eigen::Isometry3d::Identity(), params);
  const NdtResult b = registerNdt(source, both, Eigen::Isometry3d::Identity(), params);
  EXPECT_GT(both.cellCount(0.005), near_only.cellCount(0.005));
  EXPECT_LT(a.pose.translation().norm(), 0.05);
  EXPECT_TRUE(a.pose.matrix() == b.pose.matrix());
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(NdtRegistration, TargetIsReusableAndBuildsMissingResolutionsOnDemand) {
  const PointCloud target_cloud = makeBoxAndSphere(0.0005, 5);
  NdtParameters only_two;
  only_two.resolutions = {0.02};
  const NdtTarget partial(target_cloud, only_two);
  const NdtTarget full(target_cloud);
  EXPECT_GT(partial.cellCount(0.02), 0u);
  EXPECT_EQ(partial.cellCount(0.01), 0u);  // not prebuilt
  EXPECT_EQ(full.cellCount(0.02), partial.cellCount(0.02));
  const Eigen::Isometry3d truth = makePose({0.01, -0.005, 0.008}, {0, 1, 1}, 4 * kDeg);
  const PointCloud source = transformedCloud(makeBoxAndSphere(0.0005, 6), truth.inverse());
  const NdtResult a = registerNdt(source, partial, Eigen::Isometry3d::Identity());
  const NdtResult b = registerNdt(source, full, Eigen::Isometry3d::Identity());
  const NdtResult c = registerNdt(source, full, Eigen::Isometry3d::Identity());  // reuse
  EXPECT_TRUE(a.pose.matrix() == b.pose.matrix());
  EXPECT_TRUE(b.pose.matrix() == c.pose.matrix());
  const PoseError e = poseError(a.pose, truth);
  EXPECT_LT(e.translation_m, 2e-4);  // independent noise in source and target: sub-0.2 mm, not exact
  EXPECT_LT(e.rotation_rad, 0.05 * kDeg);
}

TEST(NdtRegistration, BadInputThrowsInputError) {
  const PointCloud cloud = makeBoxAndSphere(0.0, 0);
  const PointCloud empty;
  EXPECT_THROW(NdtTarget{empty}, InputError);
  const NdtTarget target(cloud);
  EXPECT_THROW(registerNdt(empty, target, Eigen::Isometry3d::Identity()), InputError);
  PointCloud few;  // four points: no cell can hold five
  few.positions = {{0, 0, 0}, {0.001, 0, 0}, {0, 0.001, 0}, {0, 0, 0.001}};
  EXPECT_THROW(NdtTarget{few}, InputError);
  PointCloud nan_cloud = cloud;
  nan_cloud.positions[7].x() = std::nan("");
  EXPECT_THROW(registerNdt(nan_cloud, target, Eigen::Isometry3d::Identity()), InputError);
  NdtParameters bad;
  bad.resolutions = {0.02, -0.01};
  EXPECT_THROW(registerNdt(cloud, target, Eigen::Isometry3d::Identity(), bad), InputError);
  bad = NdtParameters{};
  bad.outlier_ratio = 1.0;
  EXPECT_THROW(registerNdt(cloud, target, Eigen::Isometry3d::Identity(), bad), InputError);
  bad = NdtParameters{};
  bad.source_voxel_size = -0.001;
  EXPECT_THROW(registerNdt(cloud, target, Eigen::Isometry3d::Identity(), bad), InputError);
  // No overlap at all: the source is a metre away.
  EXPECT_THROW(registerNdt(cloud, target, makePose({1.0, 0, 0}, {0, 0, 1}, 0)), InputError);
}

// ---- Stanford bunny -------------------------------------------------------

std::string sharedData(const std::string& relative) { return std::string(ICRKIT_SHARED_DATA_DIR) + "/" + relative; }

// bun.conf: `bmesh FILE tx ty tz qx qy qz qw`; a scan point p maps into the
// reference frame as R(q)^T p + t (see the data README).
std::optional<Eigen::Isometry3d> bunConfPose(const std::string& conf, const std::string& scan) {
  std::ifstream in(conf);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind, file;
    double tx, ty, tz, qx, qy, qz, qw;
    if (!(s >> kind >> file >> tx >> ty >> tz >> qx >> qy >> qz >> qw) || kind != "bmesh" || file != scan) continue;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix().transpose();
    pose.translation() = Eigen::Vector3d(tx, ty, tz);
    return pose;
  }
  return std::nullopt;
}

void registerBunnyPair(const std::string& target_scan, const std::string& source_scan, const NdtParameters& params = {}) {
  const std::string conf = sharedData("stanford-bunny/bun.conf");
  const std::string target_path = sharedData("stanford-bunny/" + target_scan);
  const std::string source_path = sharedData("stanford-bunny/" + source_scan);
  for (const std::string& path : {conf, target_path, source_path})
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found: " << path;
  const auto target_pose = bunConfPose(conf, target_scan);
  const auto source_pose = bunConfPose(conf, source_scan);
  ASSERT_TRUE(target_pose && source_pose) << "scan missing from " << conf;
  const Eigen::Isometry3d truth = target_pose->inverse() * *source_pose;  // source -> target

  const PointCloud target_cloud = io::readPointCloud(target_path);
  const PointCloud source = io::readPointCloud(source_path);
  const NdtTarget target(target_cloud, params);
  // Perturbations of 5 degrees and 1 cm in several directions, applied in the target frame.
  const std::vector<Eigen::Isometry3d> perturbations{
      makePose({0.01, 0, 0}, {0, 1, 0}, 5 * kDeg),
      makePose({0, -0.01, 0}, {1, 0, 0}, -5 * kDeg),
      makePose({0, 0, 0.01}, {0, 0, 1}, 5 * kDeg),
      makePose(Eigen::Vector3d(-1, 1, 1).normalized() * 0.01, {1, -1, 1}, 5 * kDeg),
  };
  double worst_t = 0, worst_r = 0;
  for (const Eigen::Isometry3d& perturbation : perturbations) {
    const Eigen::Isometry3d guess = perturbation * truth;
    const NdtResult r = registerNdt(source, target, guess, params);
    const PoseError before = poseError(guess, truth);
    const PoseError e = poseError(r.pose, truth);
    std::printf("[ %s -> %s%s ] %zu -> %zu points; start %.2f mm %.2f deg -> error %.3f mm %.3f deg, iterations %d/%d/%d, "
                "converged %d, score %.3f, %.0f ms\n",
                source_scan.c_str(), target_scan.c_str(),
                params.source_voxel_size > 0 ? ", source subsampled" : "", source.size(), target_cloud.size(), before.translation_m * 1e3,
                before.rotation_rad / kDeg, e.translation_m * 1e3, e.rotation_rad / kDeg, r.iterations[0],
                r.iterations[1], r.iterations[2], int(r.converged), r.normalized_score, r.time_ms);
    worst_t = std::max(worst_t, e.translation_m);
    worst_r = std::max(worst_r, e.rotation_rad);
    EXPECT_LT(e.translation_m, 1e-3);
    EXPECT_LT(e.rotation_rad, 0.3 * kDeg);
  }
  ::testing::Test::RecordProperty("worst_translation_error_mm", std::to_string(worst_t * 1e3));
  ::testing::Test::RecordProperty("worst_rotation_error_deg", std::to_string(worst_r / kDeg));
}

TEST(NdtRegistrationRealData, Bunny045OntoBun000) { registerBunnyPair("bun000.ply", "bun045.ply"); }
TEST(NdtRegistrationRealData, Bunny315OntoBun000) { registerBunnyPair("bun000.ply", "bun315.ply"); }
TEST(NdtRegistrationRealData, SubsampledSourcesKeepTheAccuracy) {
  NdtParameters params;
  params.source_voxel_size = 0.002;  // ~40k -> ~6k points, ~5x faster
  registerBunnyPair("bun000.ply", "bun045.ply", params);
  registerBunnyPair("bun000.ply", "bun315.ply", params);
}

}  // namespace
}  // namespace icrkit::ndt
