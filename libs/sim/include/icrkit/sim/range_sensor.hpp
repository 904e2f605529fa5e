#pragma once
/// \file
/// Range sensor models (Microsoft Kinect v1, MESA SwissRanger SR4000) and the
/// rendering of one simulated scan of a scene with Embree (core RayCaster).
/// Equations, parameters and their sources: docs/sensors.md.
///
/// Camera frame used here: the optical frame (x right, y down, z forward,
/// as in OpenCV). MRPT's sensor frame (x forward, y left, z up) is only used
/// when a scan is written to a rawlog. Pixel (column u, row v) has its centre
/// at image coordinates (u, v): OpenCV's convention.

#include <icrkit/core/camera_intrinsics.hpp>
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

using icrkit::CameraIntrinsics;  // core/camera_intrinsics.hpp

/// Every number of a sensor model; the factory functions fill realistic,
/// documented defaults (docs/sensors.md). Units: metres, radians, pixels.
/// Fields a model does not use are ignored (e.g. `baseline` by the SR4000).
struct SensorModel {
  SensorType type = SensorType::Kinect;
  CameraIntrinsics intrinsics;
  bool range_is_depth = true;   ///< true: the z coordinate (Kinect); false: distance along the ray (SR4000)
  double range_units = 0.001;   ///< metres per count of the stored 16-bit range image (rawlogs)
  double min_range = 0.5, max_range = 4.0;  ///< metres, on the measured range; outside: no return (0)
  /// Incidence angle (between the pixel's ray and the surface normal) beyond
  /// which no range is returned; >= pi/2 turns the cut-off off.
  double grazing_angle = 1.40;

  // --- Kinect: depth from the disparity of a projector-camera pair. ---
  double baseline = 0.075;               ///< projector-camera baseline (m), projector at +x of the IR camera
  double disparity_quantisation = 0.125; ///< pixels (1/8 px subpixel disparity steps)
  /// Axial noise, the standard deviation of the output depth (quantisation
  /// included, as measured by Nguyen et al. 2012):
  /// sigma_z(z, theta) = a + b (z - c)^2 + d / sqrt(z) * theta^2 / (pi/2 - theta)^2.
  double axial_a = 0.0012, axial_b = 0.0019, axial_c = 0.4, axial_d = 0.0001;
  /// Share (0..1) of the axial noise's variance that is spatially
  /// correlated: a structured-light camera matches a window of the pattern
  /// per pixel, so neighbouring pixels share much of their error. That share
  /// is a Gaussian random field over the image (white noise blurred by a
  /// Gaussian of `axial_correlation_px` pixels, autocorrelation
  /// exp(-d^2 / (4 s^2)) at d pixels), the rest independent per pixel; sigma_z
  /// is the same either way. 0 (default): all independent, as the datasets
  /// have always been made. Kinect only; the length in [1, 64] pixels.
  /// docs/sensors.md, "Correlated depth noise".
  double axial_correlated_share = 0.0;
  double axial_correlation_px = 3.0;
  /// Lateral noise in pixels: sigma_L(theta) = lateral_sigma_px + lateral_sigma_slope * theta / (pi/2 - theta).
  double lateral_sigma_px = 0.8, lateral_sigma_slope = 0.035;
  /// Colour image: share of the light that is ambient; the rest is a
  /// Lambertian light at the camera.
  double ambient_light = 0.3;

  // --- SR4000: continuous-wave time-of-flight range. ---
  double modulation_frequency = 30e6;       ///< Hz; the non-ambiguity range is c / (2 f)
  /// Returned amplitude, in units of what a white (reflectivity 1) surface
  /// facing the camera at `amplitude_reference_range` returns:
  /// A = reflectivity * cos(incidence) * (amplitude_reference_range / range)^2.
  double amplitude_reference_range = 2.0;   ///< metres
  double range_noise_at_reference = 0.004;  ///< metres, sigma of the range at A = 1; sigma = this / A
  double min_amplitude = 0.05;              ///< below: no return (the noise would exceed 8 cm)
  double amplitude_full_scale = 4.0;        ///< amplitude shown as 255 in the intensity image
  double wiggling_amplitude = 0.005;        ///< metres, of the systematic error A_w sin(2 pi r / wavelength)
  double wiggling_wavelength = 1.249;       ///< metres: c / (8 f), a quarter of the non-ambiguity range
  /// Sub-rays per pixel side (n x n per pixel, on a regular grid whose
  /// centre is the pixel's own ray); their returns are summed as phasors, so
  /// pixels across a depth discontinuity come out mixed. 1: no mixing.
  int mixed_pixel_samples = 3;

  std::string name;                          ///< "Kinect v1", "SwissRanger SR4000"
};

SensorModel kinectV1();
SensorModel swissRangerSr4000();
SensorModel sensorModel(SensorType type);

/// The model's standard deviation of the measured range (metres) for a
/// surface at `range` (depth for the Kinect, distance along the ray for the
/// SR4000) seen at `incidence` radians from its normal, of NIR reflectivity
/// `reflectivity` (used by the SR4000 only). The systematic errors
/// (quantisation steps are part of the Kinect's sigma; the SR4000's
/// wiggling is not) and the lateral noise are not included.
double rangeNoiseSigma(const SensorModel& model, double range, double incidence, double reflectivity = 0.6);

/// What the scene looks like to the sensors: RGB albedo (Kinect's colour
/// image) and near-infrared reflectivity in [0, 1] (the SR4000's amplitude,
/// the Kinect's IR image). Both are called concurrently from several
/// threads, with the face hit and the point in the scene frame.
struct SceneAppearance {
  std::function<Colour(int face, const Eigen::Vector3d& point)> colour;  ///< default: mid grey
  std::function<double(int face, const Eigen::Vector3d& point)> reflectivity;  ///< default: 0.6
};

/// One simulated frame, row-major, width x height.
struct SimulatedScan {
  int width = 0, height = 0;
  std::vector<float> range;          ///< metres (depth or ray range per the model), 0 = no return
  std::vector<Colour> colour;          ///< Kinect: the colour image (registered to depth); empty for SR4000
  std::vector<std::uint8_t> intensity;   ///< SR4000 amplitude image; Kinect: IR-like grey image
  std::vector<std::uint8_t> confidence;  ///< 0..255; SR4000 from the amplitude; Kinect: 255 where valid
  // Ground truth, kept for tests (not written to rawlogs).
  std::vector<float> true_range;     ///< noise-free range (depth or ray range) of the surface the pixel's central ray hits, 0 = none
  std::vector<int> true_face;        ///< face hit by the pixel's central ray, -1 = none
};

/// Renders one scan of `scene` seen from `camera_in_scene` (the optical
/// frame's pose in the scene frame). Deterministic for a seed, whatever the
/// thread count. Throws InputError for an inconsistent model (sizes, focal
/// lengths, ranges).
SimulatedScan simulateScan(const RayCaster& scene, const SceneAppearance& appearance,
                           const Eigen::Isometry3d& camera_in_scene, const SensorModel& model, std::uint64_t seed);

/// Which range image unprojectScan reads.
enum class RangeSource { Measured, GroundTruth };

/// The scan's pixels with a range (range > 0, or true_range > 0 for
/// GroundTruth) unprojected to 3D in the optical frame, undistorting with
/// the model's intrinsics, for tests and tools. Row-major pixel order;
/// attributes "pixel" (row * width + column), "intensity", "confidence";
/// colours when the scan has a colour image. Throws InputError when the
/// scan's size does not match the model.
PointCloud unprojectScan(const SimulatedScan& scan, const SensorModel& model,
                         RangeSource source = RangeSource::Measured);

}  // namespace icrkit::sim
