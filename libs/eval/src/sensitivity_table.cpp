// The sensitivity study's table, computed from grasp records, and its JSON form.

#include <icrkit/eval/results_tables.hpp>

#include <icrkit/eval/sensitivity_study.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdio>

namespace icrkit::eval {

SensitivityTable computeSensitivityTable(const std::vector<GraspRecord>& records, const std::string& object,
                                         double spacing_m, const std::vector<double>& noise_levels,
                                         const std::vector<std::string>& rules) {
  SensitivityTable table{object, spacing_m, noise_levels, rules, {}};
  for (const double level : noise_levels)
    for (const std::string& rule : rules) {
      const std::string name = sensitivityDatasetName(object, level, rule);
      std::vector<GraspRecord> mine;
      for (const GraspRecord& r : records)
        if (r.dataset == name) mine.push_back(r);
      SensitivityRow row;
      row.noise_level = level;
      row.rule = rule;
      row.grasps = mine.size();
      if (!mine.empty()) {
        const EligibilitySummary e = computeEligibility(mine);
        row.raw_eligible_percent = e.overall.all.percent(e.overall.all.raw_eligible);
        row.filtered_eligible_percent = e.overall.all.percent(e.overall.all.filtered_eligible);
        row.filtered_eligible_after_snapping_percent =
            e.overall.all.percent(e.overall.all.filtered_eligible_after_snapping);
        const EligibilityCounts& all = e.overall.all;
        row.off_rim_grasps_percent = all.percent(all.off_rim_grasps);
        row.raw_eligible_off_rim_percent = all.offRimPercent(all.raw_eligible_off_rim);
        row.filtered_eligible_off_rim_percent = all.offRimPercent(all.filtered_eligible_off_rim);
        const TableOne t = computeTableOne(mine);
        const TableOneRow& one = t.rows.front();
        row.evaluated = one.evaluated_grasps;
        row.raw_intersection_percent = one.raw.intersection_percent;
        row.raw_false_positive_percent = one.raw.false_positive_percent;
        row.filtered_intersection_percent = one.filtered.intersection_percent;
        row.filtered_false_positive_percent = one.filtered.false_positive_percent;
      }
      table.rows.push_back(row);
    }
  return table;
}

namespace {

nlohmann::json optional(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

}  // namespace

std::string sensitivityJson(const SensitivityTable& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (const SensitivityRow& r : t.rows)
    rows.push_back({{"noise_level", r.noise_level},
                    {"sigma_m", r.noise_level * t.spacing_m},
                    {"rule", r.rule},
                    {"grasps", r.grasps},
                    {"evaluated", r.evaluated},
                    {"raw_eligible_percent", optional(r.raw_eligible_percent)},
                    {"filtered_eligible_percent", optional(r.filtered_eligible_percent)},
                    {"raw_intersection_percent", optional(r.raw_intersection_percent)},
                    {"raw_false_positive_percent", optional(r.raw_false_positive_percent)},
                    {"filtered_intersection_percent", optional(r.filtered_intersection_percent)},
                    {"filtered_false_positive_percent", optional(r.filtered_false_positive_percent)},
                    {"filtered_eligible_after_snapping_percent",
                     optional(r.filtered_eligible_after_snapping_percent)},
                    {"off_rim_grasps_percent", optional(r.off_rim_grasps_percent)},
                    {"raw_eligible_off_rim_percent", optional(r.raw_eligible_off_rim_percent)},
                    {"filtered_eligible_off_rim_percent", optional(r.filtered_eligible_off_rim_percent)}});
  return nlohmann::json{{"object", t.object},
                        {"spacing_m", t.spacing_m},
                        {"noise_levels", t.noise_levels},
                        {"rules", t.rules},
                        {"rows", rows}}
      .dump(1);
}

}  // namespace icrkit::eval
