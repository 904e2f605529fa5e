#pragma once
/// \file
/// Moving a transferred grasp off the vertices the preselection excluded:
/// each contact on an excluded vertex goes to the nearest kept vertex (used
/// by a face and not excluded) within a radius; contacts on kept vertices
/// stay. This is what a planner executing G^F on the filtered mesh would do.
/// The paper's check is stricter (a contact on an excluded vertex makes G^F
/// ineligible); the experiment reports the snapped grasp beside it, never in
/// its place (docs/evaluation.md, "Snapping to the nearest kept vertex").

#include <icrkit/core/kd_tree.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace icrkit::eval {

struct SnappedContacts {
  /// One per input contact; empty when some contact found no kept vertex.
  std::vector<int> contacts;
  /// How far each contact moved (metres; 0 for a contact that stayed);
  /// empty when `contacts` is.
  std::vector<double> move_distances_m;
  /// Why the snapped grasp is not a grasp; empty when it is.
  std::string reason;
};

class KeptVertexSnapping {
public:
  /// Keeps a reference to `object` (it must outlive this). Throws InputError
  /// unless `radius_m` is finite and > 0.
  KeptVertexSnapping(const icr::GraspableObject& object, double radius_m);
  KeptVertexSnapping(const KeptVertexSnapping&) = delete;
  KeptVertexSnapping& operator=(const KeptVertexSnapping&) = delete;

  /// Snaps every contact that is not on a kept vertex. Fails (with a reason
  /// naming the contact) when no kept vertex lies within the radius of it,
  /// or when two contacts end on one vertex. The nearest is by Euclidean
  /// distance, ties to the lower vertex index, so the answer is a
  /// deterministic function of the mesh, its mask and the radius.
  SnappedContacts snap(const std::vector<int>& contacts) const;

  double radius() const { return radius_; }

private:
  const icr::GraspableObject* object_;
  double radius_;
  // Kept vertices in ascending index order, so that the kd-tree's tie-break
  // on its own (lower) index is the tie-break on the mesh's vertex index.
  std::vector<int> kept_vertices_;
  std::vector<Eigen::Vector3d> kept_positions_;
  KdTree kept_tree_;  // over kept_positions_, declared after it
};

}  // namespace icrkit::eval
