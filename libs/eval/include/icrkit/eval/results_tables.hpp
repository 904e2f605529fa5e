#pragma once
/// \file
/// Table I (median intersection and false-positive areas per dataset) and the
/// eligibility rates of Section V, computed from grasp records, the paper's
/// published values for comparison, and their JSON forms (table1.json,
/// eligibility.json).

#include <icrkit/eval/experiment_records.hpp>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

/// Medians over all regions of evaluated grasps on one mesh type.
struct MeshMedians {
  std::optional<double> intersection_percent;    ///< median of 100 A(I_n) / A(C_n^C); unset without regions
  std::optional<double> false_positive_percent;  ///< median of 100 FP / A(C_n^C); unset without regions
  std::size_t regions = 0;             ///< all regions of the evaluated grasps on this mesh type
  /// Regions without a percent (A(C_n^C) = 0): counted here, left out of the medians.
  std::size_t degenerate_regions = 0;
};

/// One line of Table I. In the Average row the medians are the means of the
/// per-dataset medians (as in the paper: 59 = mean of 56, 54, ..., 73) and the
/// counts are totals.
struct TableOneRow {
  std::string dataset;
  std::size_t evaluated_grasps = 0;
  MeshMedians filtered;  ///< the paper's "smooth mesh"
  MeshMedians raw;
};

struct TableOneOptions {
  /// Rows in this order first (listed datasets without records give empty
  /// rows); datasets of the records that are not listed follow in sorted
  /// order. Empty: every dataset of the records, sorted.
  std::vector<std::string> dataset_order;
  /// Only grasps with this many fingers; 0 (default): 4 and 5 together, as in the paper.
  std::size_t fingers = 0;
  /// Eligibility is also reported for the grasps farther than this (m)
  /// from the rim of the seen surface (GraspRecord::seen_rim_distance_m):
  /// the rim of what the views saw, where a smoothing window is half empty
  /// and the preselection's isolation test fires. 3 mm: about the smoothing
  /// radius of the datasets (3.2 mm on the real recording).
  double seen_rim_distance_m = 3e-3;
};

struct TableOne {
  std::size_t fingers = 0;  ///< as in TableOneOptions
  std::vector<TableOneRow> rows;
  TableOneRow average;      ///< dataset "Average"; means over the rows whose median is set
};

/// Median of `values` (mean of the two middle ones for an even count); unset when empty.
std::optional<double> median(std::vector<double> values);

TableOne computeTableOne(const std::vector<GraspRecord>& records, const TableOneOptions& options = {});

/// Counts of one group of grasps (a dataset and/or finger count).
struct EligibilityCounts {
  std::size_t grasps = 0;
  std::size_t raw_eligible = 0;                   ///< raw.eligible()
  std::size_t filtered_eligible = 0;              ///< filtered.eligible()
  std::size_t filtered_preselection_failed = 0;   ///< !filtered.preselection_passed
  std::size_t both_eligible = 0;                  ///< raw and filtered eligible
  std::size_t evaluated = 0;                      ///< record.evaluated (normally equal to both_eligible)
  /// filtered.eligibleAfterSnapping(): after snapping to the nearest kept
  /// vertex (not the paper's check); >= filtered_eligible.
  std::size_t filtered_eligible_after_snapping = 0;
  /// Failed the preselection with no snapped grasp recorded (older records,
  /// or snapping switched off): filtered_eligible_after_snapping is then a
  /// lower bound.
  std::size_t filtered_snapping_not_recorded = 0;
  /// Eligibility on surface the views saw (not the paper's figure, beside
  /// it): grasps farther than TableOneOptions::seen_rim_distance_m from the
  /// rim of the seen surface, and of those the eligible ones. A grasp on or
  /// near surface no view saw (an object's base) is mapped by eq. (2) onto
  /// that rim on both meshes; it judges neither reconstruction.
  std::size_t off_rim_grasps = 0;
  std::size_t raw_eligible_off_rim = 0;
  std::size_t filtered_eligible_off_rim = 0;
  /// Records without the rim distance (written before it existed): in none
  /// of the three counts above.
  std::size_t rim_not_recorded = 0;

  /// 100 count / grasps; unset without grasps.
  std::optional<double> percent(std::size_t count) const;
  /// 100 count / off_rim_grasps; unset without such grasps.
  std::optional<double> offRimPercent(std::size_t count) const;
};

struct EligibilityGroup {
  std::string dataset;                                 ///< "all" for the overall group
  std::map<std::size_t, EligibilityCounts> by_fingers; ///< per finger count present in the records
  EligibilityCounts all;                               ///< every finger count together
};

struct EligibilitySummary {
  std::vector<EligibilityGroup> datasets;  ///< in the order of TableOneOptions::dataset_order
  EligibilityGroup overall;
  double seen_rim_distance_m = 0.0;        ///< TableOneOptions::seen_rim_distance_m used for the off-rim counts
};

/// Per dataset and overall; `options.fingers` is ignored (every finger count is reported).
EligibilitySummary computeEligibility(const std::vector<GraspRecord>& records, const TableOneOptions& options = {});

/// One row of the paper's Table I, as printed.
struct PaperTableOneRow {
  std::string dataset;  ///< our dataset name, e.g. "cup_sr4000_A"; "Average" for the Average row
  std::string sensor;   ///< "SR4000" or "Kinect"; empty for the Average row
  std::string object;   ///< as the paper names it, e.g. "Wooden Toy 1"
  double filtered_intersection_percent = 0.0;
  double filtered_false_positive_percent = 0.0;
  double raw_intersection_percent = 0.0;
  double raw_false_positive_percent = 0.0;
};

struct PaperTableOne {
  std::vector<PaperTableOneRow> rows;  ///< in the paper's order
  PaperTableOneRow average;            ///< as printed: 59, 9.0, 12, 0.0
  double filtered_eligible_percent = 98.3;  ///< Section V
  double raw_eligible_percent = 88.0;       ///< Section V
};

/// Krug et al., Table I and Section V.
PaperTableOne paperTableOne();
/// The paper's row for one of our dataset names (or "Average"), if it has one.
std::optional<PaperTableOneRow> paperTableOneRow(const std::string& dataset);

/// Data forms (deterministic; the Markdown and CSV tables are
/// icrkit/report/table_one_text.hpp).
/// JSON: {"fingers", "rows": [...], "average": {...}}; unset is null.
std::string tableOneJson(const TableOne& table);
/// JSON: {"datasets": [...], "overall": {...}, "paper": {...}, "notes": {...}};
/// unset is null. "notes" says what the after-snapping counts mean.
std::string eligibilityJson(const EligibilitySummary& summary);

/// Atomic writers of the JSON forms above.
void writeTableOneJson(const std::string& path, const TableOne& table);
void writeEligibilityJson(const std::string& path, const EligibilitySummary& summary);

}  // namespace icrkit::eval
