// Throughput of core::RayCaster: closest-hit rays/s and all-hits lines/s on
// the Stanford bunny (bun_zipper.ply, 69k faces), batched (TBB, every core)
// and single-threaded. items_per_second is the figure to read.

#include <icrkit/core/io/geometry_io.hpp>
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
// of similar size at 6 levels (82k faces).
TriangleMesh icosphere(int levels) {
  TriangleMesh mesh;
  auto& p = mesh.vertices.positions;
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  for (const auto& v : {Eigen::Vector3d(-1, g, 0), Eigen::Vector3d(1, g, 0), Eigen::Vector3d(-1, -g, 0),
                        Eigen::Vector3d(1, -g, 0), Eigen::Vector3d(0, -1, g), Eigen::Vector3d(0, 1, g),
                        Eigen::Vector3d(0, -1, -g), Eigen::Vector3d(0, 1, -g), Eigen::Vector3d(g, 0, -1),
                        Eigen::Vector3d(g, 0, 1), Eigen::Vector3d(-g, 0, -1), Eigen::Vector3d(-g, 0, 1)})
    p.push_back(v.normalized());
  mesh.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;  // shared edges get one new vertex
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      p.push_back((p[a] + p[b]).normalized());
      return midpoints[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<icrkit::Triangle> finer;
    for (const auto& f : mesh.faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    mesh.faces = std::move(finer);
  }
  for (auto& v : p) v *= 0.1;  // bunny-sized, metres
  return mesh;
}

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
