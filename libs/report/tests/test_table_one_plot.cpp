// Table I as SVG and PNG.

#include <icrkit/report/table_one_plot.hpp>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

namespace icrkit::report {
namespace {

using namespace icrkit::eval;

TableOne sampleTable() {
  TableOne table;
  TableOneRow row;
  row.dataset = "cup_kinect_B";
  row.evaluated_grasps = 12;
  row.filtered.intersection_percent = 61.26;
  row.filtered.false_positive_percent = 3.5;
  row.raw.intersection_percent = 14.0;
  table.rows.push_back(row);
  row.dataset = "my_object";  // not one of the paper's
  table.rows.push_back(row);
  table.average = row;
  table.average.dataset = "Average";
  return table;
}

TEST(TableOnePlot, SvgHoldsOursAndThePapersValues) {
  const std::string svg = tableOneSvg(sampleTable());
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find(">cup_kinect_B<"), std::string::npos);
  EXPECT_NE(svg.find(">61.3<"), std::string::npos);  // ours, one decimal
  EXPECT_NE(svg.find(">62.0<"), std::string::npos);  // the paper's Kinect cup
  EXPECT_NE(svg.find(">59.0<"), std::string::npos);  // the paper's average
  EXPECT_NE(svg.find(">-<"), std::string::npos);     // raw FP unset
  // Two paper lines: the cup and the Average; none for my_object.
  std::size_t paper_lines = 0;
  for (std::size_t at = svg.find(">  paper<"); at != std::string::npos; at = svg.find(">  paper<", at + 1)) ++paper_lines;
  EXPECT_EQ(paper_lines, 2u);
}

TEST(TableOnePlot, PngDecodesAndIsNotBlank) {
  const std::vector<unsigned char> png = tableOnePng(sampleTable());
  const cv::Mat image = cv::imdecode(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 790);
  cv::Scalar mean, deviation;
  cv::meanStdDev(image, mean, deviation);
  EXPECT_GT(deviation[0], 10.0);
}

}  // namespace
}  // namespace icrkit::report
