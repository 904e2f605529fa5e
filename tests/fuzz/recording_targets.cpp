// Recordings and their side files: the readers `icrkit reconstruct` and
// `icrkit calibrate` open, each through a file as they get it.
#include "fuzz_targets.hpp"
#include "temp_input.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>
#include <icrkit/reconstruction/input/mcap_reader.hpp>
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

void fuzzMcap(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".mcap", [](const std::string& path) {
    // A seed's tf and pose topics: both pose sources and the defaults.
    for (int source = 0; source < 3; ++source) {
      reconstruction::McapReaderOptions options;
      if (source == 1) options.pose_topic = "/camera/pose";
      if (source == 2) options.parent_frame = "world";
      try {
        reconstruction::McapReader reader(path, options);
        for (int i = 0; i < 8; ++i)
          if (!reader.next()) break;
      } catch (const InputError& error) {
        rejected(error);
      }
    }
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
