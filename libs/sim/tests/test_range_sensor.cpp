#include <icrkit/sim/range_sensor.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>

// Internal model functions, tested against the rendered images.
#include "kinect_model.hpp"
#include "lens_distortion.hpp"
#include "sr4000_model.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

namespace icrkit::sim {
namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kDegree = kPi / 180.0;

void append(TriangleMesh& mesh, const TriangleMesh& part) {
  const int offset = static_cast<int>(mesh.vertices.positions.size());
  for (const auto& p : part.vertices.positions) mesh.vertices.positions.push_back(p);
  for (const Triangle& f : part.faces) mesh.faces.emplace_back(f[0] + offset, f[1] + offset, f[2] + offset);
}

// A square of side 2 * half through `centre` with unit normal `normal`: two
// triangles wound so that their normal is `normal`.
TriangleMesh square(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double half) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d a = n.unitOrthogonal();
  const Eigen::Vector3d b = n.cross(a);
  TriangleMesh mesh;
  for (const auto& [s, t] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}})
    mesh.vertices.positions.push_back(centre + half * (s * a + t * b));
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

// Axis-aligned box, outward winding, 12 faces.
TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.positions.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    mesh.faces.emplace_back(q[0], q[1], q[2]);
    mesh.faces.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

// Does the segment a-b cross the open box (lo, hi)? Slab test.
bool segmentHitsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (a[k] <= lo[k] || a[k] >= hi[k]) return false;
      continue;
    }
    double s0 = (lo[k] - a[k]) / d[k], s1 = (hi[k] - a[k]) / d[k];
    if (s0 > s1) std::swap(s0, s1);
    t0 = std::max(t0, s0);
    t1 = std::min(t1, s1);
  }
  return t0 < t1;
}

// The pixel (u, v) of a point in the optical frame: OpenCV's projection,
// written out here independently of the library's lens code.
Eigen::Vector2d projectPoint(const CameraIntrinsics& in, const Eigen::Vector3d& p) {
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const auto& k = in.distortion;
  const double r2 = x * x + y * y;
  const double radial = 1 + k[0] * r2 + k[1] * r2 * r2 + k[4] * r2 * r2 * r2;
  const double xd = x * radial + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
  const double yd = y * radial + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
  return {in.fx * xd + in.cx, in.fy * yd + in.cy};
}

struct Stats {
  std::size_t count = 0;
  double mean = 0.0, stddev = 0.0;
};
Stats stats(const std::vector<double>& values) {
  Stats s;
  s.count = values.size();
  if (values.empty()) return s;
  for (double v : values) s.mean += v;
  s.mean /= static_cast<double>(values.size());
  for (double v : values) s.stddev += (v - s.mean) * (v - s.mean);
  s.stddev = std::sqrt(s.stddev / static_cast<double>(values.size()));
  return s;
}

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

// Unit normal seen tilted by `angle` about the camera's y axis, facing the camera.
Eigen::Vector3d tiltedNormal(double angle) { return Eigen::Vector3d(std::sin(angle), 0.0, -std::cos(angle)); }

// The scene used for shadows and mixed pixels: a wall (faces 0, 1) at z = 2
// m and a 20 cm box (faces 2..13) whose front face is at z = 1.1 m.
const Eigen::Vector3d kBoxLo(-0.1, -0.1, 1.1), kBoxHi(0.1, 0.1, 1.3);
TriangleMesh boxBeforeWall() {
  TriangleMesh scene = square({0, 0, 2.0}, {0, 0, -1}, 10.0);
  append(scene, box(kBoxLo, kBoxHi));
  return scene;
}

// ---------------------------------------------------------------------------

TEST(RangeSensor, SensorNames) {
  EXPECT_EQ(parseSensorType("kinect"), SensorType::Kinect);
  EXPECT_EQ(parseSensorType("sr4000"), SensorType::Sr4000);
  EXPECT_EQ(sensorTypeName(SensorType::Kinect), "kinect");
  EXPECT_EQ(sensorTypeName(SensorType::Sr4000), "sr4000");
  for (const std::string bad : {"", "Kinect", "kinect ", "sr-4000", "SR4000", "kinect2", "lidar"}) {
    try {
      parseSensorType(bad);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "sensor name");
      EXPECT_NE(e.detail().find("kinect, sr4000"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(sensorModel(SensorType::Kinect).name, "Kinect v1");
  EXPECT_EQ(sensorModel(SensorType::Sr4000).name, "SwissRanger SR4000");
}

TEST(RangeSensor, ModelDefaults) {
  const SensorModel kinect = kinectV1();
  EXPECT_EQ(kinect.intrinsics.width, 640);
  EXPECT_EQ(kinect.intrinsics.height, 480);
  EXPECT_TRUE(kinect.range_is_depth);
  // Depth steps grow with z^2: 2.9 mm at 1 m, 46 mm at 4 m.
  EXPECT_NEAR(kinectDepthStep(kinect, 1.0), 0.125 / (580.0 * 0.075), 1e-12);
  EXPECT_NEAR(kinectDepthStep(kinect, 4.0) / kinectDepthStep(kinect, 1.0), 16.0, 1e-9);

  const SensorModel sr = swissRangerSr4000();
  EXPECT_EQ(sr.intrinsics.width, 176);
  EXPECT_EQ(sr.intrinsics.height, 144);
  EXPECT_FALSE(sr.range_is_depth);
  // The image edges see the datasheet's 43.6 x 34.6 deg field of view
  // through the lens distortion.
  const Eigen::Vector3d left = pixelDirection(sr.intrinsics, -0.5, sr.intrinsics.cy);
  const Eigen::Vector3d right = pixelDirection(sr.intrinsics, sr.intrinsics.width - 0.5, sr.intrinsics.cy);
  const Eigen::Vector3d top = pixelDirection(sr.intrinsics, sr.intrinsics.cx, -0.5);
  const Eigen::Vector3d bottom = pixelDirection(sr.intrinsics, sr.intrinsics.cx, sr.intrinsics.height - 0.5);
  EXPECT_NEAR((std::atan(right.x()) - std::atan(left.x())) / kDegree, 43.6, 0.1);
  EXPECT_NEAR((std::atan(bottom.y()) - std::atan(top.y())) / kDegree, 34.6, 0.1);
  // Wiggling period: a quarter of the 5 m non-ambiguity range.
  EXPECT_NEAR(sr.wiggling_wavelength, kSpeedOfLight / (2 * 30e6) / 4, 1e-9);
}

TEST(RangeSensor, InvalidModelsAreRejected) {
  const RayCaster scene(square({0, 0, 1}, {0, 0, -1}, 1.0));
  auto rejects = [&](SensorModel model) {
    EXPECT_THROW(simulateScan(scene, {}, kIdentity, model, 1), InputError);
  };
  SensorModel m = kinectV1();
  m.intrinsics.width = 0;
  rejects(m);
  m = kinectV1();
  m.intrinsics.fx = -1;
  rejects(m);
  m = kinectV1();
  m.min_range = 5.0;
  rejects(m);
  m = kinectV1();
  m.baseline = 0.0;
  rejects(m);
  m = swissRangerSr4000();
  m.mixed_pixel_samples = 2;
  rejects(m);
  m = swissRangerSr4000();
  m.intrinsics.distortion[0] = -3.0;  // folds over inside the image
  rejects(m);
  // A scan that does not match the model cannot be unprojected.
  SimulatedScan scan = simulateScan(scene, {}, kIdentity, kinectV1(), 1);
  EXPECT_THROW(unprojectScan(scan, swissRangerSr4000()), InputError);
}

TEST(RangeSensor, LensModelRoundTrip) {
  // Undistorting inverts OpenCV's distortion to rounding, also with the
  // tangential and k3 terms and across the SR4000's strong barrel distortion.
  const std::array<std::array<double, 5>, 3> models = {
      {{-0.82, 0.43, 0, 0, 0}, {-0.3, 0.1, 0.002, -0.001, 0.02}, {0.1, -0.24, 0, 0, -0.002}}};
  for (const auto& k : models)
    for (double x = -0.6; x <= 0.6; x += 0.05)
      for (double y = -0.45; y <= 0.45; y += 0.05) {
        const Eigen::Vector2d p(x, y);
        Eigen::Vector2d back;
        ASSERT_TRUE(undistortNormalised(k, distortNormalised(k, p), back)) << x << " " << y;
        EXPECT_LT((back - p).norm(), 1e-13);
      }
}

// Plane facing the camera: the spread of the measured depths is the model's
// axial sigma, and every depth lies on the disparity grid.
TEST(KinectModel, AxialNoiseAndDisparityGridOnAFacingPlane) {
  const SensorModel model = kinectV1();
  const double fb = model.intrinsics.fx * model.baseline;
  for (double z : {0.8, 1.5, 2.5, 3.5}) {
    const RayCaster scene(square({0, 0, z}, {0, 0, -1}, 20.0));
    const SimulatedScan scan = simulateScan(scene, {}, kIdentity, model, 11);
    std::vector<double> errors;
    std::size_t off_grid = 0;
    for (std::size_t i = 0; i < scan.range.size(); ++i) {
      ASSERT_NEAR(scan.true_range[i], z, 1e-5);
      if (scan.range[i] <= 0) continue;
      errors.push_back(static_cast<double>(scan.range[i]) - scan.true_range[i]);
      const double level = fb / (scan.range[i] * model.disparity_quantisation);
      off_grid += std::abs(level - std::round(level)) > 1e-3;
    }
    const Stats s = stats(errors);
    const double sigma = rangeNoiseSigma(model, z, 0.0);
    std::cout << "Kinect plane at " << z << " m: measured sigma " << s.stddev * 1e3 << " mm, model "
              << sigma * 1e3 << " mm, depth step " << kinectDepthStep(model, z) * 1e3 << " mm, bias "
              << s.mean * 1e3 << " mm, valid " << s.count << "\n";
    EXPECT_GT(s.count, scan.range.size() * 99 / 100);
    EXPECT_EQ(off_grid, 0u);
    EXPECT_NEAR(s.stddev, sigma, 0.2 * sigma);
    EXPECT_LT(std::abs(s.mean), 0.2 * sigma);
  }
}

// A plane tilted by 75 deg: the noise grows as Nguyen et al.'s angular term
// says, pixel by pixel.
TEST(KinectModel, IncidenceAngleRaisesTheNoise) {
  const SensorModel model = kinectV1();
  const CameraIntrinsics& in = model.intrinsics;
  const double z0 = 1.5;
  const Eigen::Vector3d normal = tiltedNormal(75 * kDegree);
  const RayCaster tilted(square({0, 0, z0}, normal, 20.0));
  const SimulatedScan scan = simulateScan(tilted, {}, kIdentity, model, 5);
  const SimulatedScan facing = simulateScan(RayCaster(square({0, 0, z0}, {0, 0, -1}, 20.0)), {}, kIdentity, model, 5);

  std::vector<double> normalised, band, band_facing;
  double model_band = 0.0;
  for (int v = 0; v < in.height; ++v)
    for (int u = 0; u < in.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v * in.width + u);
      if (scan.range[i] <= 0) continue;
      const Eigen::Vector3d ray = pixelDirection(in, u, v).normalized();
      const double theta = std::acos(std::abs(ray.dot(normal)));
      const double z = scan.true_range[i];
      const double error = static_cast<double>(scan.range[i]) - z;
      normalised.push_back(error / rangeNoiseSigma(model, z, theta));
      if (std::abs(z - z0) < 0.05) {
        band.push_back(error);
        model_band += std::pow(rangeNoiseSigma(model, z, theta), 2);
        band_facing.push_back(static_cast<double>(facing.range[i]) - facing.true_range[i]);
      }
    }
  const double rms = std::sqrt(std::inner_product(normalised.begin(), normalised.end(), normalised.begin(), 0.0) /
                               static_cast<double>(normalised.size()));
  const double tilted_sigma = stats(band).stddev, facing_sigma = stats(band_facing).stddev;
  std::cout << "Kinect at 1.5 m: sigma facing " << facing_sigma * 1e3 << " mm, tilted 75 deg " << tilted_sigma * 1e3
            << " mm (model " << std::sqrt(model_band / static_cast<double>(band.size())) * 1e3
            << " mm); normalised RMS over " << normalised.size() << " pixels " << rms << "\n";
  EXPECT_GT(normalised.size(), 20000u);
  EXPECT_NEAR(rms, 1.0, 0.2);
  EXPECT_GT(band.size(), 2000u);
  EXPECT_GT(tilted_sigma, 1.3 * facing_sigma);
}

// Beyond the grazing angle there is no depth; below it there is.
TEST(KinectModel, GrazingAnglesGiveNoReturn) {
  const SensorModel model = kinectV1();
  const CameraIntrinsics& in = model.intrinsics;
  const Eigen::Vector3d normal = tiltedNormal(80 * kDegree);
  const SimulatedScan scan = simulateScan(RayCaster(square({0, 0, 2.0}, normal, 30.0)), {}, kIdentity, model, 3);
  std::size_t beyond = 0, beyond_returned = 0, below = 0, below_returned = 0;
  for (int v = 0; v < in.height; ++v)
    for (int u = 0; u < in.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v * in.width + u);
      if (scan.true_range[i] <= 0) continue;
      const double theta = std::acos(std::abs(pixelDirection(in, u, v).normalized().dot(normal)));
      const double z = scan.true_range[i];
      if (theta > model.grazing_angle + 0.005) {
        ++beyond;
        beyond_returned += scan.range[i] > 0;
      } else if (theta < model.grazing_angle - 0.02 && z > 1.1 * model.min_range && z < 0.9 * model.max_range) {
        ++below;
        below_returned += scan.range[i] > 0;
      }
    }
  EXPECT_GT(beyond, 10000u);
  EXPECT_EQ(beyond_returned, 0u);
  EXPECT_GT(below, 10000u);
  EXPECT_GE(below_returned, below * 99 / 100);
}

// The projector, 7.5 cm to the camera's right, cannot light the wall just
// left of the box: no depth there; nothing is missing on the right.
TEST(KinectModel, ProjectorShadowsFallOnTheExpectedSide) {
  const SensorModel model = kinectV1();
  const CameraIntrinsics& in = model.intrinsics;
  const SimulatedScan scan = simulateScan(RayCaster(boxBeforeWall()), {}, kIdentity, model, 9);
  const Eigen::Vector3d projector(model.baseline, 0, 0);
  std::size_t shadow = 0, shadow_missing = 0, lit = 0, lit_missing = 0, shadow_right = 0, flying = 0;
  const double box_left_u = in.cx + in.fx * kBoxLo.x() / kBoxLo.z();
  for (int v = 0; v < in.height; ++v)
    for (int u = 0; u < in.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v * in.width + u);
      if (scan.range[i] > 1.25 && scan.range[i] < 1.85) ++flying;  // the Kinect does not mix depths
      if (scan.true_face[i] > 1) continue;                           // the box itself
      const Eigen::Vector3d point = scan.true_range[i] * pixelDirection(in, u, v);
      if (segmentHitsBox(projector, point, kBoxLo, kBoxHi)) {
        ++shadow;
        shadow_missing += scan.range[i] == 0;
        shadow_right += u > in.cx;
        EXPECT_LT(u, box_left_u + 1) << "shadow right of the box's left edge";
      } else {
        ++lit;
        lit_missing += scan.range[i] == 0;
      }
    }
  std::cout << "Kinect box before wall: " << shadow << " wall pixels in the projector's shadow, " << shadow_missing
            << " of them without depth; " << lit_missing << " of " << lit << " lit wall pixels without depth\n";
  EXPECT_GT(shadow, 1000u);
  EXPECT_EQ(shadow_right, 0u);
  EXPECT_GE(shadow_missing, shadow * 9 / 10);  // lateral noise moves the shadow's edges by a pixel or so
  EXPECT_LE(lit_missing, lit / 500);
  EXPECT_EQ(flying, 0u);
}

TEST(KinectModel, ColourImageIsShadedAlbedo) {
  const SensorModel model = kinectV1();
  SceneAppearance appearance;
  appearance.colour = [](int, const Eigen::Vector3d&) { return Colour{200, 100, 50}; };
  const Eigen::Vector3d normal = tiltedNormal(60 * kDegree);
  const SimulatedScan scan = simulateScan(RayCaster(square({0, 0, 2.0}, normal, 20.0)), appearance, kIdentity, model, 1);
  const std::size_t centre = static_cast<std::size_t>(240 * 640 + 320);
  const double theta = std::acos(std::abs(pixelDirection(model.intrinsics, 320, 240).normalized().dot(normal)));
  const double shade = model.ambient_light + (1 - model.ambient_light) * std::cos(theta);
  EXPECT_NEAR(scan.colour[centre][0], 200 * shade, 0.6);
  EXPECT_NEAR(scan.colour[centre][1], 100 * shade, 0.6);
  EXPECT_NEAR(scan.colour[centre][2], 50 * shade, 0.6);
  EXPECT_EQ(scan.confidence[centre], 255);
  EXPECT_GT(scan.intensity[centre], 0);
}

// SR4000 on a facing plane: noise from the amplitude, plus the wiggling.
TEST(Sr4000Model, RangeNoiseFollowsTheAmplitude) {
  const SensorModel model = swissRangerSr4000();
  double previous_intensity = 1e9;
  for (double z : {1.0, 2.0, 3.0}) {
    const SimulatedScan scan =
        simulateScan(RayCaster(square({0, 0, z}, {0, 0, -1}, 20.0)), {}, kIdentity, model, 21);
    const PointCloud truth = unprojectScan(scan, model, RangeSource::GroundTruth);
    const auto& pixel = truth.attributes.get("pixel").values;
    std::vector<double> residual, raw, wiggle;
    double model_variance = 0.0, intensity = 0.0;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const std::size_t i = static_cast<std::size_t>(pixel[k]);
      intensity += scan.intensity[i];
      if (scan.range[i] <= 0) continue;
      const double r = scan.true_range[i];
      const double theta = std::acos(std::abs(truth.positions[k].normalized().z()));
      const double sigma = rangeNoiseSigma(model, r, theta, 0.6);
      raw.push_back(static_cast<double>(scan.range[i]) - r);
      wiggle.push_back(sr4000Wiggling(model, r));
      residual.push_back((raw.back() - wiggle.back()) / sigma);
      model_variance += sigma * sigma;
    }
    intensity /= static_cast<double>(truth.size());
    const Stats normalised = stats(residual), measured = stats(raw), systematic = stats(wiggle);
    const double model_sigma = std::sqrt(model_variance / static_cast<double>(raw.size()));
    // The wiggling adds its own spread over the ranges a plane covers.
    const double expected = std::sqrt(model_sigma * model_sigma + systematic.stddev * systematic.stddev);
    std::cout << "SR4000 plane at " << z << " m: measured sigma " << measured.stddev * 1e3 << " mm, model "
              << model_sigma * 1e3 << " mm noise (+ wiggling spread " << systematic.stddev * 1e3
              << " mm); mean error " << measured.mean * 1e3 << " mm, mean wiggling " << systematic.mean * 1e3
              << " mm; mean intensity " << intensity << "\n";
    EXPECT_EQ(raw.size(), truth.size());
    EXPECT_NEAR(normalised.stddev, 1.0, 0.2);
    EXPECT_NEAR(measured.stddev, expected, 0.2 * expected);
    EXPECT_NEAR(measured.mean, systematic.mean, 0.1 * model_sigma + 2e-4);
    EXPECT_LT(intensity, previous_intensity);  // the amplitude image darkens with distance
    previous_intensity = intensity;
  }
}

TEST(Sr4000Model, GrazingAnglesGiveNoReturn) {
  const SensorModel model = swissRangerSr4000();
  const Eigen::Vector3d normal = tiltedNormal(85 * kDegree);
  const SimulatedScan scan = simulateScan(RayCaster(square({0, 0, 1.0}, normal, 30.0)), {}, kIdentity, model, 4);
  const PointCloud truth = unprojectScan(scan, model, RangeSource::GroundTruth);
  const auto& pixel = truth.attributes.get("pixel").values;
  std::size_t weak = 0, weak_returned = 0, strong = 0, strong_returned = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(pixel[k]);
    const double r = scan.true_range[i];
    const double theta = std::acos(std::abs(truth.positions[k].normalized().dot(normal)));
    const double amplitude = sr4000Amplitude(model, 0.6, theta, r);
    if (r < 1.05 * model.min_range || r > 0.9 * model.max_range) continue;
    if (amplitude < 0.8 * model.min_amplitude) {
      ++weak;
      weak_returned += scan.range[i] > 0;
    } else if (amplitude > 1.25 * model.min_amplitude) {
      ++strong;
      strong_returned += scan.range[i] > 0;
    }
  }
  std::cout << "SR4000 grazing: " << weak << " pixels below the amplitude threshold, " << strong << " above\n";
  EXPECT_GT(weak, 200u);
  EXPECT_EQ(weak_returned, 0u);
  EXPECT_GT(strong, 2000u);
  EXPECT_GE(strong_returned, strong * 99 / 100);
}

// Pixels across the box's silhouette see box and wall at once: their range
// is a mix, between the two.
TEST(Sr4000Model, MixedPixelsAtTheSilhouette) {
  const SensorModel model = swissRangerSr4000();
  const CameraIntrinsics& in = model.intrinsics;
  const SimulatedScan scan = simulateScan(RayCaster(boxBeforeWall()), {}, kIdentity, model, 2);
  std::size_t left = 0, right = 0, away = 0;
  double mixed_confidence = 0.0, box_confidence = 0.0;
  std::size_t box_pixels = 0;
  for (int v = 1; v + 1 < in.height; ++v)
    for (int u = 1; u + 1 < in.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v * in.width + u);
      const double r = scan.range[i];
      if (scan.true_face[i] > 1 && r > 0) {
        box_confidence += scan.confidence[i];
        ++box_pixels;
      }
      // The box's front is at 1.10-1.11 m (ray range, noise 2 mm), the wall
      // behind it at 2.0-2.1 m (noise 7 mm).
      if (!(r > 1.15 && r < 1.9)) continue;
      mixed_confidence += scan.confidence[i];
      bool box = false, wall = false;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          const int face = scan.true_face[static_cast<std::size_t>((v + dv) * in.width + u + du)];
          box |= face > 1;
          wall |= face == 0 || face == 1;
        }
      if (!(box && wall)) ++away;
      else if (u < in.cx) ++left;
      else ++right;
    }
  std::cout << "SR4000 box before wall: mixed pixels " << left << " left, " << right << " right of centre; "
            << "mean confidence " << mixed_confidence / std::max<std::size_t>(left + right, 1) << " mixed vs "
            << box_confidence / std::max<std::size_t>(box_pixels, 1) << " on the box\n";
  EXPECT_GT(left, 20u);
  EXPECT_GT(right, 20u);
  EXPECT_EQ(away, 0u);
  EXPECT_LT(mixed_confidence / static_cast<double>(left + right), box_confidence / static_cast<double>(box_pixels));

  // Without sub-rays there is nothing to mix.
  SensorModel single = model;
  single.mixed_pixel_samples = 1;
  const SimulatedScan sharp = simulateScan(RayCaster(boxBeforeWall()), {}, kIdentity, single, 2);
  EXPECT_EQ(std::count_if(sharp.range.begin(), sharp.range.end(), [](float r) { return r > 1.15f && r < 1.9f; }), 0);
}

// The noise-free ranges unprojected land on the surfaces hit, and project
// back to their pixels: the lens model round trip, with a camera pose.
TEST(RangeSensor, UnprojectedGroundTruthReproducesTheHitPoints) {
  TriangleMesh mesh = square({0.2, -0.1, 2.4}, Eigen::Vector3d(0.3, -0.2, -1.0), 3.0);
  append(mesh, box({-0.4, -0.3, 1.2}, {-0.1, 0.0, 1.5}));
  append(mesh, makeIcosphere(3, 0.25, {0.3, 0.2, 1.6}));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  pose.pretranslate(Eigen::Vector3d(0.5, -1.0, 2.0));
  TriangleMesh scene_mesh = mesh;
  for (auto& p : scene_mesh.vertices.positions) p = pose * p;  // the scene as seen from `pose`
  const RayCaster scene(scene_mesh);

  SensorModel distorted = swissRangerSr4000();
  distorted.intrinsics.distortion = {-0.3, 0.1, 0.002, -0.001, 0.02};
  for (const SensorModel& model : {kinectV1(), swissRangerSr4000(), distorted}) {
    const SimulatedScan scan = simulateScan(scene, {}, pose, model, 1);
    const PointCloud cloud = unprojectScan(scan, model, RangeSource::GroundTruth);
    const auto& pixel = cloud.attributes.get("pixel").values;
    ASSERT_GT(cloud.size(), static_cast<std::size_t>(model.intrinsics.width * model.intrinsics.height) / 2);
    double worst_point = 0.0, worst_pixel = 0.0;
    std::vector<Ray> rays;
    for (const Eigen::Vector3d& p : cloud.positions) {
      Ray ray;
      ray.origin = pose.translation();
      ray.direction = pose.rotation() * p;
      rays.push_back(ray);
    }
    const std::vector<RayHit> hits = scene.closestHits(rays);
    for (std::size_t k = 0; k < cloud.size(); ++k) {
      ASSERT_TRUE(hits[k].hit);
      worst_point = std::max(worst_point, (hits[k].point - pose * cloud.positions[k]).norm());
      const auto i = static_cast<std::size_t>(pixel[k]);
      const Eigen::Vector2d uv(static_cast<double>(i % static_cast<std::size_t>(scan.width)),
                               static_cast<double>(i / static_cast<std::size_t>(scan.width)));
      worst_pixel = std::max(worst_pixel, (projectPoint(model.intrinsics, cloud.positions[k]) - uv).norm());
    }
    EXPECT_LT(worst_point, 1e-6) << model.name;
    EXPECT_LT(worst_pixel, 1e-6) << model.name;
    // The measured cloud keeps the pixel order and the colours.
    const PointCloud measured = unprojectScan(scan, model);
    EXPECT_EQ(measured.hasColours(), model.type == SensorType::Kinect);
    EXPECT_GT(measured.size(), cloud.size() / 2);
  }
}

TEST(RangeSensor, DeterministicForASeedWhateverTheThreadCount) {
  TriangleMesh mesh = boxBeforeWall();
  append(mesh, makeIcosphere(3, 0.2, {0.4, 0.1, 1.5}));
  const RayCaster scene(mesh);
  SceneAppearance appearance;
  appearance.reflectivity = [](int face, const Eigen::Vector3d&) { return face % 2 ? 0.3 : 0.8; };
  for (const SensorModel& model : {kinectV1(), swissRangerSr4000()}) {
    auto render = [&](int threads, std::uint64_t seed) {
      SimulatedScan scan;
      tbb::task_arena(threads).execute([&] { scan = simulateScan(scene, appearance, kIdentity, model, seed); });
      return scan;
    };
    const SimulatedScan one = render(1, 42), two = render(2, 42), again = render(2, 42), other = render(2, 43);
    for (const SimulatedScan* s : {&two, &again}) {
      EXPECT_EQ(one.range, s->range) << model.name;
      EXPECT_EQ(one.colour, s->colour);
      EXPECT_EQ(one.intensity, s->intensity);
      EXPECT_EQ(one.confidence, s->confidence);
      EXPECT_EQ(one.true_range, s->true_range);
      EXPECT_EQ(one.true_face, s->true_face);
    }
    EXPECT_NE(one.range, other.range) << model.name;
    EXPECT_EQ(one.true_range, other.true_range);
  }
}

// Not a check: frames per second of both sensors on a small scene, for
// docs/sensors.md.
TEST(RangeSensor, RenderingSpeed) {
  TriangleMesh mesh = boxBeforeWall();
  append(mesh, makeIcosphere(5, 0.2, {0.4, 0.1, 1.5}));  // 20k faces
  const RayCaster scene(mesh);
  for (const SensorModel& model : {kinectV1(), swissRangerSr4000()}) {
    const int frames = model.type == SensorType::Kinect ? 5 : 20;
    const auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) simulateScan(scene, {}, kIdentity, model, static_cast<std::uint64_t>(f));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << model.name << ": " << frames / seconds << " frames/s with "
              << tbb::this_task_arena::max_concurrency() << " threads\n";
  }
}

}  // namespace
}  // namespace icrkit::sim
