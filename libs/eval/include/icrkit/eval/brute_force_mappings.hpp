#pragma once
/// \file
/// The normal-line mappings computed by exhaustive search: every triangle for
/// the line crossing or the nearest surface point, every vertex for the
/// candidates, in double precision. Same rules as normal_line_mappings.hpp;
/// the reference that tests and benchmarks compare the Embree version with.

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/normal_line_mappings.hpp>

#include <Eigen/Core>

namespace icrkit::eval {

/// P_C2S by brute force; `neighbourhood_radius` and `max_line_distance` as
/// resolved by a MappingTarget (no automatic values here).
VertexImage bruteForceCadToScan(const TriangleMesh& scan, const Eigen::Vector3d& cad_point,
                                const Eigen::Vector3d& cad_normal, double neighbourhood_radius,
                                double max_line_distance);

/// P_S2C by brute force.
VertexImage bruteForceScanToCad(const TriangleMesh& cad, const Eigen::Vector3d& scan_point,
                                const Eigen::Vector3d& scan_normal, double neighbourhood_radius,
                                double max_line_distance);

}  // namespace icrkit::eval
