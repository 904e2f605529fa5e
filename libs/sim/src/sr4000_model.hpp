#pragma once
/// \file
/// The SwissRanger SR4000's range measurement: continuous-wave time of
/// flight, with noise set by the returned amplitude (Lange and Seitz 2001)
/// and the systematic "wiggling" error of a non-sinusoidal modulation
/// sampled at four phases. docs/sensors.md.

#include <icrkit/sim/range_sensor.hpp>

namespace icrkit::sim {

/// Speed of light in vacuum, m/s (the SR4000 works in air; the 3e-4
/// relative difference is far below its noise).
constexpr double kSpeedOfLight = 299792458.0;

/// Returned amplitude (1 = a white surface facing the camera at the
/// reference range): reflectivity * cos(incidence) * (r_ref / range)^2.
double sr4000Amplitude(const SensorModel& model, double reflectivity, double incidence, double range);

/// Standard deviation (m) of the range at `amplitude`: sigma_ref / amplitude.
double sr4000RangeSigma(const SensorModel& model, double amplitude);

/// Systematic range error (m) at `range`: A_w sin(2 pi range / wavelength).
double sr4000Wiggling(const SensorModel& model, double range);

/// Phase (radians) of the modulation after the round trip to `range`: 4 pi f r / c.
double sr4000Phase(const SensorModel& model, double range);

}  // namespace icrkit::sim
