// The Kinect's shared depth noise (SensorModel::axial_correlated_share): the
// random field alone, then a facing plane rendered with it.

#include <icrkit/sim/range_sensor.hpp>

#include <icrkit/core/error.hpp>

#include "gaussian_random_field.hpp"
#include "kinect_model.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <string>
#include <vector>

namespace icrkit::sim {
namespace {

// Mean product of the values d pixels apart along rows and columns,
// over the product at d = 0 (the field's mean is 0 by construction; the
// sample mean is removed all the same).
double correlationAt(const std::vector<double>& image, int width, int height, int d) {
  double mean = 0.0;
  for (double v : image) mean += v;
  mean /= static_cast<double>(image.size());
  double lagged = 0.0, same = 0.0;
  std::size_t lagged_count = 0;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const double a = image[static_cast<std::size_t>(v * width + u)] - mean;
      same += a * a;
      if (u + d < width) {
        lagged += a * (image[static_cast<std::size_t>(v * width + u + d)] - mean);
        ++lagged_count;
      }
      if (v + d < height) {
        lagged += a * (image[static_cast<std::size_t>((v + d) * width + u)] - mean);
        ++lagged_count;
      }
    }
  return (lagged / static_cast<double>(lagged_count)) / (same / static_cast<double>(image.size()));
}

TEST(GaussianRandomField, UnitVarianceAndTheGaussianCorrelationItPromises) {
  const int width = 400, height = 300;
  const double sigma = 3.0;
  const std::vector<float> field = gaussianRandomField(width, height, sigma, 7);
  ASSERT_EQ(field.size(), static_cast<std::size_t>(width * height));
  std::vector<double> values(field.begin(), field.end());
  double sq = 0.0;
  for (double x : values) sq += x * x;
  // 120k pixels but only ~120k / (4 pi s^2) ~ 1000 independent blobs.
  EXPECT_NEAR(sq / static_cast<double>(values.size()), 1.0, 0.1);
  for (int d : {1, 2, 3, 6, 9}) {
    const double expected = std::exp(-d * d / (4.0 * sigma * sigma));
    EXPECT_NEAR(correlationAt(values, width, height, d), expected, 0.05) << "lag " << d;
  }
}

// The corner and the edges see truncated kernels, renormalised: their
// variance is 1 too. Pixels near a corner move together, so one field says
// little about them: averaged over 400 fields of different seeds.
TEST(GaussianRandomField, BorderPixelsKeepUnitVariance) {
  const int width = 24, height = 18;
  double corner = 0.0, edge = 0.0, inside = 0.0;
  const int fields = 400;
  for (int seed = 0; seed < fields; ++seed) {
    const std::vector<float> f = gaussianRandomField(width, height, 3.0, static_cast<std::uint64_t>(seed));
    corner += f[0] * f[0];
    edge += f[static_cast<std::size_t>(width / 2)] * f[static_cast<std::size_t>(width / 2)];
    const float c = f[static_cast<std::size_t>((height / 2) * width + width / 2)];
    inside += c * c;
  }
  // A variance estimated from 400 normals: standard error sqrt(2 / 400) = 0.07.
  EXPECT_NEAR(corner / fields, 1.0, 0.25);
  EXPECT_NEAR(edge / fields, 1.0, 0.25);
  EXPECT_NEAR(inside / fields, 1.0, 0.25);
}

TEST(GaussianRandomField, DeterministicForASeedWhateverTheThreadCount) {
  const std::vector<float> all = gaussianRandomField(160, 120, 2.5, 3);
  std::vector<float> one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = gaussianRandomField(160, 120, 2.5, 3);
  }
  EXPECT_EQ(all, one);
  EXPECT_NE(all, gaussianRandomField(160, 120, 2.5, 4));
}

// A plane facing the camera at 0.8 m: with 70 % of the variance shared over
// 3 px the depth noise keeps the model's sigma, and neighbouring pixels
// correlate as 0.7 x exp(-d^2 / 36) times the share of the variance that is
// not the disparity steps' rounding (1.8 mm steps against a sigma of 1.5 mm:
// 0.87); independent by default.
TEST(KinectModel, SharedDepthNoiseKeepsSigmaAndCorrelatesNeighbours) {
  SensorModel model = kinectV1();
  const double z = 0.8;
  std::vector<Eigen::Vector3d> corners{{-20, -20, z}, {20, -20, z}, {20, 20, z}, {-20, 20, z}};
  TriangleMesh plane;
  plane.vertices.positions = corners;
  plane.faces = {{0, 2, 1}, {0, 3, 2}};
  const RayCaster scene(plane);
  const double sigma = rangeNoiseSigma(model, z, 0.0);
  const int width = model.intrinsics.width, height = model.intrinsics.height;
  auto errors = [&](const SensorModel& m) {
    const SimulatedScan scan = simulateScan(scene, {}, Eigen::Isometry3d::Identity(), m, 11);
    std::vector<double> e(scan.range.size(), 0.0);
    for (std::size_t i = 0; i < e.size(); ++i) {
      EXPECT_GT(scan.range[i], 0.0f);
      e[i] = static_cast<double>(scan.range[i]) - scan.true_range[i];
    }
    return e;
  };
  const std::vector<double> independent = errors(model);
  model.axial_correlated_share = 0.7;
  model.axial_correlation_px = 3.0;
  const std::vector<double> shared = errors(model);
  auto rms = [](const std::vector<double>& e) {
    double s = 0.0;
    for (double x : e) s += x * x;
    return std::sqrt(s / static_cast<double>(e.size()));
  };
  EXPECT_NEAR(rms(independent), sigma, 0.1 * sigma);
  EXPECT_NEAR(rms(shared), sigma, 0.1 * sigma);
  EXPECT_LT(std::abs(correlationAt(independent, width, height, 1)), 0.05);
  const double step = kinectDepthStep(model, z);
  const double not_rounding = 1.0 - step * step / 12.0 / (sigma * sigma);
  EXPECT_NEAR(correlationAt(shared, width, height, 1), 0.7 * not_rounding * std::exp(-1.0 / 36.0), 0.05);
  EXPECT_NEAR(correlationAt(shared, width, height, 3), 0.7 * not_rounding * std::exp(-9.0 / 36.0), 0.05);
  EXPECT_NEAR(correlationAt(shared, width, height, 9), 0.7 * not_rounding * std::exp(-81.0 / 36.0), 0.05);
}

// The error names the field at fault.
std::string rejectedField(const SensorModel& model) {
  const RayCaster scene(TriangleMesh{});
  try {
    simulateScan(scene, {}, Eigen::Isometry3d::Identity(), model, 1);
  } catch (const InputError& error) {
    return error.location();
  }
  return "(accepted)";
}

TEST(KinectModel, SharedNoiseOutsideItsRangeIsRejected) {
  SensorModel model = kinectV1();
  model.axial_correlated_share = 1.5;
  EXPECT_EQ(rejectedField(model), "axial_correlated_share");
  model.axial_correlated_share = 0.5;
  model.axial_correlation_px = 0.5;  // below a pixel the kernel is no longer Gaussian
  EXPECT_EQ(rejectedField(model), "axial_correlation_px");
  model.axial_correlation_px = 3.0;
  SensorModel tof = swissRangerSr4000();
  tof.axial_correlated_share = 0.5;
  EXPECT_EQ(rejectedField(tof), "axial_correlated_share");
}

}  // namespace
}  // namespace icrkit::sim
