#include <icrkit/eval/conservative_summary.hpp>

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/eval/results_tables.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
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

std::string growthLabel(const GrowthRow& row) {
  std::ostringstream out;
  if (row.patch_radius_m)
    out << "patch " << *row.patch_radius_m * 1000 << " mm";
  else if (row.sigmas)
    out << "K " << *row.sigmas;
  else
    out << "plain";
  return out.str();
}

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

std::string cell(const std::optional<double>& v, int digits = 1) {
  if (!v) return "–";
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << *v;
  return out.str();
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

std::string conservativeSummaryMarkdown(const ConservativeSummary& summary) {
  std::ostringstream out;
  out << "| dataset | growth | grasps | filtered Int % | filtered FP % | filtered empty | filtered aim inside % | "
         "filtered centre outside % | filtered picks held % (grasps) | filtered aimed grasp held % | raw Int % | raw FP % | "
         "raw empty | raw aim inside % | raw centre outside % | raw picks held % (grasps) | raw aimed grasp held % |\n"
      << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const GrowthRow& row : summary.rows) {
    out << "| " << row.dataset << " | " << growthLabel(row) << " | " << row.evaluated_grasps;
    if (row.patch_radius_m) out << " of " << row.studied_grasps;
    for (const GrowthFigures* f : {&row.filtered, &row.raw})
      out << " | " << cell(f->intersection_percent) << " | " << cell(f->false_positive_percent) << " | "
          << f->empty_regions << "/" << f->regions << " | " << cell(f->recommendedInsidePercent()) << " | "
          << cell(f->centerOutsidePercent()) << " | " << cell(f->picksHeldPercent()) << " (" << f->grasps_with_picks
          << ") | " << cell(f->aimedHeldPercent());
    out << " |\n";
  }
  out << "\nInt, FP: medians over all regions (an empty region counts 0 and 0). Aim inside: the region's "
         "recommended contact (its deepest vertex) maps into the CAD region; an empty region has none and "
         "counts as not inside. Centre outside: Q_n < 0, over the non-empty regions. Picks held: random picks of "
         "one vertex per region (ExperimentConfig::picks_per_grasp), moved onto the CAD mesh by eq. (3), whose CAD grasp holds the "
         "task; in brackets the grasps whose regions were all non-empty. Aimed grasp held: the grasp of every "
         "region's recommended contact, moved onto the CAD mesh the same way, holds the task (over those grasps).\n";
  if (!summary.patch_radii_m.empty())
    out << "\nPatch rows: the grasps run again with the reference library's multi-point contacts on all three "
           "meshes (its own task, alpha x the CAD grasp's patch epsilon, and its own CAD regions); grasps: those "
           "whose mapped patch grasps both hold that task, of those the plain experiment evaluated. No random picks; the aimed "
           "grasp is checked with CAD patches.\n";
  return out.str();
}

std::string conservativeCurveSvg(const ConservativeSummary& summary) {
  const double width = 640, height = 440, left = 70, right = 30, top = 40, bottom = 60;
  auto x = [&](double fp) { return left + (width - left - right) * std::clamp(fp, 0.0, 100.0) / 100.0; };
  auto y = [&](double in) { return height - bottom - (height - top - bottom) * std::clamp(in, 0.0, 100.0) / 100.0; };
  std::ostringstream svg;
  svg << std::fixed << std::setprecision(1);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << width / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">Median Int against median FP "
      << "over K (all datasets)</text>\n";
  for (int t = 0; t <= 100; t += 20) {
    svg << "<line x1=\"" << x(t) << "\" y1=\"" << y(0) << "\" x2=\"" << x(t) << "\" y2=\"" << y(100)
        << "\" stroke=\"#eee\"/>\n<line x1=\"" << x(0) << "\" y1=\"" << y(t) << "\" x2=\"" << x(100) << "\" y2=\""
        << y(t) << "\" stroke=\"#eee\"/>\n"
        << "<text x=\"" << x(t) << "\" y=\"" << y(0) + 16 << "\" text-anchor=\"middle\">" << t << "</text>\n"
        << "<text x=\"" << x(0) - 8 << "\" y=\"" << y(t) + 4 << "\" text-anchor=\"end\">" << t << "</text>\n";
  }
  svg << "<text x=\"" << (x(0) + x(100)) / 2 << "\" y=\"" << height - 18 << "\" text-anchor=\"middle\">median FP (% of "
      << "the CAD region)</text>\n<text transform=\"translate(18," << (y(0) + y(100)) / 2
      << ") rotate(-90)\" text-anchor=\"middle\">median Int (%)</text>\n";
  // The paper's result (filtered, Table I average): Int 59 %, FP 9 %.
  svg << "<circle cx=\"" << x(9) << "\" cy=\"" << y(59) << "\" r=\"5\" fill=\"none\" stroke=\"black\"/>\n<text x=\""
      << x(9) + 8 << "\" y=\"" << y(59) - 6 << "\">paper</text>\n";
  const struct {
    const char* name;
    const char* colour;
    bool filtered;
  } meshes[] = {{"filtered", "#1f77b4", true}, {"raw", "#d62728", false}};
  double legend_y = top + 10;
  for (const auto& mesh : meshes) {
    std::ostringstream points, labels;
    points << std::fixed << std::setprecision(1);
    labels << std::fixed << std::setprecision(1);
    for (const GrowthRow& row : summary.rows) {
      if (row.dataset != "All" || row.patch_radius_m) continue;
      const GrowthFigures& f = mesh.filtered ? row.filtered : row.raw;
      if (!f.intersection_percent || !f.false_positive_percent) continue;
      const double px = x(*f.false_positive_percent), py = y(*f.intersection_percent);
      points << px << "," << py << " ";
      labels << "<circle cx=\"" << px << "\" cy=\"" << py << "\" r=\"3\" fill=\"" << mesh.colour << "\"/>\n<text x=\""
             << px + 5 << "\" y=\"" << py + 14 << "\" fill=\"" << mesh.colour << "\">" << growthLabel(row)
             << "</text>\n";
    }
    svg << "<polyline points=\"" << points.str() << "\" fill=\"none\" stroke=\"" << mesh.colour
        << "\" stroke-width=\"2\"/>\n"
        << labels.str() << "<text x=\"" << x(100) - 80 << "\" y=\"" << legend_y << "\" fill=\"" << mesh.colour
        << "\">" << mesh.name << " mesh</text>\n";
    legend_y += 16;
    // The patch study is not a point of the K curve: its own task and CAD regions.
    for (const GrowthRow& row : summary.rows) {
      if (row.dataset != "All" || !row.patch_radius_m) continue;
      const GrowthFigures& f = mesh.filtered ? row.filtered : row.raw;
      if (!f.intersection_percent || !f.false_positive_percent) continue;
      const double px = x(*f.false_positive_percent), py = y(*f.intersection_percent);
      svg << "<rect x=\"" << px - 4 << "\" y=\"" << py - 4 << "\" width=\"8\" height=\"8\" fill=\"none\" stroke=\""
          << mesh.colour << "\" stroke-width=\"2\"/>\n<text x=\"" << px + 6 << "\" y=\"" << py - 6 << "\" fill=\""
          << mesh.colour << "\">" << growthLabel(row) << "</text>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

std::vector<std::string> writeConservativeSummary(const std::string& directory, const ConservativeSummary& summary) {
  namespace fs = std::filesystem;
  const fs::path dir(directory);
  std::vector<std::string> files;
  const auto write = [&](const std::string& name, const std::string& text) {
    files.push_back((dir / name).string());
    writeFileAtomically(files.back(), [&](std::ostream& out) { out << text; });
  };
  write("conservative.json", conservativeSummaryJson(summary) + "\n");
  write("conservative.md", conservativeSummaryMarkdown(summary));
  write("conservative.svg", conservativeCurveSvg(summary));
  return files;
}

}  // namespace icrkit::eval
