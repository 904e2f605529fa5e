// Random force-closure grasps on CokePlasticSmall_5k (4 frictional fingers,
// mu 0.8, L 8: 36 wrenches per grasp): grasps sampled per second (every core
// and one thread), and what one pre-check costs next to one full 6-D hull.
// items_per_second is the figure to read.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/grasp_sampling.hpp>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using icrkit::TriangleMesh;
using namespace icrkit::icr;

// A UV sphere of radius 5 cm with exact normals: the stand-in when the model
// is absent (a sphere is force closure far more often than the bottle).
TriangleMesh uvSphere(int rings, int segments) {
  TriangleMesh mesh;
  for (int i = 0; i <= rings; ++i) {
    const double theta = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * M_PI * j / segments;
      const Eigen::Vector3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      mesh.vertices.positions.push_back(0.05 * n);
      mesh.vertices.normals.push_back(n);
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      mesh.faces.emplace_back(a, a + segments, b);
      mesh.faces.emplace_back(b, a + segments, b + segments);
    }
  return mesh;
}

ContactModel paperContact() {
  ContactModel model;
  model.type = ContactType::Frictional;
  model.friction = 0.8;
  model.cone_edges = 8;
  return model;
}

struct Scene {
  TriangleMesh mesh;
  std::unique_ptr<GraspableObject> object;
  std::vector<WrenchSet> random_grasps;   // uniform random 4-finger grasps
  std::vector<WrenchSet> closure_grasps;  // the force-closure ones among them
  std::vector<WrenchSet> other_grasps;    // the rest
};

const Scene& scene() {
  static const Scene instance = [] {
    Scene s;
    const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/CokePlasticSmall_5k.obj";
    if (std::filesystem::exists(path)) {
      s.mesh = icrkit::io::readTriangleMesh(path);
    } else {
      std::printf("%s not found: benchmarking a sphere instead\n", path.c_str());
      s.mesh = uvSphere(50, 50);
    }
    s.object = std::make_unique<GraspableObject>(GraspableObject::withDefaultFrame(s.mesh));
    const ContactWrenches contact(paperContact(), s.object->frame());
    std::mt19937_64 rng(2024);
    std::uniform_int_distribution<std::size_t> pick(0, s.mesh.vertexCount() - 1);
    for (int g = 0; g < 256; ++g) {
      WrenchSet w(6, static_cast<Eigen::Index>(4 * contact.perContact()));
      for (Eigen::Index f = 0; f < 4; ++f) {
        const std::size_t v = pick(rng);
        const auto first = f * static_cast<Eigen::Index>(contact.perContact());
        contact.compute(s.object->position(v), s.object->normal(v), w, first);
      }
      s.random_grasps.push_back(w);
      (computeGraspWrenchSpace(w).force_closure ? s.closure_grasps : s.other_grasps).push_back(w);
    }
    std::printf("%zu vertices; of 256 random grasps %zu are force closure\n", s.mesh.vertexCount(),
                s.closure_grasps.size());
    return s;
  }();
  return instance;
}

// Arg: threads (0 = every core). Each iteration samples 20 grasps with a new seed.
void BM_SampleForceClosureGrasps(benchmark::State& state) {
  const Scene& s = scene();
  const int threads = state.range(0) > 0 ? static_cast<int>(state.range(0)) : tbb::info::default_concurrency();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  GraspSamplingParameters params;
  params.fingers = 4;
  params.count = 20;
  std::size_t grasps = 0, attempts = 0, rejected = 0, hulls = 0;
  for (auto _ : state) {
    GraspSamplingStatistics stats;
    const auto sampled = sampleForceClosureGrasps(*s.object, paperContact(), params, &stats);
    benchmark::DoNotOptimize(sampled.data());
    grasps += sampled.size();
    attempts += stats.attempts;
    rejected += stats.rejected_by_precheck;
    hulls += stats.hulls_built;
    ++params.seed;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(grasps));
  state.counters["threads"] = threads;
  state.counters["attempts_per_grasp"] = grasps ? static_cast<double>(attempts) / grasps : 0.0;
  state.counters["precheck_rejected"] = attempts ? static_cast<double>(rejected) / attempts : 0.0;
  state.counters["hulls_per_grasp"] = grasps ? static_cast<double>(hulls) / grasps : 0.0;
}
BENCHMARK(BM_SampleForceClosureGrasps)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// One pre-check or one hull per item, over a fixed pool of grasps.
void runOverPool(benchmark::State& state, const std::vector<WrenchSet>& pool, bool hull) {
  if (pool.empty()) {
    state.SkipWithError("empty pool");
    return;
  }
  std::size_t next = 0, positive = 0;
  for (auto _ : state) {
    const WrenchSet& w = pool[next];
    next = (next + 1) % pool.size();
    if (hull) {
      const GraspWrenchSpace gws = computeGraspWrenchSpace(w);
      positive += gws.force_closure;
    } else {
      positive += mayBeForceClosure(w);
    }
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["positive"] = state.iterations() ? static_cast<double>(positive) / state.iterations() : 0.0;
}

void BM_PrecheckRandomGrasps(benchmark::State& state) { runOverPool(state, scene().random_grasps, false); }
void BM_PrecheckNonClosureGrasps(benchmark::State& state) { runOverPool(state, scene().other_grasps, false); }
void BM_PrecheckClosureGrasps(benchmark::State& state) { runOverPool(state, scene().closure_grasps, false); }
void BM_HullRandomGrasps(benchmark::State& state) { runOverPool(state, scene().random_grasps, true); }
BENCHMARK(BM_PrecheckRandomGrasps)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PrecheckNonClosureGrasps)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PrecheckClosureGrasps)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HullRandomGrasps)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
