#pragma once
/// \file
/// The Kinect v1's depth measurement: triangulation against the projector
/// with 1/8-pixel disparity steps (Konolige and Mihelich), axial and lateral
/// noise after Nguyen, Izadi and Lovell (3DIMPVT 2012). docs/sensors.md.

#include <icrkit/sim/range_sensor.hpp>

namespace icrkit::sim {

/// Standard deviation (m) of the output depth of a surface at `depth` m
/// seen at `incidence` rad: sigma_z = a + b (z - c)^2 + d / sqrt(z) * t^2 / (pi/2 - t)^2.
double kinectAxialSigma(const SensorModel& model, double depth, double incidence);

/// Standard deviation (pixels) of where a pixel samples the surface:
/// sigma_L = s0 + s1 * t / (pi/2 - t).
double kinectLateralSigmaPx(const SensorModel& model, double incidence);

/// Depth step (m) between neighbouring disparity levels at `depth`:
/// z^2 q / (f b).
double kinectDepthStep(const SensorModel& model, double depth);

/// The depth the sensor reports for a (noisy) disparity in pixels: the
/// disparity rounded to the quantisation grid, then z = f b / d. 0 when the
/// rounded disparity is not positive (a surface "at infinity").
double kinectQuantisedDepth(const SensorModel& model, double disparity);

}  // namespace icrkit::sim
