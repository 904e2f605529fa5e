#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/progress.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

using namespace icrkit;

TEST(Elapsed, CountsMillisecondsOfTheSteadyClock) {
  const auto start = std::chrono::steady_clock::now();
  // sleep_for waits at least as long as asked, on the steady clock.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double first = millisecondsSince(start);
  EXPECT_GE(first, 20.0);
  EXPECT_GE(millisecondsSince(start), first) << "a later reading is never smaller";
  EXPECT_GE(millisecondsSince(std::chrono::steady_clock::now()), 0.0);
}

TEST(ReportProgress, ReachesAGivenCallbackAndIsSilentWithout) {
  std::vector<std::string> heard;
  const ProgressCallback listener = [&](const std::string& stage, std::size_t done, std::size_t total) {
    heard.push_back(stage + " " + std::to_string(done) + "/" + std::to_string(total));
  };
  reportProgress(listener, "fusion", 3, 18);
  reportProgress(listener, "normals", 0, 0);
  EXPECT_EQ(heard, (std::vector<std::string>{"fusion 3/18", "normals 0/0"}));
  EXPECT_NO_THROW(reportProgress(ProgressCallback{}, "fusion", 1, 2)) << "an empty callback is not called";
}
