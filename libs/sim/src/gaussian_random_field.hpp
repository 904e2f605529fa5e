#pragma once
/// \file
/// A spatially correlated noise image: the part of a structured-light
/// camera's depth error that neighbouring pixels share (range_sensor.hpp,
/// SensorModel::axial_correlated_share).

#include <cstdint>
#include <vector>

namespace icrkit::sim {

/// A Gaussian random field over a width x height image, row-major, with
/// mean 0 and variance 1 at every pixel (borders included): independent
/// standard normals per pixel blurred by a separable Gaussian kernel of
/// standard deviation `sigma_px` pixels (cut at 3 sigma), each 1-D pass
/// divided by the root of the sum of its squared weights inside the image.
/// Two pixels d apart away from the borders correlate by exp(-d^2 / (4
/// sigma_px^2)). Deterministic for a seed, whatever the thread count.
/// Requires width, height >= 1 and sigma_px > 0.
std::vector<float> gaussianRandomField(int width, int height, double sigma_px, std::uint64_t seed);

}  // namespace icrkit::sim
