#include <icrkit/report/conservative_plot.hpp>

#include <icrkit/core/atomic_file.hpp>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace icrkit::report {
namespace {

using eval::ConservativeSummary;
using eval::GrowthFigures;
using eval::GrowthRow;

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

std::string cell(const std::optional<double>& v, int digits = 1) {
  if (!v) return "–";
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << *v;
  return out.str();
}

}  // namespace

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
  write("conservative.json", eval::conservativeSummaryJson(summary) + "\n");
  write("conservative.md", conservativeSummaryMarkdown(summary));
  write("conservative.svg", conservativeCurveSvg(summary));
  return files;
}

}  // namespace icrkit::report
