// Time per grasp of the multi-point (patch) contact model (r = 5 mm, the
// reference grasps of icr-reference/*_patch5mm.json on the ~2.5k-vertex
// icr-models meshes), with the per-phase breakdown; the patches are built
// once per mesh and radius and shared by every grasp, as in use. Also: the
// one-off cost of building every patch of a mesh. The reference library
// takes about 0.45 s per grasp here (issue 19). Results: docs/icr.md.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/patch_contacts.hpp>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <memory>

using namespace icrkit;
using namespace icrkit::icr;

namespace {

const std::string kData = ICRKIT_SHARED_DATA_DIR;

struct Workload {
  TriangleMesh mesh;
  std::unique_ptr<GraspableObject> object;
  std::unique_ptr<ContactPatches> patches;
  PatchParameters patch;
  std::vector<std::vector<int>> grasps;
};

// The patch reference grasps of one model (frictional, mu 0.8, L 8, 4 fingers, alpha 0.5).
std::shared_ptr<Workload> patchWorkload(const std::string& model) {
  const std::string file = kData + "/icr-reference/" + model + "__frictional_mu0.8_L8_f4_a0.5_patch5mm.json";
  if (!std::filesystem::exists(file)) return nullptr;
  auto w = std::make_shared<Workload>();
  w->mesh = io::readTriangleMesh(kData + "/icr-models/" + model + ".obj");
  w->object = std::make_unique<GraspableObject>(GraspableObject::withDefaultFrame(w->mesh));
  std::ifstream in(file);
  const nlohmann::json reference = nlohmann::json::parse(in);
  w->patch.radius_m = reference.at("patch").at("radius_m").get<double>();
  w->patch.filter_border = reference.at("patch").at("filter_patch").get<bool>();
  w->patches = std::make_unique<ContactPatches>(*w->object, w->patch);
  for (const auto& g : reference.at("grasps")) w->grasps.push_back(g.at("contacts").get<std::vector<int>>());
  return w;
}

void runPatchIcr(benchmark::State& state, std::shared_ptr<Workload> w, GrowthMode mode) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  IcrParameters params;
  params.alpha = 0.5;
  params.mode = mode;
  std::size_t i = 0;
  double hull = 0, zones = 0, growth = 0, tested = 0;
  for (auto _ : state) {
    const IcrResult r = computePatchContactRegions(*w->object, *w->patches, w->grasps[i++ % w->grasps.size()], params);
    hull += r.timings.hull_ms;
    zones += r.timings.zones_ms;
    growth += r.timings.growth_ms;
    tested += static_cast<double>(r.vertices_tested);
    benchmark::DoNotOptimize(r.regions.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["hull_ms"] = hull / n;
  state.counters["zones_ms"] = zones / n;
  state.counters["growth_ms"] = growth / n;
  state.counters["vertices_tested"] = tested / n;
}

// The same grasps with single-point contacts, for scale.
void runSinglePointIcr(benchmark::State& state, std::shared_ptr<Workload> w) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  IcrParameters params;
  params.alpha = 0.5;
  std::size_t i = 0;
  for (auto _ : state) {
    const IcrResult r = computeIndependentContactRegions(*w->object, w->grasps[i++ % w->grasps.size()], params);
    benchmark::DoNotOptimize(r.regions.data());
  }
}

// Every patch of the mesh from scratch, one thread (the lazy cache makes a
// grasp pay only for the patches it touches).
void buildAllPatches(benchmark::State& state, std::shared_ptr<Workload> w) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  for (auto _ : state) {
    const ContactPatches patches(*w->object, w->patch);
    patches.buildAll();
    benchmark::DoNotOptimize(&patches.of(0));
  }
  state.counters["vertices"] = static_cast<double>(w->mesh.vertexCount());
}

}  // namespace

int main(int argc, char** argv) {
  for (const char* model : {"CokePlasticSmall_5k", "Fish_5k", "RedCup_5k"}) {
    auto w = patchWorkload(model);
    if (!w) {
      std::fprintf(stderr, "note: shared ICR patch data for %s not found, skipped\n", model);
      continue;
    }
    const std::string name(model);
    // Every grasp equally often (a hull takes 0.1-0.5 s, so time-based
    // iteration counts would sample a few grasps only).
    const auto runs = static_cast<benchmark::IterationCount>(2 * w->grasps.size());
    benchmark::RegisterBenchmark(("BM_PatchIcr/" + name + "/bfs").c_str(),
                                 [w](benchmark::State& s) { runPatchIcr(s, w, GrowthMode::BreadthFirst); })
        ->Iterations(runs)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_PatchIcr/" + name + "/full").c_str(),
                                 [w](benchmark::State& s) { runPatchIcr(s, w, GrowthMode::Full); })
        ->Iterations(runs)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_SinglePointIcr/" + name).c_str(),
                                 [w](benchmark::State& s) { runSinglePointIcr(s, w); })
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_PatchBuildAll/" + name).c_str(),
                                 [w](benchmark::State& s) { buildAllPatches(s, w); })
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
