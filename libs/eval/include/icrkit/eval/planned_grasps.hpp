#pragma once
/// \file
/// The planned grasps of one dataset executed on its CAD mesh, beside the
/// paper's random ones: `icrkit plan` (planning/grasp_planner.hpp) is run on
/// the raw and on the filtered mesh, as a robot without CAD would run it,
/// and each of its top-k grasps is executed on the CAD mesh the way a robot
/// would execute it:
///
/// - aimed: every finger at its region's recommended contact;
/// - picks: one random vertex of every region;
/// - placement: every finger aimed at its recommended contact and missing
///   by a 2-D Gaussian error in the contact's tangent plane.
///
/// A finger's landing point on the reconstruction (with the reconstruction's
/// normal there) goes onto the CAD mesh by eq. (3) (ScanToCadMapping: the
/// CAD vertex near the nearest CAD surface point, among those facing the
/// finger's side); the grasp holds when the CAD grasp of those vertices is
/// force closure and holds the task (epsilon >= the plan's TWS radius).
///
/// The task is absolute and the same on every grasp of a dataset: half the
/// median epsilon of the random CAD grasps with the plan's finger count
/// (the acceptance figure of the planner, docs/planning.md). All meshes use
/// the CAD mesh's wrench frame, so that radius means the same on each.

#include <icrkit/eval/normal_line_mappings.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/planning/grasp_planner.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace icrkit::eval {

struct PlannedExecutionParameters {
  std::size_t picks_per_grasp = 100;   ///< random picks per planned grasp
  std::size_t placement_samples = 100; ///< placement-error trials per planned grasp
  double placement_error_m = 0.003;    ///< sigma per tangent axis (metres)
  std::uint64_t seed = 1;

  /// InputError naming the field for a value out of range.
  void validate() const;
};

/// One planned grasp executed on the CAD mesh.
struct PlannedGraspExecution {
  std::size_t rank = 0;
  double score = 0.0;                  ///< the planner's score
  double epsilon = 0.0;                ///< of the prototype on the reconstruction
  std::vector<double> region_areas_m2;
  bool aimed_held = false;
  double aimed_epsilon = 0.0;          ///< of the aimed grasp on the CAD mesh (0: not force closure or unmapped)
  std::size_t picks = 0, picks_held = 0;
  std::size_t placements = 0, placements_held = 0;
  std::size_t unmapped = 0;            ///< trials with a finger that mapped nowhere or onto another's vertex (failures)
};

/// The plan on one reconstructed mesh and its execution.
struct PlannedMeshStudy {
  std::string mesh;                    ///< "raw" or "filtered"
  std::string error;                   ///< the planner's error when it found no grasp (grasps empty)
  double plan_ms = 0.0;
  std::vector<PlannedGraspExecution> grasps;

  double aimedHeldFraction() const;    ///< over grasps; 0 without grasps
  double picksHeldFraction() const;    ///< over all picks
  double placementsHeldFraction() const;
  double medianRegionAreaM2() const;   ///< over every region of every grasp
};

struct PlannedGraspStudy {
  std::string dataset;
  std::size_t fingers = 0;
  double tws_radius = 0.0;             ///< half the median CAD epsilon
  std::size_t cad_grasps = 0;          ///< random CAD grasps that median is over
  PlannedMeshStudy raw, filtered;
  /// The baseline beside: random force-closure grasps on each mesh that meet
  /// the same task, with plain regions, no trust mask and no margin (what a
  /// user gets from `icrkit grasps` and `icrkit icr` alone), executed alike.
  PlannedMeshStudy raw_random, filtered_random;
};

/// The planner's parameters of the baseline: `planned` without the trust
/// mask and the margin, every candidate kept; keepFirstDrawn then drops the
/// ranking (the first `count` draws that meet the task).
planning::PlanningParameters randomBaselineParameters(const planning::PlanningParameters& planned, std::size_t count);
void keepFirstDrawn(planning::PlanResult& plan, std::size_t count);

/// Executes `plan` (made on `scan`) on `cad`: `to_cad` maps the
/// reconstruction onto the CAD mesh. Deterministic for a seed.
PlannedMeshStudy executePlanOnCad(const planning::PlanResult& plan, const icr::GraspableObject& scan,
                                  const ScanToCadMapping& to_cad, const icr::GraspableObject& cad,
                                  const icr::ContactModel& model, const PlannedExecutionParameters& params);

/// One line of planned.jsonl (compact JSON, sorted keys).
std::string plannedGraspStudyJson(const PlannedGraspStudy& study);

/// A Markdown table, one row per dataset and mesh (planned.md).
std::string plannedGraspStudiesMarkdown(const std::vector<std::string>& jsonl_lines);

}  // namespace icrkit::eval
