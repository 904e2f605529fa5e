#pragma once
// Helpers shared by the core tests.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace icrkit::test {

/// Path of a file in the shared real-data directory.
inline std::string sharedData(const std::string& relative) {
  return std::string(ICRKIT_SHARED_DATA_DIR) + "/" + relative;
}

/// A fresh scratch directory, removed with the object.
class ScratchDir {
public:
  ScratchDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("icrkit_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

}  // namespace icrkit::test

/// Skips the current test when a shared data file is absent.
#define ICRKIT_REQUIRE_SHARED_FILE(path)                                                          \
  do {                                                                                            \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared test data not found: " << (path); \
  } while (0)
