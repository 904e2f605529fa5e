// The records commands write and other commands (or other people) hand
// back: contact regions, grasp lines, plans.
#include "fuzz_targets.hpp"
#include "temp_input.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/icr/regions_file.hpp>
#include <icrkit/planning/plan_file.hpp>

#include <string>

namespace icrkit::fuzz {

namespace {

// Regions are checked against a mesh: a strip of 8 vertices and 6 faces,
// so that an index may be in range, out of range or on no face (vertex 7).
TriangleMesh stripMesh() {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.positions.emplace_back(0.01 * (i / 2), 0.01 * (i % 2), 0.0);
  for (int i = 0; i + 2 < 7; ++i) mesh.faces.emplace_back(i, i + 1, i + 2);
  return mesh;
}

std::string text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace

void fuzzRegionsJson(const std::uint8_t* data, std::size_t size) {
  const TriangleMesh mesh = stripMesh();
  try {
    icr::parseRegionsJson(text(data, size), "fuzz_regions.json", mesh, "strip");
  } catch (const InputError& e) {
    rejected(e);
  }
}

void fuzzGraspsJsonl(const std::uint8_t* data, std::size_t size) {
  readThroughFile(data, size, ".jsonl", [](const std::string& path) { eval::readGraspRecords(path); });
}

void fuzzPlanJson(const std::uint8_t* data, std::size_t size) {
  try {
    planning::parsePlanJson(text(data, size), "fuzz_plan.json", 4096);
  } catch (const InputError& e) {
    rejected(e);
  }
}

}  // namespace icrkit::fuzz
