#pragma once
/// \file
/// plan.json, what `icrkit plan` writes and a robot's executor reads (units
/// metres; docs/planning.md):
///
///     {"mesh": PATH, "model": {"type", "mu", "mu_t", "edges"},
///      "torque_reference_m": [x, y, z], "lambda_m": L,
///      "grasps": [{"rank", "fingers", "tws_radius", "score", "epsilon",
///                  "growth_tws_radius", "contacts": [ids],
///                  "regions": [{"finger", "vertices": [ids], "area_m2",
///                               "landing_probability",
///                               "recommended": {"vertex", "position",
///                                               "normal", "depth_m"}}]}]}
///
/// Vertex ids index the vertices of the mesh file at PATH as written;
/// `tws_radius` is in the wrench units of `icrkit icr`: force 1 per contact,
/// torques about `torque_reference_m` divided by `lambda_m`.

#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/contact_model.hpp>
#include <icrkit/planning/grasp_planner.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace icrkit::planning {

/// plan.json of `result` (compact JSON, keys sorted; the same plan always
/// gives the same bytes). `object` is the one planned on; `extra` is a JSON
/// object text whose members are added at the top level (empty: none).
std::string planJson(const std::string& mesh_path, const icr::GraspableObject& object, const icr::ContactModel& model,
                     const PlanResult& result, const std::string& extra = {});

struct StoredPlanRegion {
  std::size_t finger = 0;
  std::vector<int> vertices;
  double area_m2 = 0.0;
  int recommended = -1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

struct StoredPlanGrasp {
  std::size_t rank = 0;
  double tws_radius = 0.0;
  double score = 0.0;
  std::vector<StoredPlanRegion> regions;
};

struct StoredPlan {
  std::string mesh;
  icr::ContactModel model;
  icr::WrenchFrame frame;
  std::vector<StoredPlanGrasp> grasps;
};

/// Parses plan.json text. Errors (InputError) name `source` and the element
/// (`grasps[2].regions[1].vertices[5]`) and what was expected; with
/// `vertex_count` > 0 every vertex id must be below it.
StoredPlan parsePlanJson(const std::string& text, const std::string& source, std::size_t vertex_count = 0);
/// Reads and parses the file at `path`.
StoredPlan readPlanFile(const std::string& path, std::size_t vertex_count = 0);

}  // namespace icrkit::planning
