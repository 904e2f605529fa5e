#pragma once
/// \file
/// Independent Contact Regions painted on their mesh, as `icrkit icr` writes
/// its PLY: one colour per finger (Tableau 10 without its grey; more than
/// nine fingers reuse the hues), grey outside every region, each region's
/// recommended contact black; int vertex attributes `region` (the finger
/// index, -1 outside; a vertex in several regions gets the lowest finger
/// index) and `recommended` (the finger index at its recommended vertex,
/// -1 elsewhere).

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <vector>

namespace icrkit::icr {

/// A copy of `mesh` (the mesh the regions were grown on) with the colours
/// and attributes above. InputError("regions", "finger N") for a vertex
/// index outside the mesh.
TriangleMesh regionMesh(const TriangleMesh& mesh, const std::vector<ContactRegion>& regions);

}  // namespace icrkit::icr
