#include <icrkit/report/html_report.hpp>

#include "report_assets.hpp"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace icrkit::report {
namespace {

using eval::EligibilityCounts;
using eval::EligibilityGroup;
using eval::EligibilitySummary;
using eval::MeshMedians;
using eval::PaperTableOne;
using eval::PaperTableOneRow;
using eval::TableOne;
using eval::TableOneRow;
using eval::paperTableOne;
using eval::paperTableOneRow;

// --- small formatting helpers --------------------------------------------

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string percentCell(const std::optional<double>& value) { return value ? fixed(*value, 1) : "&ndash;"; }

std::string countWithPercent(const EligibilityCounts& counts, std::size_t count) {
  const auto percent = counts.percent(count);
  return std::to_string(count) + (percent ? " (" + fixed(*percent, 1) + " %)" : "");
}

std::string offRimText(const EligibilityCounts& counts) {
  if (counts.rim_not_recorded == counts.grasps && counts.grasps > 0) return "&ndash;";
  const auto percent = [&](std::size_t count) {
    const auto p = counts.offRimPercent(count);
    return p ? fixed(*p, 1) + " %" : std::string("&ndash;");
  };
  return std::to_string(counts.off_rim_grasps) + " / " + percent(counts.raw_eligible_off_rim) + " / " +
         percent(counts.filtered_eligible_off_rim);
}

std::string bytesText(std::size_t bytes) {
  if (bytes >= 1024 * 1024) return fixed(bytes / (1024.0 * 1024.0), 1) + " MiB";
  if (bytes >= 1024) return fixed(bytes / 1024.0, 1) + " KiB";
  return std::to_string(bytes) + " B";
}

// JSON placed inside <script type="application/json">: "</" would end the
// element early, so it becomes "<\/" (a valid JSON escape of '/').
std::string jsonForScript(const nlohmann::json& value) {
  std::string text = value.dump();
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

template <typename T>
std::string base64Of(const std::vector<T>& values) {
  return base64Encode(reinterpret_cast<const unsigned char*>(values.data()), values.size() * sizeof(T));
}

// Little-endian on the page (typed arrays use the platform's order, and every
// browser platform is little-endian); written explicitly so that the bytes do
// not depend on the machine that builds the report.
void appendLittleEndian(std::vector<unsigned char>& out, std::uint64_t value, int bytes) {
  for (int b = 0; b < bytes; ++b) out.push_back(static_cast<unsigned char>((value >> (8 * b)) & 0xff));
}

// An SVG document inlined in HTML: its XML prolog and doctype are not allowed there.
std::string inlineSvg(const std::string& svg) {
  std::size_t start = svg.find("<svg");
  return start == std::string::npos ? htmlEscape(svg) : svg.substr(start);
}

// --- sections (the page's fixed parts, its CSS and JavaScript, are files in
// libs/report/assets/, embedded at build time: report_assets.hpp) -----------

void writeParameters(std::ostringstream& out, const HtmlReportInput& input) {
  out << "<section id=\"parameters\">\n<details open>\n<summary><h2 style=\"display:inline\">Run parameters</h2></summary>\n";
  if (!input.parameters.empty()) {
    out << "<table class=\"kv\">\n";
    for (const auto& [key, value] : input.parameters)
      out << "<tr><th class=\"name\">" << htmlEscape(key) << "</th><td class=\"name\">" << htmlEscape(value)
          << "</td></tr>\n";
    out << "</table>\n";
  }
  if (!input.run_json.empty()) {
    std::string pretty = input.run_json;
    try {
      pretty = nlohmann::json::parse(input.run_json).dump(2);
    } catch (const std::exception&) {  // shown as is; the command reports the parse error
    }
    out << "<details><summary>run.json</summary><pre>" << htmlEscape(pretty) << "</pre></details>\n";
  } else {
    out << "<p class=\"note\">No run.json: the parameters are unknown.</p>\n";
  }
  out << "</details>\n</section>\n";
}

void writeTableOne(std::ostringstream& out, const HtmlReportInput& input) {
  out << "<section id=\"table1-section\">\n<h2>Table I: median intersection and false-positive areas</h2>\n";
  if (!input.table) {
    out << "<p class=\"unavailable\">Table I unavailable: it is computed from grasps.jsonl, which this run folder "
           "lacks.</p>\n</section>\n";
    return;
  }
  const TableOne& table = *input.table;
  out << "<table id=\"table1\">\n<thead>\n"
         "<tr><th class=\"name\" rowspan=\"2\">Dataset</th><th class=\"name\" rowspan=\"2\">Paper's object</th>"
         "<th rowspan=\"2\">Evaluated grasps</th>"
         "<th colspan=\"4\">Smooth (filtered) mesh</th><th colspan=\"4\">Raw mesh</th></tr>\n<tr>";
  for (int mesh = 0; mesh < 2; ++mesh)
    out << "<th>Int % ours</th><th>Int % paper</th><th>FP % ours</th><th>FP % paper</th>";
  out << "</tr>\n</thead>\n<tbody>\n";
  auto row = [&](const TableOneRow& r, bool average) {
    const auto paper = paperTableOneRow(average ? "Average" : r.dataset);
    std::string object = paper ? paper->object + (paper->sensor.empty() ? "" : " (" + paper->sensor + ")") : "";
    out << "<tr" << (average ? " class=\"average\"" : "") << "><td class=\"name\">" << htmlEscape(r.dataset)
        << "</td><td class=\"name\">" << (object.empty() ? "&ndash;" : htmlEscape(object)) << "</td><td>"
        << r.evaluated_grasps << "</td>";
    auto pair = [&](const std::optional<double>& ours, std::optional<double> theirs) {
      out << "<td>" << percentCell(ours) << "</td><td class=\"paper\">" << percentCell(theirs) << "</td>";
    };
    pair(r.filtered.intersection_percent,
         paper ? std::optional<double>(paper->filtered_intersection_percent) : std::nullopt);
    pair(r.filtered.false_positive_percent,
         paper ? std::optional<double>(paper->filtered_false_positive_percent) : std::nullopt);
    pair(r.raw.intersection_percent, paper ? std::optional<double>(paper->raw_intersection_percent) : std::nullopt);
    pair(r.raw.false_positive_percent,
         paper ? std::optional<double>(paper->raw_false_positive_percent) : std::nullopt);
    out << "</tr>\n";
  };
  for (const TableOneRow& r : table.rows) row(r, false);
  row(table.average, true);
  out << "</tbody>\n</table>\n<p class=\"note\">Medians over all regions of the evaluated grasps ("
      << (table.fingers == 0 ? std::string("every finger count together, as in the paper")
                             : std::to_string(table.fingers) + " fingers")
      << "): Int = 100 A(I<sub>n</sub>) / A(C<sub>n</sub><sup>C</sup>), FP = 100 FP / A(C<sub>n</sub><sup>C</sup>). "
         "Grey columns: Krug et al., Table I (the Average row there is the mean of the per-dataset medians, as here). "
         "&ndash;: no value (no evaluated grasp, or a dataset the paper does not have).</p>\n</section>\n";
}

void writeEligibility(std::ostringstream& out, const HtmlReportInput& input) {
  out << "<section id=\"eligibility\">\n<h2>Eligibility</h2>\n";
  if (!input.eligibility) {
    out << "<p class=\"unavailable\">Eligibility rates unavailable: they are computed from grasps.jsonl, which this "
           "run folder lacks.</p>\n</section>\n";
    return;
  }
  out << "<table id=\"eligibility-table\">\n<thead><tr><th class=\"name\">Dataset</th><th class=\"name\">Fingers</th>"
         "<th>Grasps</th><th>Raw eligible</th><th>Filtered eligible</th><th>Filtered: preselection failed</th>"
         "<th>Both eligible</th><th>Evaluated</th><th>Filtered eligible after snapping to the nearest kept vertex (not "
         "the paper's check)</th><th>Away from the rim of the seen surface: grasps / raw / filtered eligible (not "
         "the paper's check)</th></tr></thead>\n<tbody>\n";
  auto row = [&](const std::string& name, const std::string& fingers, const EligibilityCounts& c, bool strong) {
    out << "<tr" << (strong ? " class=\"average\"" : "") << "><td class=\"name\">" << htmlEscape(name)
        << "</td><td class=\"name\">" << htmlEscape(fingers) << "</td><td>" << c.grasps << "</td><td>"
        << countWithPercent(c, c.raw_eligible) << "</td><td>" << countWithPercent(c, c.filtered_eligible)
        << "</td><td>" << countWithPercent(c, c.filtered_preselection_failed) << "</td><td>"
        << countWithPercent(c, c.both_eligible) << "</td><td>" << countWithPercent(c, c.evaluated) << "</td><td>"
        << countWithPercent(c, c.filtered_eligible_after_snapping) << "</td><td>" << offRimText(c) << "</td></tr>\n";
  };
  for (const EligibilityGroup& group : input.eligibility->datasets) row(group.dataset, "all", group.all, false);
  for (const auto& [fingers, counts] : input.eligibility->overall.by_fingers)
    row("all datasets", std::to_string(fingers), counts, false);
  row("all datasets", "all", input.eligibility->overall.all, true);
  const PaperTableOne paper = paperTableOne();
  out << "<tr><td class=\"name paper\">Krug et al., Section V</td><td class=\"name paper\">4, 5</td>"
         "<td class=\"paper\">&ndash;</td><td class=\"paper\">"
      << fixed(paper.raw_eligible_percent, 1) << " %</td><td class=\"paper\">" << fixed(paper.filtered_eligible_percent, 1)
      << " %</td><td class=\"paper\">&ndash;</td><td class=\"paper\">&ndash;</td><td class=\"paper\">&ndash;</td>"
         "<td class=\"paper\">&ndash;</td><td class=\"paper\">&ndash;</td></tr>\n"
         "</tbody>\n</table>\n<p class=\"note\">A mapped grasp is eligible when it fulfils the task (force closure, "
         "its GWS holds the TWS) and, on the filtered mesh, avoids excluded vertices. Grasps eligible on both meshes "
         "are evaluated. The column \"after snapping\" is not the paper's check: it also counts a filtered grasp whose contacts on "
         "excluded vertices, each moved to the nearest kept vertex within the mapping's neighbourhood radius, meet the "
         "task (what a planner would do); a grasp eligible only after snapping is not evaluated. The column \"away from "
         "the rim\" (not the paper's check either) keeps only grasps whose mapped contacts all lie farther than "
      << fixed(input.eligibility->seen_rim_distance_m * 1e3, 1)
      << " mm from the filtered mesh's boundary (the rim of what the views saw, and of the holes left open): a "
         "grasp on surface no view saw (an object's base) is mapped onto that rim on both meshes.</p>\n</section>\n";
}

void writePlanned(std::ostringstream& out, const HtmlReportInput& input) {
  if (input.planned_lines.empty()) return;
  out << "<section id=\"planned\">\n<h2>Planned grasps executed on the CAD mesh</h2>\n"
         "<table id=\"planned-table\">\n<thead><tr><th class=\"name\">Dataset</th><th class=\"name\">Mesh</th>"
         "<th>Grasps</th><th>TWS radius</th><th>Aimed held</th><th>Picks held</th><th>Placement error held</th>"
         "<th>Median region area (mm&sup2;)</th></tr></thead>\n<tbody>\n";
  const std::pair<const char*, const char*> meshes[] = {{"filtered", "filtered, planned"},
                                                        {"filtered_random", "filtered, random baseline"},
                                                        {"raw", "raw, planned"},
                                                        {"raw_random", "raw, random baseline"}};
  for (const std::string& line : input.planned_lines) {
    nlohmann::json study;
    try {
      study = nlohmann::json::parse(line);
    } catch (const std::exception&) {
      continue;  // run_report checked the lines
    }
    for (const auto& [key, label] : meshes) {
      if (!study.contains(key)) continue;
      const nlohmann::json& m = study.at(key);
      out << "<tr><td class=\"name\">" << htmlEscape(study.value("dataset", std::string())) << "</td><td class=\"name\">"
          << label << "</td>";
      if (m.contains("error")) {
        out << "<td>0</td><td colspan=\"5\" class=\"name\">" << htmlEscape(m.at("error").get<std::string>())
            << "</td></tr>\n";
        continue;
      }
      out << "<td>" << m.at("grasps").size() << "</td><td>" << fixed(study.value("tws_radius", 0.0), 4) << "</td><td>"
          << fixed(100.0 * m.value("aimed_held_fraction", 0.0), 1) << " %</td><td>"
          << fixed(100.0 * m.value("picks_held_fraction", 0.0), 1) << " %</td><td>"
          << fixed(100.0 * m.value("placements_held_fraction", 0.0), 1) << " %</td><td>"
          << fixed(1e6 * m.value("median_region_area_m2", 0.0), 0) << "</td></tr>\n";
    }
  }
  out << "</tbody>\n</table>\n<p class=\"note\">The top grasps of <code>icrkit plan</code> on each reconstructed "
         "mesh (task: half the median epsilon of the random CAD grasps), executed on the CAD mesh as a robot would: "
         "every finger at its region's recommended contact (aimed), at one random vertex of each region (picks), and "
         "aimed with a Gaussian placement error. Each landing point goes onto the CAD mesh along its normal (eq. (3), "
         "by touch). The random baseline: force-closure grasps meeting the same task with plain regions, no trust "
         "mask (docs/planning.md).</p>\n</section>\n";
}

void writeSurface(std::ostringstream& out, const HtmlReportInput& input) {
  if (input.surface_lines.empty()) return;
  out << "<section id=\"surface\">\n<h2>Surface accuracy against the CAD mesh</h2>\n"
         "<table id=\"surface-table\">\n<thead><tr><th class=\"name\">Dataset</th><th class=\"name\">Mesh</th>"
         "<th>Mean distance (mm)</th><th>near edges</th><th>elsewhere</th><th>Median normal error near edges "
         "(deg)</th><th>elsewhere</th><th>Vertices near edges</th></tr></thead>\n<tbody>\n";
  for (const std::string& line : input.surface_lines) {
    nlohmann::json study;
    try {
      study = nlohmann::json::parse(line);
    } catch (const std::exception&) {
      continue;  // run_report checked the lines
    }
    for (const char* mesh : {"filtered", "raw"}) {
      if (!study.contains(mesh)) continue;
      const nlohmann::json& m = study.at(mesh);
      const auto distance = [&](const char* group) { return fixed(1e3 * m.at(group).value("mean_distance_m", 0.0), 2); };
      const auto angle = [&](const char* group) {
        const nlohmann::json& g = m.at(group);
        return g.contains("median_normal_error_deg") && g.value("vertices", 0) > 0
                   ? fixed(g.at("median_normal_error_deg").get<double>(), 1)
                   : std::string("&ndash;");
      };
      out << "<tr><td class=\"name\">" << htmlEscape(study.value("dataset", std::string())) << "</td><td class=\"name\">"
          << mesh << "</td><td>" << distance("all") << "</td><td>" << distance("near_edges") << "</td><td>"
          << distance("elsewhere") << "</td><td>" << angle("near_edges") << "</td><td>" << angle("elsewhere")
          << "</td><td>" << m.at("near_edges").value("vertices", 0) << " of " << m.at("all").value("vertices", 0)
          << "</td></tr>\n";
    }
  }
  out << "</tbody>\n</table>\n<p class=\"note\">Per vertex of each reconstructed mesh: the distance to the CAD "
         "surface, and the angle between its normal and the CAD face a finger approaching along it touches. Near "
         "edges: within 4 mm of a CAD edge whose faces differ by more than 30 deg (docs/evaluation.md).</p>\n"
         "</section>\n";
}

void writeViewer(std::ostringstream& out, const HtmlReportInput& input, HtmlReportSizes& sizes) {
  out << "<section id=\"viewer-section\">\n<h2>3D viewer</h2>\n";
  if (!input.grasp_label.empty()) out << "<p><b>Grasp:</b> " << htmlEscape(input.grasp_label) << "</p>\n";
  if (!input.viewer_note.empty()) out << "<p class=\"note\">" << htmlEscape(input.viewer_note) << "</p>\n";
  const bool have_three = !input.three_module_base64.empty() && !input.orbit_controls_base64.empty();
  if (input.meshes.empty()) {
    out << "<p class=\"unavailable\" id=\"viewer-unavailable\">3D viewer: no meshes to show (see Missing and "
           "Warnings).</p>\n</section>\n<script>window.icrkitReport.viewer = 'no-meshes';</script>\n";
    return;
  }
  if (!have_three) {
    out << "<p class=\"unavailable\" id=\"viewer-unavailable\">3D viewer unavailable: three.js was not vendored at "
           "build time (scripts/vendor-threejs.sh needs npm and the npm registry, or ICRKIT_THREEJS_TARBALL).</p>\n"
           "</section>\n<script>window.icrkitReport.viewer = 'unavailable';</script>\n";
    return;
  }

  // Common bounding box of every mesh: one quantization grid keeps them aligned.
  Eigen::AlignedBox3f box;
  for (const ReportMesh& mesh : input.meshes)
    for (const auto& p : mesh.positions) box.extend(Eigen::Vector3f(p[0], p[1], p[2]));
  if (box.isEmpty()) box = Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero());
  const Eigen::Vector3f lo = box.min(), extent = box.max() - box.min();

  nlohmann::json data{{"fingers", input.fingers},
                      {"box", {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {box.max().x(), box.max().y(), box.max().z()}}}},
                      {"meshes", nlohmann::json::array()}};
  out << "<div class=\"viewer-controls\"><span><b>Meshes:</b></span>";
  for (const ReportMesh& mesh : input.meshes) {
    std::vector<unsigned char> positions, faces;
    positions.reserve(mesh.positions.size() * 6);
    for (const auto& p : mesh.positions)
      for (int a = 0; a < 3; ++a) {
        const float t = extent[a] > 0.0f ? (p[a] - lo[a]) / extent[a] : 0.0f;
        appendLittleEndian(positions, static_cast<std::uint16_t>(std::lround(std::clamp(t, 0.0f, 1.0f) * 65535.0f)), 2);
      }
    faces.reserve(mesh.faces.size() * 12);
    for (const auto& f : mesh.faces)
      for (int a = 0; a < 3; ++a) appendLittleEndian(faces, f[a], 4);
    nlohmann::json contacts = nlohmann::json::array();
    for (const auto& c : mesh.contacts) contacts.push_back(c ? nlohmann::json{(*c)[0], (*c)[1], (*c)[2]} : nlohmann::json());
    nlohmann::json item{{"key", mesh.key},
                        {"label", mesh.label},
                        {"positions", base64Of(positions)},
                        {"faces", base64Of(faces)},
                        {"region", mesh.region.empty() ? std::string() : base64Of(mesh.region)},
                        {"contacts", contacts}};
    sizes.meshes += item["positions"].get_ref<const std::string&>().size() +
                    item["faces"].get_ref<const std::string&>().size() +
                    item["region"].get_ref<const std::string&>().size();
    data["meshes"].push_back(std::move(item));
    const std::string colour = mesh.key == "cad" ? "#bdbdbd" : mesh.key == "raw" ? "#d9b48f" : "#9ecae1";
    const bool capped = mesh.faces.size() < mesh.source_faces;
    out << "<label title=\"" << htmlEscape(mesh.source) << "\"><input type=\"checkbox\" id=\"mesh-" << htmlEscape(mesh.key)
        << "\" checked> <span class=\"swatch\" style=\"background:" << colour << "\"></span>" << htmlEscape(mesh.label)
        << " (" << mesh.positions.size() << " vertices, " << mesh.faces.size() << " faces"
        << (capped ? " of " + std::to_string(mesh.source_faces) : std::string()) << ")</label>";
  }
  out << "</div>\n<div class=\"viewer-controls\"><span><b>Fingers:</b></span>";
  static const char* const kFingerColours[] = {"#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
                                              "#e377c2", "#8c564b", "#bcbd22", "#1f77b4", "#7f7f7f"};
  for (std::size_t f = 0; f < input.fingers; ++f)
    out << "<label><input type=\"checkbox\" id=\"finger-" << f << "\" checked> <span class=\"swatch\" style=\"background:"
        << kFingerColours[f % 10] << "\"></span>finger " << f << "</label>";
  if (input.fingers == 0) out << "<span class=\"note\">no regions</span>";
  out << "</div>\n<div class=\"viewer-controls\"><span><b>Layout:</b></span>"
         "<label><input type=\"radio\" name=\"layout\" id=\"layout-side\" checked> side by side</label>"
         "<label><input type=\"radio\" name=\"layout\" id=\"layout-overlay\"> overlaid (as measured)</label>"
         "<button type=\"button\" id=\"view-reset\">Reset view</button></div>\n"
         "<canvas id=\"viewer\"></canvas>\n<p class=\"note\" id=\"viewer-message\">Loading the viewer&hellip;</p>\n"
         "<p class=\"note\">Legend: grey = CAD mesh, tan = raw mesh, blue = filtered mesh; coloured patches = the "
         "independent contact region of each finger (C<sup>C</sup> on the CAD mesh, C<sup>R</sup> on the raw, "
         "C<sup>F</sup> on the filtered mesh; where regions overlap the lower finger's colour shows); spheres = the "
         "grasp's contact points on each mesh. Positions are quantized to 16 bits over the common bounding box; "
         "normals are computed in the browser.</p>\n";
  out << "<script type=\"application/json\" id=\"viewer-data\">" << jsonForScript(data) << "</script>\n";
  out << "<script type=\"text/plain\" id=\"three-module\">" << input.three_module_base64 << "</script>\n";
  out << "<script type=\"text/plain\" id=\"three-orbit\">" << input.orbit_controls_base64 << "</script>\n";
  sizes.threejs = input.three_module_base64.size() + input.orbit_controls_base64.size();
  out << "<script type=\"module\">" << kReportViewerJs << "</script>\n</section>\n";
}

}  // namespace

std::string base64Encode(const unsigned char* data, std::size_t size) {
  static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t v = (std::uint32_t(data[i]) << 16) | (std::uint32_t(data[i + 1]) << 8) | data[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < size) {
    const bool two = i + 1 < size;
    const std::uint32_t v = (std::uint32_t(data[i]) << 16) | (two ? std::uint32_t(data[i + 1]) << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += two ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string htmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

ReportMesh makeReportMesh(const std::string& key, const std::string& label, const std::string& source,
                          const TriangleMesh& mesh, const std::vector<std::vector<int>>& regions,
                          const std::vector<int>& contacts, std::size_t max_faces) {
  ReportMesh out;
  out.key = key;
  out.label = label;
  out.source = source;
  const std::size_t n = mesh.vertexCount();
  out.source_vertices = n;
  out.source_faces = mesh.faceCount();
  const std::size_t step =
      max_faces > 0 && mesh.faceCount() > max_faces ? (mesh.faceCount() + max_faces - 1) / max_faces : 1;

  // Finger per original vertex; filled from the last finger down so that the
  // lowest finger wins where regions overlap.
  std::vector<std::int8_t> finger_of;
  bool any_region = false;
  for (const auto& region : regions) any_region = any_region || !region.empty();
  if (any_region) {
    finger_of.assign(n, -1);
    for (std::size_t f = regions.size(); f-- > 0;)
      for (const int v : regions[f])
        if (v >= 0 && static_cast<std::size_t>(v) < n)
          finger_of[v] = static_cast<std::int8_t>(std::min<std::size_t>(f, std::numeric_limits<std::int8_t>::max()));
  }

  std::vector<std::int64_t> remap(n, -1);
  auto keep = [&](int v) -> std::uint32_t {
    if (remap[v] < 0) {
      remap[v] = static_cast<std::int64_t>(out.positions.size());
      const Eigen::Vector3d& p = mesh.vertices.positions[v];
      out.positions.push_back({static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
      if (any_region) out.region.push_back(finger_of[v]);
    }
    return static_cast<std::uint32_t>(remap[v]);
  };
  for (std::size_t f = 0; f < mesh.faceCount(); f += step) {
    const Triangle& t = mesh.faces[f];
    if (t.minCoeff() < 0 || static_cast<std::size_t>(t.maxCoeff()) >= n) continue;
    out.faces.push_back({keep(t[0]), keep(t[1]), keep(t[2])});
  }
  for (const int c : contacts) {
    if (c >= 0 && static_cast<std::size_t>(c) < n) {
      const Eigen::Vector3d& p = mesh.vertices.positions[c];
      out.contacts.push_back(std::array<float, 3>{float(p.x()), float(p.y()), float(p.z())});
    } else {
      out.contacts.push_back(std::nullopt);
    }
  }
  return out;
}

HtmlReport buildHtmlReport(const HtmlReportInput& input) {
  HtmlReport report;
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
         // The page must work from disk without any network: forbid fetches
         // outright so that a regression shows up as an error, not a request.
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'unsafe-inline' blob:; "
         "style-src 'unsafe-inline'; img-src data: blob:\">\n"
         "<title>"
      << htmlEscape(input.title) << "</title>\n<style>" << kReportCss << "</style>\n<script>" << kReportStatusJs
      << "</script>\n</head>\n<body>\n<header>\n<h1>" << htmlEscape(input.title) << "</h1>\n<p>Run folder: <code>"
      << htmlEscape(input.run_dir) << "</code></p>\n";
  if (!input.generated_by.empty()) out << "<p>" << htmlEscape(input.generated_by) << "</p>\n";
  out << "<p>Reproducing Krug et al., &ldquo;Generation of Independent Contact Regions on Objects Reconstructed from "
         "Noisy Real-World Range Data&rdquo;.</p>\n</header>\n<nav>";
  if (!input.missing.empty()) out << "<a href=\"#missing\">Missing</a>";
  out << "<a href=\"#parameters\">Parameters</a><a href=\"#table1-section\">Table I</a><a href=\"#viewer-section\">3D "
         "viewer</a><a href=\"#eligibility\">Eligibility</a>";
  if (!input.planned_lines.empty()) out << "<a href=\"#planned\">Planned grasps</a>";
  if (!input.surface_lines.empty()) out << "<a href=\"#surface\">Surface accuracy</a>";
  out << "<a href=\"#fig8\">Fig. 8</a><a href=\"#renders\">Renders</a>"
         "</nav>\n<main>\n";

  if (!input.missing.empty()) {
    out << "<section id=\"missing\" class=\"missing\">\n<h2>Missing</h2>\n<p>This run folder lacks the files below; "
           "the parts of the report that need them say so.</p>\n<ul>\n";
    for (const std::string& m : input.missing) out << "<li>" << htmlEscape(m) << "</li>\n";
    out << "</ul>\n</section>\n";
  }
  if (!input.warnings.empty()) {
    out << "<section id=\"warnings\" class=\"warnings\">\n<h2>Warnings</h2>\n<ul>\n";
    for (const std::string& w : input.warnings) out << "<li>" << htmlEscape(w) << "</li>\n";
    out << "</ul>\n</section>\n";
  }
  writeParameters(out, input);
  writeTableOne(out, input);
  writeViewer(out, input, report.sizes);
  writeEligibility(out, input);
  writePlanned(out, input);
  writeSurface(out, input);

  out << "<section id=\"fig8\">\n<h2>Fig. 8: cumulative histograms of Q<sub>n</sub></h2>\n";
  if (input.histograms.empty()) {
    out << "<p class=\"unavailable\">No fig8_&lt;N&gt;fingers.svg in this run folder.</p>\n";
  } else {
    out << "<div class=\"figures\">\n";
    for (const ReportSvg& svg : input.histograms) {
      const std::string inlined = inlineSvg(svg.svg);
      report.sizes.histograms += inlined.size();
      out << "<figure>" << inlined << "<figcaption>" << htmlEscape(svg.name) << "</figcaption></figure>\n";
    }
    out << "</div>\n";
  }
  out << "</section>\n<section id=\"renders\">\n<h2>Renders</h2>\n";
  if (input.renders.empty()) {
    out << "<p class=\"unavailable\">"
        << htmlEscape(input.renders_note.empty() ? "No renders." : input.renders_note) << "</p>\n";
  } else {
    out << "<div class=\"figures\">\n";
    for (const ReportImage& image : input.renders) {
      const std::string data = base64Encode(image.png.data(), image.png.size());
      report.sizes.renders += data.size();
      out << "<figure><img alt=\"" << htmlEscape(image.name) << "\" src=\"data:image/png;base64," << data
          << "\"><figcaption>" << htmlEscape(image.name) << "</figcaption></figure>\n";
    }
    out << "</div>\n";
  }
  out << "</section>\n</main>\n<footer style=\"padding: 0 24px 24px 24px\">\n";
  if (!input.three_version.empty()) {
    out << "<details><summary class=\"note\">three.js " << htmlEscape(input.three_version)
        << " (MIT licence), embedded in this page</summary><pre>"
        << htmlEscape(input.three_license) << "</pre></details>\n";
  }
  out << "<p class=\"note\">Embedded: meshes " << bytesText(report.sizes.meshes) << ", renders "
      << bytesText(report.sizes.renders) << ", three.js " << bytesText(report.sizes.threejs) << ", histograms "
      << bytesText(report.sizes.histograms) << ".</p>\n"
      << "<pre id=\"report-status\">{\"ready\": false}</pre>\n"
      // Classic scripts run before the deferred viewer module: a page without
      // a viewer is ready here; with one, the viewer sets ready after its first frame.
      << "<script>(function () { var r = window.icrkitReport; if (r.viewer !== 'pending') r.ready = true; "
         "if (r.viewer === 'pending' && !document.getElementById('viewer')) { r.viewer = 'none'; r.ready = true; } "
         "r.update(); })();</script>\n</footer>\n</body>\n</html>\n";
  report.html = out.str();
  report.sizes.total = report.html.size();
  return report;
}

}  // namespace icrkit::report
