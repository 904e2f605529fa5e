#include <icrkit/eval/quality_histogram.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/report/quality_plot.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>

namespace icrkit::eval {
namespace {

MeshOutcome meshWithQualities(const std::vector<std::optional<double>>& qualities) {
  MeshOutcome mesh;
  mesh.task_fulfilled = true;
  for (const auto& q : qualities) {
    RegionComparison region;
    region.quality = q;
    mesh.regions.push_back(region);
  }
  return mesh;
}

GraspRecord grasp(const std::string& dataset, std::size_t fingers, bool evaluated,
                  const std::vector<std::optional<double>>& raw, const std::vector<std::optional<double>>& filtered) {
  GraspRecord record;
  record.dataset = dataset;
  record.fingers = fingers;
  record.raw = meshWithQualities(raw);
  record.filtered = meshWithQualities(filtered);
  record.evaluated = evaluated;
  return record;
}

/// Raw: 1.2, 1.0, 0.95, 0.5, 0.0, -0.3 and one undefined; filtered: 0.7, 0.65, 0.3, 0.1
/// (over two datasets), plus grasps that must not count.
std::vector<GraspRecord> handMadeRecords() {
  return {
      grasp("a", 4, true, {1.2, 1.0, 0.95, std::nullopt}, {0.7, 0.65}),
      grasp("b", 4, true, {0.5, 0.0, -0.3}, {0.3, 0.1}),
      grasp("a", 5, true, {-5.0, -5.0}, {2.0}),
      grasp("b", 4, false, {-5.0}, {-5.0}),
  };
}

/// A small well-formedness check: every tag closes in order, attributes are
/// quoted, and '&' only starts an entity.
void expectWellFormedXml(const std::string& xml) {
  std::vector<std::string> open;
  std::size_t pos = 0;
  bool sawRoot = false;
  while ((pos = xml.find('<', pos)) != std::string::npos) {
    const std::size_t end = xml.find('>', pos);
    ASSERT_NE(end, std::string::npos) << "unterminated tag at " << pos;
    const std::string tag = xml.substr(pos + 1, end - pos - 1);
    ASSERT_FALSE(tag.empty());
    ASSERT_EQ(tag.find('<'), std::string::npos) << "'<' inside a tag at " << pos;
    std::size_t quotes = 0;
    for (char c : tag) quotes += c == '"';
    EXPECT_EQ(quotes % 2, 0u) << tag;
    if (tag[0] == '?') {
      EXPECT_EQ(tag.back(), '?');
    } else if (tag[0] == '/') {
      ASSERT_FALSE(open.empty()) << "stray </" << tag << ">";
      EXPECT_EQ(tag.substr(1), open.back());
      open.pop_back();
    } else {
      const std::string name = tag.substr(0, tag.find_first_of(" \t\n/"));
      if (!sawRoot) {
        EXPECT_EQ(name, "svg");
      }
      sawRoot = true;
      if (tag.back() != '/') open.push_back(name);
    }
    pos = end + 1;
  }
  EXPECT_TRUE(open.empty()) << open.size() << " unclosed tags, innermost " << (open.empty() ? "" : open.back());
  for (std::size_t amp = xml.find('&'); amp != std::string::npos; amp = xml.find('&', amp + 1)) {
    const std::string rest = xml.substr(amp, 6);
    EXPECT_TRUE(rest.rfind("&lt;", 0) == 0 || rest.rfind("&gt;", 0) == 0 || rest.rfind("&amp;", 0) == 0 ||
                rest.rfind("&quot;", 0) == 0 || rest.rfind("&apos;", 0) == 0)
        << rest;
  }
}

TEST(QualityHistogram, HandMadeCounts) {
  const QualityHistogram h = cumulativeQualityHistogram(handMadeRecords(), 4);
  EXPECT_EQ(h.fingers, 4u);
  EXPECT_EQ(h.evaluated_grasps, 2u);
  ASSERT_EQ(h.thresholds.size(), 11u);
  EXPECT_EQ(h.thresholds.front(), 1.0);
  EXPECT_EQ(h.thresholds[3], 0.7);
  EXPECT_EQ(h.thresholds.back(), 0.0);
  const std::vector<std::string> labels = {"1.0", "0.9", "0.8", "0.7", "0.6", "0.5",
                                           "0.4", "0.3", "0.2", "0.1", "0.0", "<0"};
  EXPECT_EQ(h.labels, labels);

  EXPECT_EQ(h.raw.regions, 6u);
  EXPECT_EQ(h.raw.undefined, 1u);
  const std::vector<std::size_t> raw = {2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 5, 1};
  EXPECT_EQ(h.raw.counts, raw);
  ASSERT_EQ(h.raw.percent.size(), 12u);
  EXPECT_DOUBLE_EQ(h.raw.percent[0], 100.0 * 2 / 6);
  EXPECT_DOUBLE_EQ(h.raw.percent[10] + h.raw.percent[11], 100.0);

  EXPECT_EQ(h.filtered.regions, 4u);
  EXPECT_EQ(h.filtered.undefined, 0u);
  // Q_n exactly at a threshold (0.7, 0.3, 0.1) counts for it.
  const std::vector<std::size_t> filtered = {0, 0, 0, 1, 2, 2, 2, 3, 3, 4, 4, 0};
  EXPECT_EQ(h.filtered.counts, filtered);
  EXPECT_DOUBLE_EQ(h.filtered.percent[3], 25.0);
  EXPECT_DOUBLE_EQ(h.filtered.percent[10], 100.0);

  const QualityHistogram all = cumulativeQualityHistogram(handMadeRecords(), 0);
  EXPECT_EQ(all.evaluated_grasps, 3u);
  EXPECT_EQ(all.raw.regions, 8u);
  EXPECT_EQ(all.raw.counts.back(), 3u);
  EXPECT_EQ(all.filtered.counts.front(), 1u);

  const QualityHistogram none = cumulativeQualityHistogram({}, 4);
  EXPECT_EQ(none.raw.regions, 0u);
  EXPECT_EQ(none.raw.percent, std::vector<double>(12, 0.0));
}

TEST(QualityHistogram, JsonCarriesTheNumbers) {
  const auto j = nlohmann::json::parse(qualityHistogramJson(cumulativeQualityHistogram(handMadeRecords(), 4)));
  EXPECT_EQ(j["fingers"].get<int>(), 4);
  EXPECT_EQ(j["labels"].size(), 12u);
  EXPECT_EQ(j["raw"]["undefined"].get<int>(), 1);
  EXPECT_EQ(j["filtered"]["counts"][3].get<int>(), 1);
  EXPECT_DOUBLE_EQ(j["filtered"]["percent"][10].get<double>(), 100.0);
}

TEST(QualityHistogram, SvgIsWellFormedWithTitleLegendAndBars) {
  const QualityHistogram h = cumulativeQualityHistogram(handMadeRecords(), 4);
  const std::string svg = report::qualityHistogramSvg(h);
  expectWellFormedXml(svg);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("Cumulative Q_n, 4 fingers"), std::string::npos);
  EXPECT_NE(svg.find("raw mesh (n = 6, 1 undefined)"), std::string::npos);
  EXPECT_NE(svg.find("filtered mesh (n = 4)"), std::string::npos);
  EXPECT_NE(svg.find(">&lt;0</text>"), std::string::npos);
  EXPECT_NE(svg.find(">1.0</text>"), std::string::npos);
  EXPECT_NE(svg.find("fill=\"#e6550d\""), std::string::npos);
  EXPECT_NE(svg.find("fill=\"#3182bd\""), std::string::npos);
  EXPECT_NE(svg.find("Q_n &gt;= 0.7: 25.0 % (1 of 4)"), std::string::npos);
  EXPECT_EQ(report::qualityHistogramSvg(h), svg) << "deterministic";

  report::QualityPlotOptions options;
  options.title = "Ampersand & <angle>";
  const std::string custom = report::qualityHistogramSvg(h, options);
  expectWellFormedXml(custom);
  EXPECT_NE(custom.find("Ampersand &amp; &lt;angle&gt;"), std::string::npos);

  options.raw_colour = "red";
  EXPECT_THROW(report::qualityHistogramSvg(h, options), InputError);
}

TEST(QualityHistogram, PngDecodesToThePlot) {
  test::ScratchDir scratch;
  const QualityHistogram h = cumulativeQualityHistogram(handMadeRecords(), 4);
  const std::string path = scratch.file("fig8_4fingers.png");
  report::writeQualityHistogramPng(path, h);
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  const report::QualityPlotOptions defaults;
  EXPECT_EQ(image.cols, defaults.width);
  EXPECT_EQ(image.rows, defaults.height);

  std::size_t rawPixels = 0, filteredPixels = 0, darkPixels = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);  // BGR
      if (p == cv::Vec3b(0x0d, 0x55, 0xe6)) ++rawPixels;
      if (p == cv::Vec3b(0xbd, 0x82, 0x31)) ++filteredPixels;
      if (p[0] < 64 && p[1] < 64 && p[2] < 64) ++darkPixels;
    }
  EXPECT_GT(rawPixels, 1000u);
  EXPECT_GT(filteredPixels, 1000u);
  EXPECT_GT(darkPixels, 500u);  // axes, ticks and text

  // Same bytes from the encoder and the file, every time.
  const std::vector<unsigned char> png = report::qualityHistogramPng(h);
  const std::string file = test::readWholeFile(path);
  EXPECT_EQ(std::string(png.begin(), png.end()), file);
  EXPECT_EQ(report::qualityHistogramPng(h), png);

  report::QualityPlotOptions small;
  small.width = 400;
  small.height = 300;
  const cv::Mat smallImage = cv::imdecode(report::qualityHistogramPng(h, small), cv::IMREAD_COLOR);
  EXPECT_EQ(smallImage.cols, 400);
  EXPECT_EQ(smallImage.rows, 300);
}

TEST(QualityHistogram, WritesSvgAndJsonFiles) {
  test::ScratchDir scratch;
  const QualityHistogram h = cumulativeQualityHistogram(handMadeRecords(), 5);
  report::writeQualityHistogramSvg(scratch.file("fig8_5fingers.svg"), h);
  writeQualityHistogramJson(scratch.file("fig8_5fingers.json"), h);
  const std::string svg = test::readWholeFile(scratch.file("fig8_5fingers.svg"));
  EXPECT_NE(svg.find("Cumulative Q_n, 5 fingers"), std::string::npos);
  EXPECT_EQ(svg, report::qualityHistogramSvg(h));
  EXPECT_EQ(nlohmann::json::parse(test::readWholeFile(scratch.file("fig8_5fingers.json")))["raw"]["counts"].back().get<int>(), 2);
}

}  // namespace
}  // namespace icrkit::eval
