#include <icrkit/eval/conservative_summary.hpp>

#include <icrkit/eval/results_tables.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace icrkit::eval {
namespace {

// Collects one growth setting's regions of one mesh type.
struct Accumulator {
  std::vector<double> intersection, false_positive;
  GrowthFigures figures;

  void add(const RegionComparison& r) {
    ++figures.regions;
    if (r.vertices == 0) ++figures.empty_regions;
    if (r.intersection_percent) intersection.push_back(*r.intersection_percent);
    if (r.false_positive_percent) false_positive.push_back(*r.false_positive_percent);
    if (r.recommended_inside) {
      ++figures.recommended_known;
      if (*r.recommended_inside) ++figures.recommended_inside;
    }
    if (r.vertices > 0 && r.d2_m < 0) ++figures.center_outside;
  }
  void add(const std::optional<PickCheck>& picks) {
    if (!picks || picks->tried == 0) return;
    ++figures.grasps_with_picks;
    figures.picks_mapped += picks->mapped;
    figures.picks_held += picks->held;
    addAimed(picks->aimed_held);
  }
  void addAimed(const std::optional<bool>& held) {
    if (!held) return;
    ++figures.aimed_known;
    if (*held) ++figures.aimed_held;
  }
  GrowthFigures finish() const {
    GrowthFigures f = figures;
    f.intersection_percent = median(intersection);
    f.false_positive_percent = median(false_positive);
    return f;
  }
};

struct RowAccumulator {
  std::size_t grasps = 0;
  std::size_t studied = 0, raw_task_met = 0, filtered_task_met = 0;  // patch rows
  Accumulator filtered, raw;
};

// Key: (pooled: the "All" row, after every dataset; dataset; setting index:
// 0 plain, 1 + index into the K list, then 1 + |K| + index into the patch radii).
using Key = std::tuple<bool, std::string, std::size_t>;

nlohmann::ordered_json optionalJson(const std::optional<double>& v) { return v ? nlohmann::ordered_json(*v) : nullptr; }

nlohmann::ordered_json figuresJson(const GrowthFigures& f) {
  return {{"intersection_percent", optionalJson(f.intersection_percent)},
          {"false_positive_percent", optionalJson(f.false_positive_percent)},
          {"regions", f.regions},
          {"empty_regions", f.empty_regions},
          {"recommended_known", f.recommended_known},
          {"recommended_inside", f.recommended_inside},
          {"recommended_inside_percent", optionalJson(f.recommendedInsidePercent())},
          {"center_outside", f.center_outside},
          {"center_outside_percent", optionalJson(f.centerOutsidePercent())},
          {"grasps_with_picks", f.grasps_with_picks},
          {"picks_mapped", f.picks_mapped},
          {"picks_held", f.picks_held},
          {"picks_held_percent", optionalJson(f.picksHeldPercent())},
          {"aimed_known", f.aimed_known},
          {"aimed_held", f.aimed_held},
          {"aimed_held_percent", optionalJson(f.aimedHeldPercent())}};
}

}  // namespace

std::optional<double> GrowthFigures::recommendedInsidePercent() const {
  if (recommended_known == 0) return std::nullopt;
  return 100.0 * static_cast<double>(recommended_inside) / static_cast<double>(recommended_known);
}

std::optional<double> GrowthFigures::picksHeldPercent() const {
  if (picks_mapped == 0) return std::nullopt;
  return 100.0 * static_cast<double>(picks_held) / static_cast<double>(picks_mapped);
}

std::optional<double> GrowthFigures::aimedHeldPercent() const {
  if (aimed_known == 0) return std::nullopt;
  return 100.0 * static_cast<double>(aimed_held) / static_cast<double>(aimed_known);
}

std::optional<double> GrowthFigures::centerOutsidePercent() const {
  const std::size_t nonempty = regions - empty_regions;
  if (nonempty == 0) return std::nullopt;
  return 100.0 * static_cast<double>(center_outside) / static_cast<double>(nonempty);
}

ConservativeSummary computeConservativeSummary(const std::vector<GraspRecord>& records) {
  ConservativeSummary summary;
  std::set<double> ks;
  for (const GraspRecord& r : records)
    for (const ConservativeOutcome& c : r.filtered.conservative) ks.insert(c.sigmas);
  summary.sigmas.assign(ks.begin(), ks.end());
  std::set<double> radii;
  for (const GraspRecord& r : records)
    if (r.patch) radii.insert(r.patch->radius_m);
  summary.patch_radii_m.assign(radii.begin(), radii.end());
  auto settingOf = [&](double k) {
    return 1 + static_cast<std::size_t>(std::lower_bound(summary.sigmas.begin(), summary.sigmas.end(), k) -
                                        summary.sigmas.begin());
  };
  auto patchSettingOf = [&](double radius) {
    return 1 + summary.sigmas.size() +
           static_cast<std::size_t>(std::lower_bound(summary.patch_radii_m.begin(), summary.patch_radii_m.end(), radius) -
                                    summary.patch_radii_m.begin());
  };

  std::map<Key, RowAccumulator> rows;
  for (const GraspRecord& r : records) {
    if (!r.evaluated) continue;
    for (const bool pooled : {false, true}) {
      const std::string dataset = pooled ? "All" : r.dataset;
      RowAccumulator& plain = rows[{pooled, dataset, 0}];
      ++plain.grasps;
      for (const auto& region : r.filtered.regions) plain.filtered.add(region);
      for (const auto& region : r.raw.regions) plain.raw.add(region);
      plain.filtered.add(r.filtered.picks);
      plain.raw.add(r.raw.picks);
      for (const ConservativeOutcome& c : r.filtered.conservative) {
        RowAccumulator& row = rows[{pooled, dataset, settingOf(c.sigmas)}];
        ++row.grasps;
        for (const auto& region : c.regions) row.filtered.add(region);
        row.filtered.add(c.picks);
      }
      for (const ConservativeOutcome& c : r.raw.conservative) {
        RowAccumulator& row = rows[{pooled, dataset, settingOf(c.sigmas)}];
        for (const auto& region : c.regions) row.raw.add(region);
        row.raw.add(c.picks);
      }
      if (r.patch) {
        RowAccumulator& row = rows[{pooled, dataset, patchSettingOf(r.patch->radius_m)}];
        ++row.studied;
        row.raw_task_met += r.patch->raw.task_fulfilled;
        row.filtered_task_met += r.patch->filtered.task_fulfilled;
        if (!r.patch->evaluated) continue;
        ++row.grasps;
        for (const auto& region : r.patch->filtered.regions) row.filtered.add(region);
        for (const auto& region : r.patch->raw.regions) row.raw.add(region);
        row.filtered.addAimed(r.patch->filtered.aimed_held);
        row.raw.addAimed(r.patch->raw.aimed_held);
      }
    }
  }
  for (const auto& [key, acc] : rows) {
    GrowthRow row;
    row.dataset = std::get<1>(key);
    const std::size_t setting = std::get<2>(key);
    if (setting > summary.sigmas.size())
      row.patch_radius_m = summary.patch_radii_m[setting - 1 - summary.sigmas.size()];
    else if (setting > 0)
      row.sigmas = summary.sigmas[setting - 1];
    row.evaluated_grasps = acc.grasps;
    row.studied_grasps = acc.studied;
    row.raw_task_met = acc.raw_task_met;
    row.filtered_task_met = acc.filtered_task_met;
    row.filtered = acc.filtered.finish();
    row.raw = acc.raw.finish();
    summary.rows.push_back(std::move(row));
  }
  return summary;
}

std::string conservativeSummaryJson(const ConservativeSummary& summary) {
  nlohmann::ordered_json j;
  j["sigmas"] = summary.sigmas;
  // Patch keys only when the study ran, so other runs keep their form.
  if (!summary.patch_radii_m.empty()) j["patch_radii_m"] = summary.patch_radii_m;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const GrowthRow& row : summary.rows) {
    nlohmann::ordered_json item{{"dataset", row.dataset},
                                {"growth", row.patch_radius_m ? "patch" : row.sigmas ? "conservative" : "plain"},
                                {"sigmas", optionalJson(row.sigmas)}};
    if (row.patch_radius_m) {
      item["patch_radius_m"] = *row.patch_radius_m;
      item["studied_grasps"] = row.studied_grasps;
      item["raw_task_met"] = row.raw_task_met;
      item["filtered_task_met"] = row.filtered_task_met;
    }
    item["evaluated_grasps"] = row.evaluated_grasps;
    item["filtered"] = figuresJson(row.filtered);
    item["raw"] = figuresJson(row.raw);
    rows.push_back(std::move(item));
  }
  j["rows"] = std::move(rows);
  return j.dump(2);
}

}  // namespace icrkit::eval
