// Recordings and their side files: the readers `icrkit reconstruct` and
// `icrkit calibrate` open, each through a file as they get it.
#include "fuzz_targets.hpp"
#include "temp_input.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

namespace icrkit::fuzz {

void fuzzRawlog(const std::uint8_t* data, std::size_t size) {
  // Plain and gzip streams alike (the reader tells them apart itself).
  readThroughFile(data, size, ".rawlog", [](const std::string& path) {
    reconstruction::RawlogReader reader(path);
    // A bounded number of scans: a seed holds one or two.
    for (int i = 0; i < 8; ++i)
      if (!reader.next()) break;
  });
}

void fuzzTumDepthList(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".txt", [](const std::string& path) { reconstruction::readDepthList(path); });
}

void fuzzTumPoses(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".txt", [](const std::string& path) { readTumTrajectory(path); });
}

void fuzzCameraJson(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".json", [](const std::string& path) { reconstruction::readDepthCameraFile(path); });
}

void fuzzRangeModelJson(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".json", [](const std::string& path) { reconstruction::readRangeErrorModel(path); });
}

}  // namespace icrkit::fuzz
