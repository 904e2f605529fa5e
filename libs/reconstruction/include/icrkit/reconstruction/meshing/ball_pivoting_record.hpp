#pragma once
/// \file
/// What one ball pivoting did, as the JSON object `icrkit mesh` writes next
/// to its mesh (docs/formats.md).

#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>

#include <string>

namespace icrkit::reconstruction {

/// Every field of `report` as JSON text (keys sorted, lengths in metres with
/// an `_m` suffix): points, median_spacing_m, radii_m, passes [{radius_m,
/// seeds, triangles, time_ms}], triangles, used/unused/duplicate/unoriented
/// points, layer_thickness_m, thinning_cell_m, thinned/reinserted points,
/// mesh_spacing_m, removed_faces, boundary_edges, closed/folded holes,
/// boundary_loops, non_manifold_edges, components, euler_characteristic.
std::string ballPivotingRecordJson(const BallPivotingReport& report);

}  // namespace icrkit::reconstruction
