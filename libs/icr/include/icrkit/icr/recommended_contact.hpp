#pragma once
/// \file
/// The point of a region a robot should aim its finger at.
///
/// Choice: the region's deepest vertex, the one farthest (along mesh edges)
/// from the region's border, so that a finger placed there may miss by up
/// to that depth in any direction along the surface and still land in the
/// region. (The paper's central point, Fig. 7, minimises the largest
/// distance to the other vertices instead; on a non-convex region, a
/// C-shaped one say, it can lie on the border and then tolerates no error.)
/// The border is the region's vertices with a mesh neighbour outside the
/// region or on an edge of the mesh's own boundary. Ties: nearest to the
/// region's centroid, then the lowest index.

#include <icrkit/icr/graspable_object.hpp>

#include <vector>

namespace icrkit::icr {

struct RecommendedContact {
  int vertex = -1;       ///< -1 for an empty region
  double depth_m = 0.0;  ///< its distance along mesh edges to the nearest border vertex (0 on the border)
};

/// `region`: sorted vertex indices of `object`'s mesh.
RecommendedContact recommendedContact(const GraspableObject& object, const std::vector<int>& region);

}  // namespace icrkit::icr
