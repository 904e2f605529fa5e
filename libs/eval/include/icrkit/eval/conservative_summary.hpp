#pragma once
/// \file
/// Plain against uncertainty-aware growth (ExperimentConfig::conservative_sigmas),
/// from grasp records: per growth setting and mesh type, the median Int and
/// FP (as Table I), how many regions ended empty, how many recommended
/// contacts lie inside the CAD region, how many central points lie
/// outside it (Q_n < 0), how many random picks from the regions hold
/// the task on the CAD mesh (MeshOutcome::picks), and how many grasps of
/// the recommended contacts do. Records of the patch-contact study
/// (GraspRecord::patch) add a row per patch radius, measured against the CAD
/// patch regions and with the aimed grasp only (no random picks). Its JSON
/// form is here; the Markdown table and the Int-vs-FP curve are
/// icrkit/report/conservative_plot.hpp.

#include <icrkit/eval/experiment_records.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

struct GrowthFigures {
  std::optional<double> intersection_percent;    ///< median over the regions; unset without regions
  std::optional<double> false_positive_percent;  ///< median over the regions
  std::size_t regions = 0;
  std::size_t empty_regions = 0;       ///< no vertex kept the guarantee
  std::size_t recommended_known = 0;   ///< regions whose record says where the recommended contact landed
  std::size_t recommended_inside = 0;  ///< ... inside C_n^C
  std::size_t center_outside = 0;      ///< central point mapped outside C_n^C (d2 < 0)
  std::size_t grasps_with_picks = 0;   ///< grasps whose regions were all non-empty (picks drawn)
  std::size_t picks_mapped = 0;        ///< picks that mapped onto distinct CAD vertices
  std::size_t picks_held = 0;          ///< ... and hold the TWS on the CAD mesh
  std::size_t aimed_known = 0;         ///< grasps whose record says whether their aimed grasp held (PickCheck::aimed_held)
  std::size_t aimed_held = 0;          ///< ... and it held
  std::optional<double> picksHeldPercent() const;
  std::optional<double> aimedHeldPercent() const;
  std::optional<double> recommendedInsidePercent() const;
  std::optional<double> centerOutsidePercent() const;
};

struct GrowthRow {
  std::string dataset;            ///< "All" for the pooled row
  std::optional<double> sigmas;   ///< unset: plain growth (or patch contacts)
  std::optional<double> patch_radius_m;  ///< set: the patch-contact study with this radius
  /// Patch rows: grasps the study ran on (those the plain experiment
  /// evaluated); `evaluated_grasps` of them had both mapped patch grasps
  /// hold the patch task. 0 on other rows.
  std::size_t studied_grasps = 0;
  std::size_t raw_task_met = 0;       ///< patch rows: studied grasps whose raw patch grasp held the task
  std::size_t filtered_task_met = 0;  ///< ... whose filtered patch grasp did
  std::size_t evaluated_grasps = 0;
  GrowthFigures filtered, raw;
};

struct ConservativeSummary {
  std::vector<double> sigmas;  ///< the K values found in the records, ascending
  std::vector<double> patch_radii_m;  ///< the patch radii found in the records, ascending
  /// Per dataset (sorted) and then "All": plain first, then each K, then each patch radius.
  std::vector<GrowthRow> rows;
};

ConservativeSummary computeConservativeSummary(const std::vector<GraspRecord>& records);

std::string conservativeSummaryJson(const ConservativeSummary& summary);

}  // namespace icrkit::eval
