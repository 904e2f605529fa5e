#pragma once
// icrkit's fuzz targets (issue 37, docs/reliability.md): one per reader of
// files other programs write. Each takes the bytes of one input and reads
// them as the command line would; a clear InputError is the expected answer
// to bad bytes, anything else (a crash, a sanitizer report, another
// exception, an allocation beyond libFuzzer's -malloc_limit_mb) is a bug.
// The same functions run under libFuzzer (libfuzzer_entry.cpp, one binary
// per target) and in the ordinary test suite, which replays the kept
// regression inputs (replay_main.cpp).

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

namespace icrkit::fuzz {

using FuzzFunction = void (*)(const std::uint8_t* data, std::size_t size);

struct FuzzTarget {
  const char* name;  ///< also the folder of its regression inputs and corpus
  FuzzFunction run;
  std::size_t max_len;  ///< libFuzzer -max_len: its seeds' size class
};

// Geometry files (core/io).
void fuzzPly(const std::uint8_t* data, std::size_t size);
void fuzzObj(const std::uint8_t* data, std::size_t size);
void fuzzPcd(const std::uint8_t* data, std::size_t size);
void fuzzXyz(const std::uint8_t* data, std::size_t size);
// Recordings and their side files (reconstruction/input, calibration, core/pose).
void fuzzRawlog(const std::uint8_t* data, std::size_t size);
void fuzzMcap(const std::uint8_t* data, std::size_t size);  ///< ROS 2 bags
void fuzzTumDepthList(const std::uint8_t* data, std::size_t size);
void fuzzTumPoses(const std::uint8_t* data, std::size_t size);
void fuzzCameraJson(const std::uint8_t* data, std::size_t size);
void fuzzRangeModelJson(const std::uint8_t* data, std::size_t size);
// Records the commands write and read back (icr, eval, planning).
void fuzzRegionsJson(const std::uint8_t* data, std::size_t size);
void fuzzGraspsJsonl(const std::uint8_t* data, std::size_t size);
void fuzzPlanJson(const std::uint8_t* data, std::size_t size);

/// A target's InputError for bad bytes: the expected answer, silent unless
/// ICRKIT_FUZZ_VERBOSE is set (then printed, to see what a seed tripped on).
void rejected(const std::exception& error);

/// Every target, in a fixed order.
const std::vector<FuzzTarget>& fuzzTargets();

}  // namespace icrkit::fuzz
