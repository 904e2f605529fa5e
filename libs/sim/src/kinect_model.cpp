#include "kinect_model.hpp"

#include <algorithm>
#include <cmath>

namespace icrkit::sim {
namespace {
constexpr double kHalfPi = 1.5707963267948966;

// theta / (pi/2 - theta), the growth of Nguyen et al.'s noise terms towards
// grazing incidence; capped just short of pi/2 where it diverges.
double grazingRatio(double incidence) {
  const double theta = std::min(std::abs(incidence), kHalfPi - 1e-6);
  return theta / (kHalfPi - theta);
}
}  // namespace

SensorModel kinectV1() {
  SensorModel m;
  m.type = SensorType::Kinect;
  m.name = "Kinect v1";
  // IR (depth) camera at 640 x 480, f ~ 580 px (Konolige and Mihelich's ROS
  // calibration notes; Khoshelham and Elberink's calibration gives 586 px).
  // The depth image is computed on the IR camera's pixel grid; its lens
  // distortion is small enough that the sensor's own output ignores it.
  m.intrinsics.width = 640;
  m.intrinsics.height = 480;
  m.intrinsics.fx = m.intrinsics.fy = 580.0;
  m.intrinsics.cx = 319.5;
  m.intrinsics.cy = 239.5;
  m.intrinsics.distortion = {0.0, 0.0, 0.0, 0.0, 0.0};
  m.range_is_depth = true;
  m.range_units = 0.001;
  m.min_range = 0.5;
  m.max_range = 4.0;
  m.grazing_angle = 1.40;  // ~80 deg: an assumption, docs/sensors.md
  m.baseline = 0.075;
  m.disparity_quantisation = 0.125;
  m.axial_a = 0.0012;
  m.axial_b = 0.0019;
  m.axial_c = 0.4;
  m.axial_d = 0.0001;
  m.lateral_sigma_px = 0.8;
  m.lateral_sigma_slope = 0.035;
  m.ambient_light = 0.3;
  return m;
}

double kinectAxialSigma(const SensorModel& model, double depth, double incidence) {
  const double z = std::max(depth, 1e-3);
  const double offset = z - model.axial_c;
  const double ratio = grazingRatio(incidence);
  // Nguyen et al. add the angular term only beyond 60 deg, where it starts
  // to matter; below it is under 0.04 mm / sqrt(z) and is kept here so that
  // sigma is continuous in the angle.
  return model.axial_a + model.axial_b * offset * offset + model.axial_d / std::sqrt(z) * ratio * ratio;
}

double kinectLateralSigmaPx(const SensorModel& model, double incidence) {
  return model.lateral_sigma_px + model.lateral_sigma_slope * grazingRatio(incidence);
}

double kinectDepthStep(const SensorModel& model, double depth) {
  return depth * depth * model.disparity_quantisation / (model.intrinsics.fx * model.baseline);
}

double kinectQuantisedDepth(const SensorModel& model, double disparity) {
  const double q = model.disparity_quantisation;
  const double level = std::round(disparity / q);
  if (!(level >= 1.0)) return 0.0;
  return model.intrinsics.fx * model.baseline / (level * q);
}

}  // namespace icrkit::sim
