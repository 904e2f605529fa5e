// Throughput of the grasp planner (issue 33's target: <= 0.5 ms per
// candidate over a 1000-candidate plan on the authors' 2.5k-vertex models,
// regions included; their library takes 5-6 ms per 4-finger grasp), beside
// the random force-closure sampler on the same mesh. Results and the command
// in docs/performance.md.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/planning/grasp_planner.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

using namespace icrkit;

namespace {

const TriangleMesh* model(const std::string& name) {
  static std::map<std::string, TriangleMesh> meshes;
  const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/" + name;
  if (!std::filesystem::exists(path)) return nullptr;
  auto found = meshes.find(name);
  if (found == meshes.end()) found = meshes.emplace(name, io::readTriangleMesh(path)).first;
  return &found->second;
}

void BM_Plan(benchmark::State& state, const std::string& name) {
  const TriangleMesh* mesh = model(name);
  if (!mesh) {
    state.SkipWithError("shared data not found");
    return;
  }
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(*mesh, {}, icr::TorqueReference::Centroid);
  planning::PlanningParameters params;
  params.candidates = static_cast<std::size_t>(state.range(0));
  params.regions.alpha = 0.5;
  for (auto _ : state) benchmark::DoNotOptimize(planning::planGrasps(object, params));
  // items/s = candidates planned per second.
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}

void BM_SampleForceClosure(benchmark::State& state, const std::string& name) {
  const TriangleMesh* mesh = model(name);
  if (!mesh) {
    state.SkipWithError("shared data not found");
    return;
  }
  const icr::GraspableObject object = icr::GraspableObject::withDefaultFrame(*mesh, {}, icr::TorqueReference::Centroid);
  icr::GraspSamplingParameters params;
  params.count = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(icr::sampleForceClosureGrasps(object, icr::ContactModel{}, params));
}

}  // namespace

BENCHMARK_CAPTURE(BM_Plan, tortoise, std::string("Tortoise_5k.obj"))->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Plan, fish, std::string("Fish_5k.obj"))->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SampleForceClosure, tortoise, std::string("Tortoise_5k.obj"))
    ->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
