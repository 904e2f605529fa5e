#pragma once
// The noise layer of a cloud fused from many views: how thick it is against
// the points' spacing, and one representative point per cell where it is
// too thick for a ball of a few spacings to roll over.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace icrkit::reconstruction {

/// Median, over up to `samples` evenly strided points, of the RMS
/// distance of the points within `window` metres from a quadric height
/// field fitted to them over their best-fit plane: about 0 for a clean
/// sample of a smooth surface whatever its curvature, the noise layer's
/// half-thickness for a fused cloud. Points with `skip` set are left out
/// (as centres and as neighbours). 0 when no window holds 12 points.
double layerThickness(const std::vector<Eigen::Vector3d>& points, const std::vector<std::uint8_t>& skip,
                      double window, std::size_t samples = 4000);

/// One point per cube of edge `cell` (metres): of each cube's points not
/// skipped, the one nearest the cube's points' centroid (the lower index
/// on a tie) is kept. Returns the keep flags (skipped points: 0).
std::vector<std::uint8_t> thinToCells(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<std::uint8_t>& skip, double cell);

}  // namespace icrkit::reconstruction
