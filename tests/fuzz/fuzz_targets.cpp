#include "fuzz_targets.hpp"

#include <cstdio>
#include <cstdlib>

namespace icrkit::fuzz {

void rejected(const std::exception& error) {
  if (std::getenv("ICRKIT_FUZZ_VERBOSE")) std::fprintf(stderr, "rejected: %s\n", error.what());
}

const std::vector<FuzzTarget>& fuzzTargets() {
  // Sizes: a text record needs a few kilobytes; a binary geometry seed a
  // few hundred kilobytes; a rawlog seed one small range image.
  static const std::vector<FuzzTarget> targets{
      {"ply", fuzzPly, 1 << 18},
      {"obj", fuzzObj, 1 << 16},
      {"pcd", fuzzPcd, 1 << 18},
      {"xyz", fuzzXyz, 1 << 16},
      {"rawlog", fuzzRawlog, 1 << 20},
      {"mcap", fuzzMcap, 1 << 16},
      {"tum_depth_list", fuzzTumDepthList, 1 << 14},
      {"tum_poses", fuzzTumPoses, 1 << 14},
      {"camera_json", fuzzCameraJson, 1 << 12},
      {"range_model_json", fuzzRangeModelJson, 1 << 14},
      {"regions_json", fuzzRegionsJson, 1 << 14},
      {"grasps_jsonl", fuzzGraspsJsonl, 1 << 14},
      {"plan_json", fuzzPlanJson, 1 << 16},
  };
  return targets;
}

}  // namespace icrkit::fuzz
