#pragma once
/// \file
/// Moving a grasp between two meshes of one object (e.g. CAD and
/// reconstructed) with the normal-line mapping of the paper's eq. (2):
/// P(p, n) = argmin over target vertices q of || n x (p - q) ||, restricted
/// to the target vertices near p so that the far side of the object, which
/// the same line also crosses, is never chosen. On a target with faces only
/// the vertices some face uses compete (points left unmeshed are not on the
/// surface); a target without faces is a point set and all its points do.

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace icrkit::icr {

struct NormalLineMappingParameters {
  /// Candidates are the target vertices within this distance of p (metres,
  /// finite and > 0); unset: ten times the median spacing of the competing
  /// target vertices.
  std::optional<double> search_radius;
};

class NormalLineMapping {
public:
  /// Keeps references to `target` (it must outlive the mapping).
  explicit NormalLineMapping(const TriangleMesh& target, const NormalLineMappingParameters& params = {});

  /// The target vertex closest to the line through p along n, among the
  /// candidates near p; -1 when no target vertex is within the search radius.
  int map(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;

  double searchRadius() const { return radius_; }

private:
  const TriangleMesh* target_;
  std::vector<int> index_;               ///< the competing target vertices, ascending
  std::vector<Eigen::Vector3d> points_;  ///< their positions
  KdTree tree_;
  double radius_;
};

/// Maps each contact vertex of `source` (with its vertex normal) onto `target`.
/// Throws InputError when a contact is out of range, is used by no face of a
/// source that has faces, or has no target vertex within the radius.
std::vector<int> transferGrasp(const TriangleMesh& source, const std::vector<int>& contacts, const TriangleMesh& target,
                               const NormalLineMappingParameters& params = {});

}  // namespace icrkit::icr
