#include <icrkit/eval/results_tables.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace icrkit::eval {
namespace {

using Json = nlohmann::ordered_json;

const char* const kAfterSnappingNote =
    "after snapping to the nearest kept vertex (not the paper's check): filtered grasps that are eligible, or whose "
    "contacts on excluded vertices, each moved to the nearest kept vertex within the mapping's neighbourhood "
    "radius, meet the task; Table I and Fig. 8 never use it";
const char* const kSnappingNotRecordedNote =
    "filtered grasps that failed the preselection and carry no snapped grasp (records written before snapping "
    "existed, or with it switched off); filtered_eligible_after_snapping is a lower bound when this is not 0";

const char* const kOffRimNote =
    "eligibility on surface the views saw (not the paper's figure): only grasps whose contacts, mapped onto the "
    "raw and filtered meshes, all lie farther than seen_rim_distance_m from the filtered mesh's boundary (the rim "
    "of the seen surface); *_off_rim_percent are of off_rim_grasps. rim_not_recorded: records written before the "
    "rim distance existed, counted in none of these";

Json optionalJson(const std::optional<double>& value) {
  return value && std::isfinite(*value) ? Json(*value) : Json(nullptr);
}

bool fingersMatch(const GraspRecord& record, std::size_t fingers) { return fingers == 0 || record.fingers == fingers; }

/// Row order: listed datasets first, then the rest of the records' datasets sorted.
std::vector<std::string> datasetOrder(const std::vector<GraspRecord>& records, const std::vector<std::string>& listed) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const auto& name : listed)
    if (seen.insert(name).second) order.push_back(name);
  std::set<std::string> rest;
  for (const auto& record : records)
    if (!seen.count(record.dataset)) rest.insert(record.dataset);
  order.insert(order.end(), rest.begin(), rest.end());
  return order;
}

/// Collects the per-region percents of one mesh type before taking medians.
struct RegionPercents {
  std::vector<double> intersection;
  std::vector<double> false_positive;
  std::size_t regions = 0;
  std::size_t degenerate = 0;

  void add(const MeshOutcome& mesh) {
    for (const auto& region : mesh.regions) {
      ++regions;
      if (!region.intersection_percent || !region.false_positive_percent) ++degenerate;
      if (region.intersection_percent) intersection.push_back(*region.intersection_percent);
      if (region.false_positive_percent) false_positive.push_back(*region.false_positive_percent);
    }
  }

  MeshMedians medians() const {
    MeshMedians result;
    result.intersection_percent = median(intersection);
    result.false_positive_percent = median(false_positive);
    result.regions = regions;
    result.degenerate_regions = degenerate;
    return result;
  }
};

/// Mean of the set values among `values`, in order; unset when none is set.
std::optional<double> meanOfSet(const std::vector<std::optional<double>>& values) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto& value : values)
    if (value) {
      sum += *value;
      ++count;
    }
  if (count == 0) return std::nullopt;
  return sum / double(count);
}

MeshMedians averageOf(const std::vector<TableOneRow>& rows, MeshMedians TableOneRow::*mesh) {
  std::vector<std::optional<double>> intersection, falsePositive;
  MeshMedians result;
  for (const auto& row : rows) {
    intersection.push_back((row.*mesh).intersection_percent);
    falsePositive.push_back((row.*mesh).false_positive_percent);
    result.regions += (row.*mesh).regions;
    result.degenerate_regions += (row.*mesh).degenerate_regions;
  }
  result.intersection_percent = meanOfSet(intersection);
  result.false_positive_percent = meanOfSet(falsePositive);
  return result;
}

PaperTableOneRow paperRow(const char* dataset, const char* sensor, const char* object, double fi, double ffp, double ri,
                          double rfp) {
  return PaperTableOneRow{dataset, sensor, object, fi, ffp, ri, rfp};
}

void addCounts(EligibilityCounts& counts, const GraspRecord& record, double seen_rim_distance) {
  ++counts.grasps;
  if (record.raw.eligible()) ++counts.raw_eligible;
  if (record.filtered.eligible()) ++counts.filtered_eligible;
  if (!record.filtered.preselection_passed) ++counts.filtered_preselection_failed;
  if (record.raw.eligible() && record.filtered.eligible()) ++counts.both_eligible;
  if (record.evaluated) ++counts.evaluated;
  if (record.filtered.eligibleAfterSnapping()) ++counts.filtered_eligible_after_snapping;
  if (!record.filtered.preselection_passed && !record.filtered.snapped) ++counts.filtered_snapping_not_recorded;
  if (!record.seen_rim_distance_m) {
    ++counts.rim_not_recorded;
  } else if (*record.seen_rim_distance_m > seen_rim_distance) {
    ++counts.off_rim_grasps;
    if (record.raw.eligible()) ++counts.raw_eligible_off_rim;
    if (record.filtered.eligible()) ++counts.filtered_eligible_off_rim;
  }
}

void addToGroup(EligibilityGroup& group, const GraspRecord& record, double seen_rim_distance) {
  addCounts(group.by_fingers[record.fingers], record, seen_rim_distance);
  addCounts(group.all, record, seen_rim_distance);
}

Json countsJson(const EligibilityCounts& counts) {
  Json j;
  j["grasps"] = counts.grasps;
  j["raw_eligible"] = counts.raw_eligible;
  j["raw_eligible_percent"] = optionalJson(counts.percent(counts.raw_eligible));
  j["filtered_eligible"] = counts.filtered_eligible;
  j["filtered_eligible_percent"] = optionalJson(counts.percent(counts.filtered_eligible));
  j["filtered_preselection_failed"] = counts.filtered_preselection_failed;
  j["filtered_preselection_failed_percent"] = optionalJson(counts.percent(counts.filtered_preselection_failed));
  j["both_eligible"] = counts.both_eligible;
  j["both_eligible_percent"] = optionalJson(counts.percent(counts.both_eligible));
  j["evaluated"] = counts.evaluated;
  // Added after the keys above, which keep their meaning: the paper's check.
  j["filtered_eligible_after_snapping"] = counts.filtered_eligible_after_snapping;
  j["filtered_eligible_after_snapping_percent"] = optionalJson(counts.percent(counts.filtered_eligible_after_snapping));
  j["filtered_snapping_not_recorded"] = counts.filtered_snapping_not_recorded;
  j["off_rim_grasps"] = counts.off_rim_grasps;
  j["off_rim_grasps_percent"] = optionalJson(counts.percent(counts.off_rim_grasps));
  j["raw_eligible_off_rim"] = counts.raw_eligible_off_rim;
  j["raw_eligible_off_rim_percent"] = optionalJson(counts.offRimPercent(counts.raw_eligible_off_rim));
  j["filtered_eligible_off_rim"] = counts.filtered_eligible_off_rim;
  j["filtered_eligible_off_rim_percent"] = optionalJson(counts.offRimPercent(counts.filtered_eligible_off_rim));
  j["rim_not_recorded"] = counts.rim_not_recorded;
  return j;
}

Json groupJson(const EligibilityGroup& group) {
  Json j;
  j["dataset"] = group.dataset;
  j["all"] = countsJson(group.all);
  Json byFingers = Json::array();
  for (const auto& [fingers, counts] : group.by_fingers) {
    Json entry;
    entry["fingers"] = fingers;
    const Json countsPart = countsJson(counts);
    for (const auto& item : countsPart.items()) entry[item.key()] = item.value();
    byFingers.push_back(std::move(entry));
  }
  j["by_fingers"] = std::move(byFingers);
  return j;
}

Json meshMediansJson(const MeshMedians& mesh) {
  Json j;
  j["median_intersection_percent"] = optionalJson(mesh.intersection_percent);
  j["median_false_positive_percent"] = optionalJson(mesh.false_positive_percent);
  j["regions"] = mesh.regions;
  j["degenerate_regions"] = mesh.degenerate_regions;
  return j;
}

Json paperRowJson(const std::optional<PaperTableOneRow>& paper) {
  if (!paper) return nullptr;
  Json j;
  j["filtered"] = {{"median_intersection_percent", paper->filtered_intersection_percent},
                   {"median_false_positive_percent", paper->filtered_false_positive_percent}};
  j["raw"] = {{"median_intersection_percent", paper->raw_intersection_percent},
              {"median_false_positive_percent", paper->raw_false_positive_percent}};
  return j;
}

Json tableRowJson(const TableOneRow& row) {
  Json j;
  j["dataset"] = row.dataset;
  j["evaluated_grasps"] = row.evaluated_grasps;
  j["filtered"] = meshMediansJson(row.filtered);
  j["raw"] = meshMediansJson(row.raw);
  j["paper"] = paperRowJson(paperTableOneRow(row.dataset));
  return j;
}

}  // namespace

std::optional<double> median(std::vector<double> values) {
  // NaN would break the ordering; it has no place in a median of percents.
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }), values.end());
  if (values.empty()) return std::nullopt;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  if (n % 2 == 1) return values[n / 2];
  return 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

TableOne computeTableOne(const std::vector<GraspRecord>& records, const TableOneOptions& options) {
  TableOne table;
  table.fingers = options.fingers;
  for (const auto& dataset : datasetOrder(records, options.dataset_order)) {
    TableOneRow row;
    row.dataset = dataset;
    RegionPercents filtered, raw;
    for (const auto& record : records) {
      if (record.dataset != dataset || !record.evaluated || !fingersMatch(record, options.fingers)) continue;
      ++row.evaluated_grasps;
      filtered.add(record.filtered);
      raw.add(record.raw);
    }
    row.filtered = filtered.medians();
    row.raw = raw.medians();
    table.rows.push_back(std::move(row));
  }
  table.average.dataset = "Average";
  for (const auto& row : table.rows) table.average.evaluated_grasps += row.evaluated_grasps;
  table.average.filtered = averageOf(table.rows, &TableOneRow::filtered);
  table.average.raw = averageOf(table.rows, &TableOneRow::raw);
  return table;
}

std::optional<double> EligibilityCounts::percent(std::size_t count) const {
  if (grasps == 0) return std::nullopt;
  return 100.0 * double(count) / double(grasps);
}

std::optional<double> EligibilityCounts::offRimPercent(std::size_t count) const {
  if (off_rim_grasps == 0) return std::nullopt;
  return 100.0 * double(count) / double(off_rim_grasps);
}

EligibilitySummary computeEligibility(const std::vector<GraspRecord>& records, const TableOneOptions& options) {
  if (!(options.seen_rim_distance_m >= 0.0) || !std::isfinite(options.seen_rim_distance_m))
    throw InputError("seen_rim_distance_m", "", "expected a finite distance >= 0 (metres)");
  EligibilitySummary summary;
  summary.overall.dataset = "all";
  summary.seen_rim_distance_m = options.seen_rim_distance_m;
  for (const auto& dataset : datasetOrder(records, options.dataset_order)) {
    EligibilityGroup group;
    group.dataset = dataset;
    for (const auto& record : records)
      if (record.dataset == dataset) addToGroup(group, record, options.seen_rim_distance_m);
    summary.datasets.push_back(std::move(group));
  }
  for (const auto& record : records) addToGroup(summary.overall, record, options.seen_rim_distance_m);
  return summary;
}

PaperTableOne paperTableOne() {
  PaperTableOne paper;
  paper.rows = {
      paperRow("cup_sr4000_A", "SR4000", "Cup", 56, 2.0, 14, 0.0),
      paperRow("wooden_toy_1_sr4000_A", "SR4000", "Wooden Toy 1", 54, 20, 14, 0.0),
      paperRow("wooden_toy_2_sr4000_A", "SR4000", "Wooden Toy 2", 49, 1.0, 4.0, 0.0),
      paperRow("cup_kinect_B", "Kinect", "Cup", 62, 10, 17, 0.0),
      paperRow("wooden_toy_1_kinect_B", "Kinect", "Wooden Toy 1", 70, 21, 17, 0.0),
      paperRow("wooden_toy_2_kinect_B", "Kinect", "Wooden Toy 2", 50, 1.0, 12, 0.0),
      paperRow("bottle_kinect_B", "Kinect", "Bottle", 59, 6.0, 14, 0.0),
      paperRow("paper_cup_kinect_B", "Kinect", "Paper Cup", 58, 11, 18, 0.0),
      paperRow("coffee_pot_kinect_B", "Kinect", "Coffee pot", 73, 9.0, 2.0, 0.0),
  };
  // As printed; the exact mean of the raw Int column is 12.4.
  paper.average = paperRow("Average", "", "Average", 59, 9.0, 12, 0.0);
  paper.filtered_eligible_percent = 98.3;
  paper.raw_eligible_percent = 88.0;
  return paper;
}

std::optional<PaperTableOneRow> paperTableOneRow(const std::string& dataset) {
  const PaperTableOne paper = paperTableOne();
  if (dataset == paper.average.dataset) return paper.average;
  for (const auto& row : paper.rows)
    if (row.dataset == dataset) return row;
  return std::nullopt;
}

std::string tableOneJson(const TableOne& table) {
  Json j;
  j["fingers"] = table.fingers == 0 ? Json(nullptr) : Json(table.fingers);
  Json rows = Json::array();
  for (const auto& row : table.rows) rows.push_back(tableRowJson(row));
  j["rows"] = std::move(rows);
  j["average"] = tableRowJson(table.average);
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string eligibilityJson(const EligibilitySummary& summary) {
  const PaperTableOne paper = paperTableOne();
  Json j;
  Json datasets = Json::array();
  for (const auto& group : summary.datasets) datasets.push_back(groupJson(group));
  j["datasets"] = std::move(datasets);
  j["overall"] = groupJson(summary.overall);
  j["paper"] = {{"filtered_eligible_percent", paper.filtered_eligible_percent},
                {"raw_eligible_percent", paper.raw_eligible_percent}};
  j["seen_rim_distance_m"] = summary.seen_rim_distance_m;
  j["notes"] = {{"filtered_eligible_after_snapping", kAfterSnappingNote},
                {"filtered_snapping_not_recorded", kSnappingNotRecordedNote},
                {"off_rim", kOffRimNote}};
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

void writeTableOneJson(const std::string& path, const TableOne& table) {
  writeFileAtomically(path, tableOneJson(table));
}
void writeEligibilityJson(const std::string& path, const EligibilitySummary& summary) {
  writeFileAtomically(path, eligibilityJson(summary));
}

}  // namespace icrkit::eval
