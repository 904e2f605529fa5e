#pragma once
/// \file
/// Algorithm 2 for two region sets of one grasp, paired by finger: the CAD
/// mesh's regions and a reconstruction's, each as a regions file lists them
/// (icr/regions_file.hpp: a finger number per region, in any order).

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/intersection_estimation.hpp>

#include <cstddef>
#include <vector>

namespace icrkit::eval {

struct FingerIntersection {
  int finger = 0;
  std::size_t cad_region = 0;   ///< index into the CAD side's lists
  std::size_t scan_region = 0;  ///< index into the reconstruction's lists
  RegionIntersection intersection;
};

/// One entry per CAD region, in the CAD side's order: its intersection
/// with the reconstruction's region of the same finger
/// (IntersectionEstimator::estimate). Every finger must be on both sides:
/// InputError("reconstructed regions" or "CAD regions", "", "has no region
/// for finger N, ...") otherwise, and InputError("CAD regions" or
/// "reconstructed regions") when a side's finger and region counts differ.
std::vector<FingerIntersection> intersectByFinger(const IntersectionEstimator& cad, const std::vector<int>& cad_fingers,
                                                  const std::vector<std::vector<int>>& cad_regions,
                                                  const TriangleMesh& scan, const std::vector<int>& scan_fingers,
                                                  const std::vector<std::vector<int>>& scan_regions);

}  // namespace icrkit::eval
