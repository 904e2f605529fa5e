// Throughput of core::RayCaster: closest-hit rays/s and all-hits lines/s on
// the Stanford bunny (bun_zipper.ply, 69k faces), batched (TBB, every core)
// and single-threaded. items_per_second is the figure to read.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using icrkit::Ray;
using icrkit::RayCaster;
using icrkit::TriangleMesh;

// A sphere of 20 * 4^levels faces: the stand-in when the bunny is absent,
// of similar size at 6 levels (82k faces), bunny-sized in metres.
TriangleMesh icosphere(int levels) { return icrkit::makeIcosphere(levels, 0.1); }

struct Scene {
  TriangleMesh mesh;
  std::vector<Ray> rays;
  std::vector<Eigen::Vector3d> origins, directions;
  std::unique_ptr<RayCaster> caster;
};

// Rays start on a sphere around the mesh and aim at random points of its
// bounding box: most hit, some miss, in no coherent order.
const Scene& scene() {
  static const Scene instance = [] {
    Scene s;
    const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply";
    if (std::filesystem::exists(path)) {
      s.mesh = icrkit::io::readTriangleMesh(path);
    } else {
      std::printf("%s not found: benchmarking an icosphere instead\n", path.c_str());
      s.mesh = icosphere(6);
    }
    std::printf("mesh: %zu vertices, %zu faces\n", s.mesh.vertexCount(), s.mesh.faceCount());
    s.caster = std::make_unique<RayCaster>(s.mesh);

    const Eigen::AlignedBox3d box = s.mesh.vertices.bounds();
    const double radius = box.diagonal().norm();
    std::mt19937 rng(20240601);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int count = 1 << 18;
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d origin =
          box.center() + radius * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const Eigen::Vector3d target =
          box.min() + box.diagonal().cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
      Ray ray;
      ray.origin = origin;
      ray.direction = target - origin;
      s.rays.push_back(ray);
      s.origins.push_back(origin);
      s.directions.push_back(ray.direction);
    }
    return s;
  }();
  return instance;
}

// Batch benchmarks take the TBB thread count as their argument, 0 for all
// cores: batch-on-one-thread against single queries shows the batching
// gain, all cores against one thread the parallel scaling.
tbb::global_control threadLimit(const benchmark::State& state) {
  const auto threads = static_cast<std::size_t>(state.range(0));
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             threads > 0 ? threads : static_cast<std::size_t>(tbb::info::default_concurrency()));
}

void closestHitsBatch(benchmark::State& state) {
  const Scene& s = scene();
  const auto limit = threadLimit(state);
  for (auto _ : state) benchmark::DoNotOptimize(s.caster->closestHits(s.rays));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.rays.size()));
}

void closestHitSingleThread(benchmark::State& state) {
  const Scene& s = scene();
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    hits += s.caster->closestHit(s.rays[i]).hit;
    i = (i + 1) % s.rays.size();
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations());
}

void allHitsBatch(benchmark::State& state) {
  const Scene& s = scene();
  const auto limit = threadLimit(state);
  for (auto _ : state) benchmark::DoNotOptimize(s.caster->allHitsOnLines(s.origins, s.directions));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.origins.size()));
}

void allHitsSingleThread(benchmark::State& state) {
  const Scene& s = scene();
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    hits += s.caster->allHitsOnLine(s.origins[i], s.directions[i]).size();
    i = (i + 1) % s.origins.size();
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations());
}

void buildScene(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) benchmark::DoNotOptimize(RayCaster(s.mesh));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.mesh.faceCount()));
}

// Batches run on every core: wall-clock time is the honest measure there.
BENCHMARK(closestHitsBatch)->ArgName("threads")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(closestHitSingleThread);
BENCHMARK(allHitsBatch)->ArgName("threads")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(allHitsSingleThread);
BENCHMARK(buildScene)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
