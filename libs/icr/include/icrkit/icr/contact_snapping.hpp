#pragma once
/// \file
/// A prototype grasp given as points in space (say, a planner's fingertip
/// positions) turned into contact vertices of a mesh.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <vector>

namespace icrkit::icr {

struct SnappedContacts {
  std::vector<int> vertices;        ///< one per point: its nearest vertex some face uses
  std::vector<double> distances_m;  ///< how far each point moved
};

/// Each point's nearest vertex among those some face uses (only they can
/// be contacts). InputError("mesh") when no
/// vertex is used by a face, InputError("contact points", "point N") for a
/// point that is not finite.
SnappedContacts snapToFaceVertices(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& points);

}  // namespace icrkit::icr
