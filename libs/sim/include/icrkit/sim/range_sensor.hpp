#pragma once
/// \file
/// Range sensor models (Microsoft Kinect v1, MESA SwissRanger SR4000) and the
/// rendering of one simulated scan of a scene with Embree (core RayCaster).
/// Parameters and their sources: docs/sensors.md.
///
/// Camera frame used here: the optical frame (x right, y down, z forward,
/// as in OpenCV). MRPT's sensor frame (x forward, y left, z up) is only used
/// when a scan is written to a rawlog.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace icrkit::sim {

enum class SensorType { Kinect, Sr4000 };

/// "kinect", "sr4000". Throws InputError("--sensor", ...) for anything else.
SensorType parseSensorType(const std::string& name);
std::string sensorTypeName(SensorType type);

/// Pinhole intrinsics with OpenCV's (Brown-Conrady) distortion k1, k2, p1, p2, k3.
struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> distortion{};  ///< k1, k2, p1, p2, k3
};

/// Every number of a sensor model; the factory functions fill realistic,
/// documented defaults. Units: metres, radians, pixels.
struct SensorModel {
  SensorType type = SensorType::Kinect;
  CameraIntrinsics intrinsics;
  bool range_is_depth = true;   ///< true: the z coordinate (Kinect); false: distance along the ray (SR4000)
  double range_units = 0.001;   ///< metres per count of the stored 16-bit range image
  double min_range = 0.5, max_range = 4.0;  ///< metres; outside: no return (0)
  // Kinect: depth from disparity of a projector-camera pair.
  double baseline = 0.075;               ///< projector-camera baseline (m), projector at +x of the IR camera
  double disparity_quantisation = 0.125; ///< pixels (1/8 px subpixel disparity steps)
  // Axial noise sigma_z(z, theta) = a + b (z - c)^2 + d z^2 theta^2 / (pi/2 - theta)^2 (Nguyen et al. 2012 form)
  double axial_a = 0.0012, axial_b = 0.0019, axial_c = 0.4, axial_d = 0.0001;
  double lateral_sigma_px = 0.8;         ///< lateral noise in pixels (Nguyen et al.: about 0.8 px)
  double grazing_angle = 1.45;           ///< radians from the normal beyond which no depth is returned
  // SR4000: time-of-flight range.
  double range_noise_at_reference = 0.004;  ///< metres, sigma at the reference amplitude
  double wiggling_amplitude = 0.005;        ///< metres, systematic error amplitude
  double wiggling_wavelength = 1.875;       ///< metres (half of the 15 MHz modulation's 10 m / ... see docs)
  double mixed_pixel_fraction = 1.0;        ///< share of depth-discontinuity pixels that come out mixed
  std::string name;                          ///< "Kinect v1", "SwissRanger SR4000"
};

SensorModel kinectV1();
SensorModel swissRangerSr4000();
SensorModel sensorModel(SensorType type);

/// What the scene looks like to the sensors: RGB albedo (Kinect's colour
/// image) and near-infrared reflectivity in [0, 1] (the SR4000's amplitude).
struct SceneAppearance {
  std::function<Color(int face, const Eigen::Vector3d& point)> color;  ///< default: mid grey
  std::function<double(int face, const Eigen::Vector3d& point)> reflectivity;  ///< default: 0.6
};

/// One simulated frame, row-major, width x height.
struct SimulatedScan {
  int width = 0, height = 0;
  std::vector<float> range;          ///< metres (depth or ray range per the model), 0 = no return
  std::vector<Color> color;          ///< Kinect: the colour image (registered to depth); empty for SR4000
  std::vector<std::uint8_t> intensity;   ///< SR4000 amplitude image; Kinect: IR-like grey image
  std::vector<std::uint8_t> confidence;  ///< 0..255; SR4000 from the amplitude; Kinect: 255 where valid
  // Ground truth, kept for tests (not written to rawlogs).
  std::vector<float> true_range;     ///< noise-free range of the first surface hit, 0 = none
  std::vector<int> true_face;        ///< face hit, -1 = none
};

/// Renders one scan of `scene` seen from `camera_in_scene` (the optical
/// frame's pose in the scene frame). Deterministic for a seed, whatever the
/// thread count.
SimulatedScan simulateScan(const RayCaster& scene, const SceneAppearance& appearance,
                           const Eigen::Isometry3d& camera_in_scene, const SensorModel& model, std::uint64_t seed);

/// The scan's valid pixels unprojected to 3D in the optical frame
/// (undistorting with the model's intrinsics), for tests and tools.
PointCloud unprojectScan(const SimulatedScan& scan, const SensorModel& model);

}  // namespace icrkit::sim
