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
  const TempInput file(data, size, ".rawlog");
  try {
    reconstruction::RawlogReader reader(file.path());
    // A bounded number of scans: a seed holds one or two.
    for (int i = 0; i < 8; ++i)
      if (!reader.next()) break;
  } catch (const InputError& e) {
    rejected(e);
  }
}

void fuzzTumDepthList(const std::uint8_t* data, std::size_t size) {
  const TempInput file(data, size, ".txt");
  try {
    reconstruction::readDepthList(file.path());
  } catch (const InputError& e) {
    rejected(e);
  }
}

void fuzzTumPoses(const std::uint8_t* data, std::size_t size) {
  const TempInput file(data, size, ".txt");
  try {
    readTumTrajectory(file.path());
  } catch (const InputError& e) {
    rejected(e);
  }
}

void fuzzCameraJson(const std::uint8_t* data, std::size_t size) {
  const TempInput file(data, size, ".json");
  try {
    reconstruction::readDepthCameraFile(file.path());
  } catch (const InputError& e) {
    rejected(e);
  }
}

void fuzzRangeModelJson(const std::uint8_t* data, std::size_t size) {
  const TempInput file(data, size, ".json");
  try {
    reconstruction::readRangeErrorModel(file.path());
  } catch (const InputError& e) {
    rejected(e);
  }
}

}  // namespace icrkit::fuzz
