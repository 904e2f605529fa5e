#include <icrkit/sim/range_sensor.hpp>

#include <icrkit/core/error.hpp>

#include "kinect_model.hpp"
#include "lens_distortion.hpp"
#include "scan_rendering.hpp"
#include "sr4000_model.hpp"

#include <cmath>
#include <string>
#include <utility>

namespace icrkit::sim {

SensorType parseSensorType(const std::string& name) {
  if (name == "kinect") return SensorType::Kinect;
  if (name == "sr4000") return SensorType::Sr4000;
  throw InputError("sensor name", "", "unknown sensor '" + name + "', expected one of kinect, sr4000");
}

std::string sensorTypeName(SensorType type) {
  switch (type) {
    case SensorType::Kinect: return "kinect";
    case SensorType::Sr4000: return "sr4000";
  }
  throw InputError("sensor name", "", "unknown sensor type " + std::to_string(static_cast<int>(type)));
}

SensorModel sensorModel(SensorType type) {
  switch (type) {
    case SensorType::Kinect: return kinectV1();
    case SensorType::Sr4000: return swissRangerSr4000();
  }
  throw InputError("sensor name", "", "unknown sensor type " + std::to_string(static_cast<int>(type)));
}

double rangeNoiseSigma(const SensorModel& model, double range, double incidence, double reflectivity) {
  if (model.type == SensorType::Kinect) return kinectAxialSigma(model, range, incidence);
  return sr4000RangeSigma(model, sr4000Amplitude(model, reflectivity, incidence, range));
}

namespace {
void require(bool condition, const char* field, const std::string& detail) {
  if (!condition) throw InputError("sensor model", field, detail);
}
bool positive(double value) { return value > 0.0 && std::isfinite(value); }
}  // namespace

void checkSensorModel(const SensorModel& model) {
  const CameraIntrinsics& in = model.intrinsics;
  require(in.width > 0 && in.height > 0 && in.width <= 16384 && in.height <= 16384, "intrinsics",
          "image size must be 1..16384 pixels a side, got " + std::to_string(in.width) + " x " +
              std::to_string(in.height));
  require(positive(in.fx) && positive(in.fy), "intrinsics", "focal lengths must be finite and > 0");
  require(std::isfinite(in.cx) && std::isfinite(in.cy), "intrinsics", "the principal point must be finite");
  for (double k : in.distortion) require(std::isfinite(k), "intrinsics", "distortion coefficients must be finite");
  // Every pixel needs its one physical ray: the lens model must be
  // invertible, without a fold, out to the image's corners and edges.
  const double w = in.width - 0.5, h = in.height - 0.5;
  for (const auto& [u, v] : {std::pair{-0.5, -0.5}, std::pair{w, -0.5}, std::pair{-0.5, h}, std::pair{w, h},
                            std::pair{w / 2, -0.5}, std::pair{-0.5, h / 2}, std::pair{w, h / 2}, std::pair{w / 2, h}})
    require(monotoneAlongRadius(in.distortion, pixelDirection(in, u, v).head<2>()), "intrinsics",
            "the distortion cannot be inverted at the image corner or edge (" + std::to_string(u) + ", " +
                std::to_string(v) + ")");
  require(model.min_range >= 0.0 && model.min_range < model.max_range && std::isfinite(model.max_range),
          "min_range", "need 0 <= min_range < max_range < infinity");
  require(model.grazing_angle > 0.0, "grazing_angle", "must be > 0");
  if (model.type == SensorType::Kinect) {
    require(positive(model.baseline), "baseline", "must be finite and > 0");
    require(positive(model.disparity_quantisation), "disparity_quantisation", "must be finite and > 0");
    require(model.axial_a >= 0 && model.axial_b >= 0 && model.axial_d >= 0, "axial_a", "noise coefficients must be >= 0");
    require(model.lateral_sigma_px >= 0 && model.lateral_sigma_slope >= 0, "lateral_sigma_px", "must be >= 0");
    require(model.axial_correlated_share >= 0 && model.axial_correlated_share <= 1, "axial_correlated_share",
            "must be in [0, 1]");
    // Below a pixel the sampled kernel no longer has the Gaussian
    // correlation the field promises.
    require(model.axial_correlated_share == 0 || (model.axial_correlation_px >= 1 && model.axial_correlation_px <= 64),
            "axial_correlation_px", "must be in [1, 64] pixels");
    require(model.ambient_light >= 0 && model.ambient_light <= 1, "ambient_light", "must be in [0, 1]");
  } else {
    require(positive(model.modulation_frequency), "modulation_frequency", "must be finite and > 0");
    require(positive(model.amplitude_reference_range), "amplitude_reference_range", "must be finite and > 0");
    require(model.range_noise_at_reference >= 0, "range_noise_at_reference", "must be >= 0");
    require(model.min_amplitude >= 0, "min_amplitude", "must be >= 0");
    require(positive(model.amplitude_full_scale), "amplitude_full_scale", "must be finite and > 0");
    require(model.axial_correlated_share == 0, "axial_correlated_share",
            "must be 0: only the Kinect model has correlated depth noise");
    require(positive(model.wiggling_wavelength), "wiggling_wavelength", "must be finite and > 0");
    require(model.mixed_pixel_samples >= 1 && model.mixed_pixel_samples <= 15 && model.mixed_pixel_samples % 2 == 1,
            "mixed_pixel_samples",
            "must be odd (the pixel centre is one of the sub-rays), 1..15, got " + std::to_string(model.mixed_pixel_samples));
  }
}

}  // namespace icrkit::sim
