#include <icrkit/report/quality_plot.hpp>

#include "xml_escape.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/number_text.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace icrkit::report {
namespace {

using eval::QualityHistogram;
using eval::QualityHistogramSeries;

// ---------------------------------------------------------------------------
// The plot as a list of primitives, laid out once and drawn by both the SVG
// and the OpenCV renderer, so that the two files show the same figure.

struct Colour {
  unsigned char r = 0, g = 0, b = 0;
};

Colour parseColour(const std::string& text) {
  auto hex = [&](std::size_t at) {
    unsigned value = 0;
    const auto result = std::from_chars(text.data() + at, text.data() + at + 2, value, 16);
    if (result.ec != std::errc() || result.ptr != text.data() + at + 2)
      throw InputError("plot colour", "", "expected #rrggbb, got \"" + text + "\"");
    return static_cast<unsigned char>(value);
  };
  if (text.size() != 7 || text[0] != '#') throw InputError("plot colour", "", "expected #rrggbb, got \"" + text + "\"");
  return Colour{hex(1), hex(3), hex(5)};
}

std::string colourText(const Colour& c) {
  static const char* digits = "0123456789abcdef";
  std::string out = "#";
  for (unsigned char v : {c.r, c.g, c.b}) {
    out += digits[v >> 4];
    out += digits[v & 15];
  }
  return out;
}

struct Rect {
  double x0, y0, x1, y1;
  Colour fill;
  std::string tooltip;  // SVG only
};

struct Line {
  double x0, y0, x1, y1;
  Colour colour;
  double width;
  bool behind;  // grid lines: drawn under the bars
};

enum class Anchor { start, middle, end };

struct Text {
  double x, y;  // baseline point; for vertical text the baseline runs upwards through (x, y)
  std::string text;
  double size;  // pixels
  Anchor anchor;
  bool vertical;
  bool bold;
};

struct Scene {
  int width = 0, height = 0;
  std::string title;
  std::vector<Rect> rects;
  std::vector<Line> lines;
  std::vector<Text> texts;
};

const Colour kBlack{0, 0, 0};
const Colour kGrid{221, 221, 221};

std::string seriesLegend(const char* name, const QualityHistogramSeries& series) {
  std::string text = std::string(name) + " (n = " + std::to_string(series.regions);
  if (series.undefined > 0) text += ", " + std::to_string(series.undefined) + " undefined";
  return text + ")";
}

Scene layOut(const QualityHistogram& histogram, const QualityPlotOptions& options) {
  if (options.width < 320 || options.height < 240)
    throw InputError("plot size", "", "expected at least 320 x 240 pixels");
  Scene scene;
  scene.width = options.width;
  scene.height = options.height;
  scene.title = qualityPlotTitle(histogram, options);
  const Colour rawColour = parseColour(options.raw_colour);
  const Colour filteredColour = parseColour(options.filtered_colour);

  // Legend between title and plot, so that it can never hide a bar: on one
  // line when both entries fit (widths estimated generously, as the SVG
  // viewer's font is unknown), otherwise one entry per line.
  const double legendSize = 13, swatch = 12, charWidth = 0.62 * legendSize;
  const std::string rawLegend = seriesLegend("raw mesh", histogram.raw);
  const std::string filteredLegend = seriesLegend("filtered mesh", histogram.filtered);
  const double left = 64, right = options.width - 16.0;
  const double legendX = left + 8;
  const double rawEnd = legendX + swatch + 6 + charWidth * double(rawLegend.size());
  const double oneLineX = std::max(left + (right - left) / 2.0, rawEnd + 24);
  const bool oneLine = oneLineX + swatch + 6 + charWidth * double(filteredLegend.size()) <= options.width;
  const double legendY = 52, secondX = oneLine ? oneLineX : legendX, secondY = oneLine ? legendY : legendY + 18;
  const double top = secondY + 20, bottom = options.height - 56.0;
  const double plotHeight = bottom - top;
  auto yOf = [&](double percent) { return bottom - plotHeight * std::clamp(percent, 0.0, 100.0) / 100.0; };

  scene.texts.push_back({options.width / 2.0, 28, scene.title, 18, Anchor::middle, false, true});
  scene.rects.push_back({legendX, legendY - swatch + 1, legendX + swatch, legendY + 1, rawColour, ""});
  scene.texts.push_back({legendX + swatch + 6, legendY, rawLegend, legendSize, Anchor::start, false, false});
  scene.rects.push_back({secondX, secondY - swatch + 1, secondX + swatch, secondY + 1, filteredColour, ""});
  scene.texts.push_back({secondX + swatch + 6, secondY, filteredLegend, legendSize, Anchor::start, false, false});

  for (int percent = 0; percent <= 100; percent += 20) {
    const double y = yOf(percent);
    if (percent > 0) scene.lines.push_back({left, y, right, y, kGrid, 1, true});
    scene.lines.push_back({left - 5, y, left, y, kBlack, 1, false});
    scene.texts.push_back({left - 8, y + 4, std::to_string(percent), 12, Anchor::end, false, false});
  }

  const std::size_t bars = histogram.labels.size();
  const double groupWidth = (right - left) / double(std::max<std::size_t>(bars, 1));
  const double barWidth = groupWidth * 0.36;
  for (std::size_t i = 0; i < bars; ++i) {
    const double center = left + groupWidth * (double(i) + 0.5);
    const std::string condition = i + 1 < bars ? "Q_n >= " + histogram.labels[i] : std::string("Q_n < 0");
    auto bar = [&](const QualityHistogramSeries& series, const char* name, double x0, const Colour& colour) {
      if (i >= series.percent.size()) return;
      const std::string tooltip = std::string(name) + ", " + condition + ": " + formatFixed(series.percent[i], 1) +
                                  " % (" + std::to_string(series.counts[i]) + " of " +
                                  std::to_string(series.regions) + ")";
      scene.rects.push_back({x0, yOf(series.percent[i]), x0 + barWidth, bottom, colour, tooltip});
    };
    bar(histogram.raw, "raw mesh", center - barWidth - 1, rawColour);
    bar(histogram.filtered, "filtered mesh", center + 1, filteredColour);
    scene.lines.push_back({center, bottom, center, bottom + 5, kBlack, 1, false});
    scene.texts.push_back({center, bottom + 19, histogram.labels[i], 12, Anchor::middle, false, false});
  }

  scene.lines.push_back({left, top, left, bottom, kBlack, 1, false});
  scene.lines.push_back({left, bottom, right, bottom, kBlack, 1, false});
  scene.texts.push_back({(left + right) / 2.0, options.height - 14.0,
                         "threshold t: Q_n >= t (last bar: Q_n < 0)", 13, Anchor::middle, false, false});
  scene.texts.push_back({20, (top + bottom) / 2.0, "regions [%]", 13, Anchor::middle, true, false});
  return scene;
}

using detail::xmlEscape;

std::string num(double value) { return formatFixed(value, 2); }

std::string renderSvg(const Scene& scene) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << scene.width << "\" height=\"" << scene.height
      << "\" viewBox=\"0 0 " << scene.width << ' ' << scene.height << "\">\n";
  out << "<title>" << xmlEscape(scene.title) << "</title>\n";
  out << "<rect x=\"0\" y=\"0\" width=\"" << scene.width << "\" height=\"" << scene.height
      << "\" fill=\"#ffffff\"/>\n";
  // Grid and ticks first, bars over them, axes and text on top.
  out << "<g shape-rendering=\"crispEdges\">\n";
  for (const auto& line : scene.lines)
    if (line.behind)
      out << "<line x1=\"" << num(line.x0) << "\" y1=\"" << num(line.y0) << "\" x2=\"" << num(line.x1) << "\" y2=\""
          << num(line.y1) << "\" stroke=\"" << colourText(line.colour) << "\" stroke-width=\"" << num(line.width)
          << "\"/>\n";
  for (const auto& rect : scene.rects) {
    out << "<rect x=\"" << num(rect.x0) << "\" y=\"" << num(rect.y0) << "\" width=\"" << num(rect.x1 - rect.x0)
        << "\" height=\"" << num(rect.y1 - rect.y0) << "\" fill=\"" << colourText(rect.fill) << '"';
    if (rect.tooltip.empty()) out << "/>\n";
    else out << "><title>" << xmlEscape(rect.tooltip) << "</title></rect>\n";
  }
  for (const auto& line : scene.lines)
    if (!line.behind)
      out << "<line x1=\"" << num(line.x0) << "\" y1=\"" << num(line.y0) << "\" x2=\"" << num(line.x1) << "\" y2=\""
          << num(line.y1) << "\" stroke=\"" << colourText(line.colour) << "\" stroke-width=\"" << num(line.width)
          << "\"/>\n";
  out << "</g>\n";
  out << "<g font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\" fill=\"#000000\">\n";
  for (const auto& text : scene.texts) {
    const char* anchor = text.anchor == Anchor::start ? "start" : text.anchor == Anchor::middle ? "middle" : "end";
    out << "<text x=\"" << num(text.x) << "\" y=\"" << num(text.y) << "\" font-size=\"" << num(text.size)
        << "\" text-anchor=\"" << anchor << '"';
    if (text.bold) out << " font-weight=\"bold\"";
    if (text.vertical) out << " transform=\"rotate(-90 " << num(text.x) << ' ' << num(text.y) << ")\"";
    out << '>' << xmlEscape(text.text) << "</text>\n";
  }
  out << "</g>\n</svg>\n";
  return out.str();
}

cv::Scalar bgr(const Colour& c) { return cv::Scalar(c.b, c.g, c.r); }
int px(double v) { return int(std::lround(v)); }

// Hershey fonts are about 30 px per unit scale in cap-plus-descender height;
// this keeps the raster text close to the SVG's pixel sizes.
double fontScale(double sizePx) { return sizePx / 30.0; }

void drawText(cv::Mat& image, const Text& text) {
  const int face = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = fontScale(text.size);
  const int thickness = text.bold ? 2 : 1;
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text.text, face, scale, thickness, &baseline);
  const double shift = text.anchor == Anchor::start ? 0.0 : text.anchor == Anchor::middle ? size.width / 2.0 : size.width;
  if (!text.vertical) {
    cv::putText(image, text.text, cv::Point(px(text.x - shift), px(text.y)), face, scale, bgr(kBlack), thickness, cv::LINE_AA);
    return;
  }
  // Draw horizontally on a white strip, turn it a quarter counter-clockwise,
  // and paste it so that its baseline runs upwards through (x, y).
  cv::Mat strip(size.height + baseline + 2, size.width + 2, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(strip, text.text, cv::Point(1, size.height + 1), face, scale, bgr(kBlack), thickness, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int x0 = px(text.x) - (size.height + 1);
  const int y0 = px(text.y - (size.width - shift));
  const cv::Rect target = cv::Rect(x0, y0, turned.cols, turned.rows) & cv::Rect(0, 0, image.cols, image.rows);
  if (target.area() <= 0) return;
  turned(cv::Rect(target.x - x0, target.y - y0, target.width, target.height)).copyTo(image(target));
}

cv::Mat renderRaster(const Scene& scene) {
  cv::Mat image(scene.height, scene.width, CV_8UC3, cv::Scalar(255, 255, 255));
  for (const auto& line : scene.lines)
    if (line.behind)
      cv::line(image, cv::Point(px(line.x0), px(line.y0)), cv::Point(px(line.x1), px(line.y1)), bgr(line.colour),
               std::max(1, px(line.width)));
  for (const auto& rect : scene.rects) {
    // cv::rectangle includes both corners; the SVG rect ends before x1/y1.
    const cv::Point a(px(rect.x0), px(rect.y0)), b(px(rect.x1) - 1, px(rect.y1) - 1);
    if (b.x >= a.x && b.y >= a.y) cv::rectangle(image, a, b, bgr(rect.fill), cv::FILLED);
  }
  for (const auto& line : scene.lines)
    if (!line.behind)
      cv::line(image, cv::Point(px(line.x0), px(line.y0)), cv::Point(px(line.x1), px(line.y1)), bgr(line.colour),
               std::max(1, px(line.width)));
  for (const auto& text : scene.texts) drawText(image, text);
  return image;
}

}  // namespace

std::string qualityPlotTitle(const QualityHistogram& histogram, const QualityPlotOptions& options) {
  if (!options.title.empty()) return options.title;
  if (histogram.fingers == 0) return "Cumulative Q_n, all grasps";
  return "Cumulative Q_n, " + std::to_string(histogram.fingers) + (histogram.fingers == 1 ? " finger" : " fingers");
}

std::string qualityHistogramSvg(const QualityHistogram& histogram, const QualityPlotOptions& options) {
  return renderSvg(layOut(histogram, options));
}

std::vector<unsigned char> qualityHistogramPng(const QualityHistogram& histogram, const QualityPlotOptions& options) {
  const cv::Mat image = renderRaster(layOut(histogram, options));
  std::vector<unsigned char> png;
  // Fixed compression settings: the bytes depend only on the pixels.
  if (!cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 6}))
    throw std::runtime_error("PNG encoding of the quality histogram failed");
  return png;
}

void writeQualityHistogramSvg(const std::string& path, const QualityHistogram& histogram,
                              const QualityPlotOptions& options) {
  writeFileAtomically(path, qualityHistogramSvg(histogram, options));
}

void writeQualityHistogramPng(const std::string& path, const QualityHistogram& histogram,
                              const QualityPlotOptions& options) {
  const std::vector<unsigned char> png = qualityHistogramPng(histogram, options);
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
}

}  // namespace icrkit::report
