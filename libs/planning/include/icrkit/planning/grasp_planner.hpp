#pragma once
/// \file
/// Grasps a robot can execute on a mesh it reconstructed: sample candidate
/// prototype grasps on the trusted surface (contact_trust.hpp), grow their
/// Independent Contact Regions, score each by how surely it holds where a
/// robot puts its fingers (placement_score.hpp), keep the best k.
///
/// The work per finger count (docs/planning.md, "Speed"):
/// 1. `candidates` random contact sets are drawn from the trusted vertices
///    (deterministic per seed and index); each costs its wrenches, a
///    force-closure pre-check without hull, and the supports of its
///    wrenches along a fixed set of directions, whose minimum bounds epsilon
///    from above. Candidates that cannot meet the task are dropped there.
/// 2. The `hulls` candidates with the largest bound get a hull; those that
///    meet the task (epsilon >= the task radius times 1 + task_margin) get
///    regions, grown for the task radius times 1 + task_margin.
/// 3. Each is scored; ties go to the larger epsilon, then the lower index.
/// Every step runs in parallel over candidates, with results kept by index:
/// the plan is the same for any thread count.

#include <icrkit/core/progress.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/icr/patch_contacts.hpp>
#include <icrkit/planning/contact_trust.hpp>
#include <icrkit/planning/placement_score.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace icrkit::planning {

struct PlanningParameters {
  std::vector<std::size_t> finger_counts{4};
  std::size_t top = 10;             ///< grasps returned (over all finger counts)
  std::size_t candidates = 1000;    ///< random contact sets drawn per finger count
  /// Hulls built per finger count, for the candidates whose epsilon bound is
  /// largest; unset: max(20 top, 64), at most `candidates`.
  std::optional<std::size_t> hulls;
  std::uint64_t seed = 1;
  /// The task and the growth: contact model, TWS (alpha x each candidate's
  /// epsilon, or the absolute `tws_radius`), growth mode, conservative
  /// growth. A polytope TWS is not supported here.
  icr::IcrParameters regions;
  /// Regions are grown for the task radius times (1 + task_margin) and a
  /// candidate must reach that epsilon: the margin absorbs what the mesh
  /// gets wrong where the trust mask cannot see it. The plan still states
  /// the task asked (PlannedGrasp::tws_radius).
  double task_margin = 0.25;
  /// Candidates with a region smaller than this (m²) are dropped. Unset:
  /// regions without a whole triangle (area 0) are: a region of one or two
  /// vertices has nothing around it that confirms the mesh (on a
  /// misregistered bottle such a region sat on a ghost surface, its normal
  /// 60 deg off). A robot with a known fingertip may ask for its area.
  std::optional<double> min_region_area_m2;
  ContactTrustParameters trust;
  PlacementParameters placement;
  /// Multi-point (patch) contacts (icr/patch_contacts.hpp): the candidates
  /// are screened and ranked with point contacts as always (a patch hull
  /// costs up to seconds on a dense mesh), then the best 3 x `top` get
  /// their regions grown again for patch fingers, are scored again and the
  /// best `top` of those are returned. Not with conservative growth.
  std::optional<icr::PatchParameters> patch;

  /// InputError naming the field for a value out of range.
  void validate() const;
};

struct PlannedGrasp {
  std::size_t rank = 0;               ///< 1 = best
  std::size_t fingers = 0;
  std::size_t candidate = 0;          ///< index of the draw within its finger count
  std::vector<int> contacts;          ///< the prototype's vertices
  double epsilon = 0.0;
  double tws_radius = 0.0;            ///< the task asked, in the wrench units of the object's frame
  double growth_tws_radius = 0.0;     ///< the task the regions were grown for (with the margin)
  PlacementScore score;
  icr::IcrResult regions;
};

struct FingerCountReport {
  std::size_t fingers = 0;
  std::size_t drawn = 0;              ///< contact sets drawn
  std::size_t rejected_by_precheck = 0;  ///< not force closure, shown without a hull
  std::size_t rejected_by_bound = 0;     ///< their epsilon bound is below the task
  std::size_t hulls_built = 0;
  std::size_t not_force_closure = 0;  ///< hull built, not force closure
  std::size_t below_task = 0;         ///< force closure, epsilon below the task
  std::size_t small_regions = 0;      ///< met the task, a region below min_region_area_m2 (or empty)
  std::size_t with_regions = 0;       ///< regions grown and scored
};

struct PlanReport {
  ContactTrustReport trust;
  std::vector<FingerCountReport> finger_counts;
  double trust_ms = 0.0;      ///< trust mask and the placement scorer
  double screening_ms = 0.0;  ///< draws, pre-checks and bounds
  double regions_ms = 0.0;    ///< hulls, regions and scores
  double total_ms = 0.0;
};

struct PlanResult {
  std::vector<PlannedGrasp> grasps;  ///< best first
  PlanReport report;
  std::optional<icr::PatchParameters> patch;  ///< the contacts' patches, when the regions are a patch model's
};

/// `object`'s exclusion mask (preselection) is honoured; trust is assessed
/// on its mesh. Throws InputError on bad parameters, when no candidate is
/// force closure ("no force-closure grasp among N candidates ..."), or when
/// none meets the task. Progress: "candidates", done, total.
PlanResult planGrasps(const icr::GraspableObject& object, const PlanningParameters& params,
                      const ProgressCallback& progress = {});

}  // namespace icrkit::planning
