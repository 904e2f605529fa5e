#include <icrkit/ndt/normal_estimation.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/ndt/fit_uncertainty.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <random>

namespace icrkit::ndt {
namespace {

PointCloud randomSphere(std::size_t count, double radius, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  PointCloud cloud;
  while (cloud.size() < count) {
    Eigen::Vector3d d(g(rng), g(rng), g(rng));
    if (d.norm() < 1e-9) continue;
    cloud.positions.push_back(radius * d.normalized());
  }
  return cloud;
}

TEST(NormalEstimation, SphereNormalsAreRadialAndOutward) {
  PointCloud cloud = randomSphere(5000, 0.1, 3);
  const NormalEstimationReport s = estimateNormals(cloud);
  ASSERT_EQ(cloud.normals.size(), cloud.size());
  EXPECT_GT(s.radius_m, 0.0);
  double worst = 1.0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_NEAR(cloud.normals[i].norm(), 1.0, 1e-12);
    worst = std::min(worst, cloud.normals[i].dot(cloud.positions[i].normalized()));
  }
  // The window's chord bends the fit a little; every normal points out.
  EXPECT_GT(worst, 0.97);
}

// Cube by cube (the default) and in index order the windows are the same
// points, summed in another order: the normals agree to rounding, and so do
// their uncertainties; either way the same bits on one thread as on all.
TEST(NormalEstimation, CubeOrderAndIndexOrderAgree) {
  PointCloud noisy = randomSphere(20000, 0.1, 5);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 2e-4);
  for (Eigen::Vector3d& p : noisy.positions) p *= 1.0 + g(rng) / 0.1;
  NormalEstimationParameters params;
  params.viewpoint = Eigen::Vector3d::Zero();
  PointCloud cubes = noisy, indexed = noisy;
  const NormalEstimationReport a = estimateNormals(cubes, params);
  params.index_order = true;
  const NormalEstimationReport b = estimateNormals(indexed, params);
  EXPECT_EQ(a.small_windows, b.small_windows);
  const auto& sigma_a = cubes.attributes.get(kNormalSigmaAttribute).values;
  const auto& sigma_b = indexed.attributes.get(kNormalSigmaAttribute).values;
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    EXPECT_GT(cubes.normals[i].dot(indexed.normals[i]), 1.0 - 1e-9) << i;
    EXPECT_NEAR(sigma_a[i], sigma_b[i], 1e-6 * std::max(1.0, std::abs(sigma_b[i]))) << i;
  }
  // On one thread, bit for bit the same either way.
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  PointCloud cubes_one = noisy, indexed_one = noisy;
  params.index_order = false;
  estimateNormals(cubes_one, params);
  params.index_order = true;
  estimateNormals(indexed_one, params);
  EXPECT_EQ(cubes_one.normals, cubes.normals);
  EXPECT_EQ(indexed_one.normals, indexed.normals);
}

TEST(NormalEstimation, PlaneTowardsViewpoint) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < 2000; ++i) cloud.positions.emplace_back(u(rng), u(rng), 0.0);
  NormalEstimationParameters params;
  params.viewpoint = Eigen::Vector3d(0, 0, -5);
  estimateNormals(cloud, params);
  for (const auto& n : cloud.normals) EXPECT_NEAR(n.z(), -1.0, 1e-9);
  params.viewpoint = Eigen::Vector3d(0, 0, 5);
  estimateNormals(cloud, params);
  for (const auto& n : cloud.normals) EXPECT_NEAR(n.z(), 1.0, 1e-9);
}

TEST(NormalEstimation, EachPointFacesItsOwnViewpoint) {
  // Two views of a plane from either side: each half's normals face their
  // own sensor, as in a cloud fused from several scans.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointCloud cloud;
  NormalEstimationParameters params;
  for (int i = 0; i < 2000; ++i) {
    cloud.positions.emplace_back(u(rng), u(rng), 0.0);
    params.viewpoints.emplace_back(0, 0, i % 2 ? 3.0 : -3.0);
  }
  estimateNormals(cloud, params);
  for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_NEAR(cloud.normals[i].z(), i % 2 ? 1.0 : -1.0, 1e-9);
  params.viewpoints.pop_back();
  EXPECT_THROW(estimateNormals(cloud, params), InputError);
}

TEST(NormalEstimation, IsolatedPointsFallBackToNearestNeighbours) {
  PointCloud cloud = randomSphere(2000, 0.1, 5);
  cloud.positions.emplace_back(0.5, 0, 0);  // far from everything
  NormalEstimationParameters params;
  params.radius = Length::metres(0.02);
  const NormalEstimationReport s = estimateNormals(cloud, params);
  EXPECT_GE(s.small_windows, 1u);
  EXPECT_TRUE(cloud.normals.back().allFinite());
  EXPECT_NEAR(cloud.normals.back().norm(), 1.0, 1e-12);
}

TEST(NormalEstimation, BadInput) {
  PointCloud two;
  two.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(estimateNormals(two), InputError);
  PointCloud cloud = randomSphere(100, 1.0, 2);
  cloud.positions[7].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(estimateNormals(cloud), InputError);
  cloud = randomSphere(100, 1.0, 2);
  NormalEstimationParameters params;
  params.radius = Length::metres(-1);
  EXPECT_THROW(estimateNormals(cloud, params), InputError);
}

}  // namespace
}  // namespace icrkit::ndt
