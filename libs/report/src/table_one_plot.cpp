#include <icrkit/report/table_one_plot.hpp>

#include "xml_escape.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <optional>

namespace icrkit::report {

using eval::PaperTableOneRow;
using eval::TableOne;
using eval::TableOneRow;
using eval::paperTableOneRow;
namespace {

// One layout for both forms: cells of text in a grid, positions in pixels.
struct Cell {
  std::string text;
  int x = 0, y = 0;      // baseline, left (or right, when right_aligned)
  bool right_aligned = false;
  bool bold = false;
  bool grey = false;     // the paper's values
};

struct Layout {
  int width = 0, height = 0;
  std::vector<Cell> cells;
  std::vector<int> rules;  // y of horizontal lines
};

std::string number(const std::optional<double>& value) {
  if (!value) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", *value);
  return buffer;
}

Layout layOut(const TableOne& table) {
  const std::vector<std::string> header{"Dataset", "Grasps", "Smooth Int %", "Smooth FP %", "Raw Int %", "Raw FP %"};
  const std::vector<int> right{0, 300, 430, 550, 660, 770};  // column right edges (first column: left edge 10)
  const int row_height = 24, top = 50;
  Layout layout;
  layout.width = 790;
  layout.cells.push_back({"Table I: medians over all regions, % of the CAD region area (grey: Krug et al.)", 10, 22,
                          false, true, false});
  int y = top;
  for (std::size_t c = 0; c < header.size(); ++c)
    layout.cells.push_back({header[c], c == 0 ? 10 : right[c], y, c != 0, true, false});
  layout.rules.push_back(y + 8);
  y += row_height + 4;
  std::vector<const TableOneRow*> rows;
  for (const TableOneRow& row : table.rows) rows.push_back(&row);
  rows.push_back(&table.average);
  for (const TableOneRow* row : rows) {
    const bool average = row == &table.average;
    if (average) layout.rules.push_back(y - row_height + 8);
    const std::vector<std::string> ours{row->dataset,
                                        std::to_string(row->evaluated_grasps),
                                        number(row->filtered.intersection_percent),
                                        number(row->filtered.false_positive_percent),
                                        number(row->raw.intersection_percent),
                                        number(row->raw.false_positive_percent)};
    for (std::size_t c = 0; c < ours.size(); ++c)
      layout.cells.push_back({ours[c], c == 0 ? 10 : right[c], y, c != 0, average, false});
    y += row_height;
    if (const auto paper = paperTableOneRow(row->dataset)) {
      const std::vector<std::optional<double>> values{paper->filtered_intersection_percent,
                                                      paper->filtered_false_positive_percent,
                                                      paper->raw_intersection_percent,
                                                      paper->raw_false_positive_percent};
      layout.cells.push_back({"  paper", 10, y, false, false, true});
      for (std::size_t c = 0; c < values.size(); ++c) layout.cells.push_back({number(values[c]), right[c + 2], y, true, false, true});
      y += row_height;
    }
  }
  layout.height = y;
  return layout;
}

using detail::xmlEscape;

}  // namespace

std::string tableOneSvg(const TableOne& table) {
  const Layout layout = layOut(table);
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(layout.width) +
                    "\" height=\"" + std::to_string(layout.height) + "\" viewBox=\"0 0 " +
                    std::to_string(layout.width) + " " + std::to_string(layout.height) +
                    "\" font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"13\">\n"
                    "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  for (const int y : layout.rules)
    svg += "<line x1=\"8\" x2=\"" + std::to_string(layout.width - 8) + "\" y1=\"" + std::to_string(y) + "\" y2=\"" +
           std::to_string(y) + "\" stroke=\"#333333\" stroke-width=\"1\"/>\n";
  for (const Cell& cell : layout.cells)
    svg += "<text x=\"" + std::to_string(cell.x) + "\" y=\"" + std::to_string(cell.y) + "\"" +
           (cell.right_aligned ? " text-anchor=\"end\"" : "") + (cell.bold ? " font-weight=\"bold\"" : "") +
           (cell.grey ? " fill=\"#888888\"" : " fill=\"#111111\"") + ">" + xmlEscape(cell.text) + "</text>\n";
  svg += "</svg>\n";
  return svg;
}

std::vector<unsigned char> tableOnePng(const TableOne& table) {
  const Layout layout = layOut(table);
  cv::Mat image(layout.height, layout.width, CV_8UC3, cv::Scalar(255, 255, 255));
  for (const int y : layout.rules)
    cv::line(image, cv::Point(8, y), cv::Point(layout.width - 8, y), cv::Scalar(51, 51, 51), 1, cv::LINE_AA);
  const int face = cv::FONT_HERSHEY_SIMPLEX;
  for (const Cell& cell : layout.cells) {
    const double scale = 0.45;
    const int thickness = cell.bold ? 2 : 1;
    int baseline = 0;
    const cv::Size size = cv::getTextSize(cell.text, face, scale, thickness, &baseline);
    const int x = cell.right_aligned ? cell.x - size.width : cell.x;
    const cv::Scalar colour = cell.grey ? cv::Scalar(136, 136, 136) : cv::Scalar(17, 17, 17);
    cv::putText(image, cell.text, cv::Point(x, cell.y), face, scale, colour, thickness, cv::LINE_AA);
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw InputError("table1.png", "", "PNG encoding failed");
  return png;
}

void writeTableOneSvg(const std::string& path, const TableOne& table) {
  const std::string svg = tableOneSvg(table);
  writeFileAtomically(path, [&](std::ostream& out) { out << svg; }, false);
}

void writeTableOnePng(const std::string& path, const TableOne& table) {
  const std::vector<unsigned char> png = tableOnePng(table);
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

}  // namespace icrkit::report
