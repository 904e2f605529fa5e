// The page's CSS and JavaScript are embedded at build time
// (cmake/icrkitEmbedFiles.cmake): the arrays must hold the files' bytes, all of
// them (UTF-8 included) and nothing else.
#include "report_assets.hpp"

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <string>

namespace icrkit::report {
namespace {

std::string asset(const std::string& name) {
  return test::readWholeFile(std::string(ICRKIT_SOURCE_DIR) + "/libs/report/assets/" + name);
}

TEST(ReportAssets, EmbeddedBytesEqualTheFiles) {
  for (const auto& [name, embedded] : {std::pair<std::string, const char*>{"report.css", kReportCss},
                                       {"report_status.js", kReportStatusJs},
                                       {"report_viewer.js", kReportViewerJs}}) {
    const std::string file = asset(name);
    ASSERT_FALSE(file.empty()) << name;
    EXPECT_EQ(std::string(embedded), file) << name;
  }
}

}  // namespace
}  // namespace icrkit::report
