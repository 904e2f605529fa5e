#include <icrkit/core/error.hpp>
#include <icrkit/report/run_report.hpp>

#include <gtest/gtest.h>

#include <test_support.hpp>

#include <algorithm>

namespace icrkit::report {
namespace {

bool mentions(const std::vector<std::string>& list, const std::string& text) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& s) { return s.find(text) != std::string::npos; });
}

TEST(RunReport, NoRunFolderIsAnInputError) {
  test::ScratchDir scratch;
  EXPECT_THROW(buildRunReport(scratch.file("absent")), InputError);
  { std::ofstream(scratch.file("file")) << "x"; }
  EXPECT_THROW(buildRunReport(scratch.file("file")), InputError);
}

TEST(RunReport, AnEmptyRunFolderStillGivesAPageThatListsWhatIsMissing) {
  test::ScratchDir scratch;
  const RunReport run = buildRunReport(scratch.path().string());
  EXPECT_TRUE(mentions(run.missing, "run.json")) << run.missing.size();
  EXPECT_TRUE(mentions(run.missing, "grasps.jsonl"));
  EXPECT_TRUE(run.dataset.empty());
  EXPECT_FALSE(run.grasp.has_value());
  EXPECT_FALSE(run.meshes.has_value());
  EXPECT_EQ(run.renders, 0u);
  EXPECT_NE(run.page.html.find("<html"), std::string::npos);
  EXPECT_NE(run.page.html.find("run.json"), std::string::npos) << "the page names the missing file";
}

TEST(RunReport, AMalformedGraspNamesTheOptionsField) {
  test::ScratchDir scratch;
  RunReportOptions options;
  options.grasp = "cup/four/0";
  try {
    buildRunReport(scratch.path().string(), options);
    FAIL() << "accepted " << options.grasp;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "RunReportOptions::grasp");
    EXPECT_NE(error.detail().find("DATASET/FINGERS/INDEX"), std::string::npos);
  }
}

}  // namespace
}  // namespace icrkit::report
