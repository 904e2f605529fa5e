#include "sr4000_model.hpp"

#include <algorithm>
#include <cmath>

namespace icrkit::sim {

SensorModel swissRangerSr4000() {
  SensorModel m;
  m.type = SensorType::Sr4000;
  m.name = "SwissRanger SR4000";
  // 176 x 144 pixels of 40 um behind a 10 mm lens: f = 250 px. With that
  // focal length the datasheet's 43.6 x 34.6 deg field of view needs barrel
  // distortion; k1, k2 are the values for which the image edges see exactly
  // those half-angles (docs/sensors.md).
  m.intrinsics.width = 176;
  m.intrinsics.height = 144;
  m.intrinsics.fx = m.intrinsics.fy = 250.0;
  m.intrinsics.cx = 87.5;
  m.intrinsics.cy = 71.5;
  m.intrinsics.distortion = {-0.82, 0.43, 0.0, 0.0, 0.0};
  m.range_is_depth = false;
  m.range_units = 0.001;
  m.min_range = 0.1;
  m.max_range = 5.0;
  // No explicit cut-off: towards grazing incidence the amplitude falls
  // with cos(theta) below min_amplitude.
  m.grazing_angle = 1.5707963267948966;
  m.modulation_frequency = 30e6;
  m.amplitude_reference_range = 2.0;
  m.range_noise_at_reference = 0.004;
  m.min_amplitude = 0.05;
  m.amplitude_full_scale = 4.0;
  m.wiggling_amplitude = 0.005;
  m.wiggling_wavelength = kSpeedOfLight / (8.0 * m.modulation_frequency);
  m.mixed_pixel_samples = 3;
  return m;
}

double sr4000Amplitude(const SensorModel& model, double reflectivity, double incidence, double range) {
  const double ratio = model.amplitude_reference_range / std::max(range, 1e-6);
  return std::max(reflectivity, 0.0) * std::max(std::cos(incidence), 0.0) * ratio * ratio;
}

double sr4000RangeSigma(const SensorModel& model, double amplitude) {
  return model.range_noise_at_reference / std::max(amplitude, 1e-12);
}

double sr4000Wiggling(const SensorModel& model, double range) {
  return model.wiggling_amplitude * std::sin(6.283185307179586 * range / model.wiggling_wavelength);
}

double sr4000Phase(const SensorModel& model, double range) {
  return 4.0 * 3.141592653589793 * model.modulation_frequency * range / kSpeedOfLight;
}

}  // namespace icrkit::sim
