// The sensitivity study's table as Markdown and its three-panel plot (SVG, PNG).

#include <icrkit/report/sensitivity_plot.hpp>

#include "xml_escape.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>

namespace icrkit::report {

using eval::SensitivityRow;
using eval::SensitivityTable;

namespace {

std::string percent(const std::optional<double>& v) {
  if (!v) return "–";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", *v);
  return text;
}

}  // namespace

std::string sensitivityMarkdown(const SensitivityTable& t) {
  char head[256];
  std::snprintf(head, sizeof head, "# Sensitivity study: %s, Poisson-disk spacing %.3f mm\n\n", t.object.c_str(),
                t.spacing_m * 1e3);
  std::string md = head;
  md += "Noise: Gaussian along the true normal, sigma = level x spacing. Int / FP: Table I medians in % of the CAD "
        "region's area; eligible: share of the CAD grasps whose transfer meets the task (and, filtered, the "
        "preselection).\n\n";
  md += "| noise (x spacing) | sigma (mm) | rule | grasps | raw eligible | filtered eligible | raw Int | raw FP | "
        "filtered Int | filtered FP | evaluated |\n|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SensitivityRow& r : t.rows) {
    char line[512];
    std::snprintf(line, sizeof line, "| %.2f | %.3f | %s | %zu | %s | %s | %s | %s | %s | %s | %zu |\n",
                  r.noise_level, r.noise_level * t.spacing_m * 1e3, r.rule.c_str(), r.grasps,
                  percent(r.raw_eligible_percent).c_str(), percent(r.filtered_eligible_percent).c_str(),
                  percent(r.raw_intersection_percent).c_str(), percent(r.raw_false_positive_percent).c_str(),
                  percent(r.filtered_intersection_percent).c_str(),
                  percent(r.filtered_false_positive_percent).c_str(), r.evaluated);
    md += line;
  }
  return md;
}

namespace {

// The plot as plain primitives, drawn the same way into SVG and PNG.
struct Stroke {
  std::vector<std::array<double, 2>> points;
  std::array<int, 3> rgb;
  bool dashed = false;
};
struct Label {
  double x, y;
  std::string text;
  bool centred = false;
  std::array<int, 3> rgb{17, 17, 17};
};
struct Plot {
  int width = 0, height = 0;
  std::vector<Stroke> strokes;
  std::vector<Label> labels;
};

constexpr std::array<std::array<int, 3>, 4> kRuleColours{{{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}}};

Plot layOut(const SensitivityTable& t) {
  Plot plot;
  const int panel_w = 300, panel_h = 220, left = 50, top = 40, gap = 40;
  plot.width = left + 3 * panel_w + 2 * gap + 20;
  plot.height = top + panel_h + 70 + 18 * static_cast<int>(t.rules.size() + 1);
  const double max_level = t.noise_levels.empty() ? 1.0 : std::max(1e-9, *std::max_element(t.noise_levels.begin(), t.noise_levels.end()));
  using Getter = std::optional<double> (*)(const SensitivityRow&, bool filtered);
  const std::array<std::pair<const char*, Getter>, 3> panels{{
      {"eligible grasps (%)",
       [](const SensitivityRow& r, bool f) { return f ? r.filtered_eligible_percent : r.raw_eligible_percent; }},
      {"Int: median intersection (%)",
       [](const SensitivityRow& r, bool f) { return f ? r.filtered_intersection_percent : r.raw_intersection_percent; }},
      {"FP: median false positive (%)",
       [](const SensitivityRow& r, bool f) {
         return f ? r.filtered_false_positive_percent : r.raw_false_positive_percent;
       }},
  }};
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const double x0 = left + static_cast<double>(p) * (panel_w + gap), y0 = top;
    const auto at = [&](double level, double value) {
      return std::array<double, 2>{x0 + level / max_level * panel_w, y0 + panel_h - std::min(value, 100.0) / 100.0 * panel_h};
    };
    plot.strokes.push_back({{{x0, y0}, {x0, y0 + panel_h}, {x0 + panel_w, y0 + panel_h}}, {51, 51, 51}});
    for (int v = 0; v <= 100; v += 25) {
      plot.strokes.push_back({{at(0, v), {x0 + panel_w, at(0, v)[1]}}, {221, 221, 221}});
      plot.labels.push_back({x0 - 30, at(0, v)[1] + 4, std::to_string(v)});
    }
    for (const double level : t.noise_levels) {
      char text[16];
      std::snprintf(text, sizeof text, "%.2f", level);
      plot.labels.push_back({at(level, 0)[0], y0 + panel_h + 16, text, true});
    }
    plot.labels.push_back({x0 + panel_w / 2.0, y0 - 12, panels[p].first, true});
    plot.labels.push_back({x0 + panel_w / 2.0, y0 + panel_h + 34, "noise sigma (x spacing)", true});
    // Raw: the same mesh for every rule, drawn from the first rule's rows.
    for (int filtered = 0; filtered <= 1; ++filtered) {
      for (std::size_t r = 0; r < (filtered ? t.rules.size() : std::min<std::size_t>(1, t.rules.size())); ++r) {
        Stroke line{{}, filtered ? kRuleColours[r % kRuleColours.size()] : std::array<int, 3>{17, 17, 17}, !filtered};
        for (const SensitivityRow& row : t.rows)
          if (row.rule == t.rules[r])
            if (const auto v = panels[p].second(row, filtered != 0)) line.points.push_back(at(row.noise_level, *v));
        if (!line.points.empty()) plot.strokes.push_back(line);
      }
    }
  }
  double y = top + panel_h + 58;
  plot.labels.push_back({static_cast<double>(left), y, "- - raw mesh (normals estimated), black"});
  for (std::size_t r = 0; r < t.rules.size(); ++r) {
    y += 18;
    plot.labels.push_back({static_cast<double>(left), y, "--- filtered mesh, preselection " + t.rules[r], false,
                           kRuleColours[r % kRuleColours.size()]});
  }
  char title[256];
  std::snprintf(title, sizeof title, "%s: noise sensitivity (Poisson-disk spacing %.2f mm)", t.object.c_str(),
                t.spacing_m * 1e3);
  plot.labels.push_back({plot.width / 2.0, 16, title, true});
  return plot;
}

std::string rgbText(const std::array<int, 3>& c) {
  char text[16];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", c[0], c[1], c[2]);
  return text;
}

using detail::xmlEscape;

}  // namespace

std::string sensitivitySvg(const SensitivityTable& table) {
  const Plot plot = layOut(table);
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(plot.width) + "\" height=\"" +
                    std::to_string(plot.height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n" +
                    "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  char number[64];
  for (const Stroke& s : plot.strokes) {
    svg += "<polyline fill=\"none\" stroke=\"" + rgbText(s.rgb) + "\" stroke-width=\"" + (s.rgb[0] == 221 ? "1" : "2") +
           "\"" + (s.dashed ? " stroke-dasharray=\"6,4\"" : "") + " points=\"";
    for (const auto& p : s.points) {
      std::snprintf(number, sizeof number, "%.1f,%.1f ", p[0], p[1]);
      svg += number;
    }
    svg += "\"/>\n";
  }
  for (const Label& l : plot.labels) {
    std::snprintf(number, sizeof number, "x=\"%.1f\" y=\"%.1f\"", l.x, l.y);
    svg += std::string("<text ") + number + (l.centred ? " text-anchor=\"middle\"" : "") + " fill=\"" + rgbText(l.rgb) +
           "\">" + xmlEscape(l.text) + "</text>\n";
  }
  return svg + "</svg>\n";
}

std::vector<unsigned char> sensitivityPng(const SensitivityTable& table) {
  const Plot plot = layOut(table);
  cv::Mat image(plot.height, plot.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto bgr = [](const std::array<int, 3>& c) { return cv::Scalar(c[2], c[1], c[0]); };
  for (const Stroke& s : plot.strokes)
    for (std::size_t i = 1; i < s.points.size(); ++i) {
      const cv::Point2d a(s.points[i - 1][0], s.points[i - 1][1]), b(s.points[i][0], s.points[i][1]);
      const int thickness = s.rgb[0] == 221 ? 1 : 2;
      if (!s.dashed) {
        cv::line(image, a, b, bgr(s.rgb), thickness, cv::LINE_AA);
        continue;
      }
      const double length = cv::norm(b - a);
      for (double t = 0; t < length; t += 10) {
        const double u = std::min(t + 6, length);
        cv::line(image, a + (b - a) * (t / length), a + (b - a) * (u / length), bgr(s.rgb), thickness, cv::LINE_AA);
      }
    }
  for (const Label& l : plot.labels) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(l.text, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &baseline);
    const double x = l.centred ? l.x - size.width / 2.0 : l.x;
    cv::putText(image, l.text, cv::Point2d(x, l.y), cv::FONT_HERSHEY_SIMPLEX, 0.4, bgr(l.rgb), 1, cv::LINE_AA);
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw InputError("sensitivity.png", "", "PNG encoding failed");
  return png;
}

std::vector<std::string> writeSensitivityOutputs(const std::string& directory, const SensitivityTable& table) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  const auto write = [&](const std::string& name, const std::string& text) {
    files.push_back((fs::path(directory) / name).string());
    writeFileAtomically(files.back(), [&](std::ostream& out) { out << text; }, false);
  };
  write("sensitivity.md", sensitivityMarkdown(table));
  write("sensitivity.json", eval::sensitivityJson(table) + "\n");
  write("sensitivity.svg", sensitivitySvg(table));
  const std::vector<unsigned char> png = sensitivityPng(table);
  files.push_back((fs::path(directory) / "sensitivity.png").string());
  writeFileAtomically(
      files.back(), [&](std::ostream& out) { out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size())); },
      true);
  return files;
}

}  // namespace icrkit::report
