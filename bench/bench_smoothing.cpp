// Throughput of the 3D-NDT smoothing layer (ndt::smoothPointCloud) in
// points/s on a 1M-point noisy sphere at r = 4 x its median spacing, on 2
// TBB threads, next to the parts it is made of. bench/open3d_normals.py
// times Open3D's estimate_normals on the same cloud for comparison; give
// `--write-cloud=PATH.ply` to write the cloud for it (nothing is timed then).
// items_per_second is the figure to read.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/ndt/normal_orientation.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/ndt/symmetric_eigen3.hpp>

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

using icrkit::PointCloud;

constexpr std::size_t kPoints = 1000000;
constexpr double kSphereRadius = 0.1;  // metres: object-sized
constexpr double kRadiusFactor = 4.0;
constexpr int kThreads = 2;

// splitmix64: integer-only, so bench/open3d_normals.py reproduces the
// noise bit for bit without a shared random generator.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A Fibonacci sphere (even coverage, no random sampling), each point moved
// radially by up to +-20 % of the nominal spacing: range-sensor-like noise
// along the surface normal. open3d_normals.py holds the same formula.
PointCloud noisySphere() {
  PointCloud cloud;
  cloud.positions.resize(kPoints);
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  const double spacing = std::sqrt(4.0 * M_PI / static_cast<double>(kPoints)) * kSphereRadius;
  for (std::size_t i = 0; i < kPoints; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(kPoints);
    const double ring = std::sqrt(1.0 - z * z);
    const double phi = golden_angle * static_cast<double>(i);
    const double unit_noise = static_cast<double>(mix(i) >> 11) * 0x1.0p-53 * 2.0 - 1.0;  // [-1, 1)
    const double r = kSphereRadius + 0.2 * spacing * unit_noise;
    cloud.positions[i] = Eigen::Vector3d(r * ring * std::cos(phi), r * ring * std::sin(phi), r * z);
  }
  return cloud;
}

struct Fixture {
  PointCloud cloud;
  double median_spacing = 0.0;
  double radius = 0.0;
};

const Fixture& fixture() {
  static const Fixture instance = [] {
    Fixture f;
    f.cloud = noisySphere();
    f.median_spacing = icrkit::nearestNeighbourSpacing(f.cloud.positions).median;
    f.radius = kRadiusFactor * f.median_spacing;
    return f;
  }();
  return instance;
}

void report(benchmark::State& state) {
  const Fixture& f = fixture();
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kPoints));
  state.counters["radius_mm"] = f.radius * 1e3;
  state.counters["spacing_mm"] = f.median_spacing * 1e3;
}

// (a) The whole public call: median spacing, k-d tree, windows, covariances,
// eigen-decompositions, projection, normal orientation, attributes.
void BM_SmoothPointCloud(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  icrkit::ndt::SmoothingParameters params;
  params.radius = icrkit::Length::metres(f.radius);
  // Arg 1: a viewpoint instead of the k-NN/MST orientation, to show what
  // the consistent orientation costs on its own.
  if (state.range(0) == 1) params.viewpoint = Eigen::Vector3d(0.0, 0.0, 10.0);
  double mean_cardinality = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    PointCloud cloud = f.cloud;
    state.ResumeTiming();
    const auto summary = icrkit::ndt::smoothPointCloud(cloud, params);
    mean_cardinality = summary.preselection.mean_cardinality;
    benchmark::DoNotOptimize(cloud.positions.data());
  }
  report(state);
  state.counters["mean_cardinality"] = mean_cardinality;
}
BENCHMARK(BM_SmoothPointCloud)->ArgName("viewpoint")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// (b) What Open3D's estimate_normals(KDTreeSearchParamRadius) also does:
// build a k-d tree, then per point a radius query, the 3x3 covariance and its
// eigen-decomposition; written with the library's public pieces (KdTree,
// eigenSymmetric3) in the same way smoothPointCloud's pass uses them.
// Arg 1 keeps a prebuilt tree out of the timing.
void BM_WindowCovarianceEigen(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  const std::vector<Eigen::Vector3d>& points = f.cloud.positions;
  std::vector<Eigen::Vector3d> normals(points.size());
  const bool prebuilt = state.range(0) == 1;
  const icrkit::KdTree shared_tree(points);
  for (auto _ : state) {
    std::unique_ptr<icrkit::KdTree> own_tree;
    if (!prebuilt) own_tree = std::make_unique<icrkit::KdTree>(points);
    const icrkit::KdTree& tree = prebuilt ? shared_tree : *own_tree;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 2048),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::vector<std::size_t> window;
                        window.reserve(256);
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          const Eigen::Vector3d& p = points[i];
                          tree.indicesWithinRadius(p, f.radius, window);
                          if (window.size() < 3) continue;
                          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
                          Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
                          for (std::size_t j : window) {
                            const Eigen::Vector3d d = points[j] - p;
                            sum += d;
                            outer.noalias() += d * d.transpose();
                          }
                          const double inv = 1.0 / static_cast<double>(window.size());
                          const Eigen::Vector3d mean = sum * inv;
                          const Eigen::Matrix3d covariance = outer * inv - mean * mean.transpose();
                          normals[i] = icrkit::ndt::eigenSymmetric3(covariance).vectors.col(2);
                        }
                      });
    benchmark::DoNotOptimize(normals.data());
  }
  report(state);
}
BENCHMARK(BM_WindowCovarianceEigen)->ArgName("prebuilt_tree")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The radius queries alone (prebuilt tree): the share of (b) spent in nanoflann.
void BM_RadiusQueries(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  const std::vector<Eigen::Vector3d>& points = f.cloud.positions;
  const icrkit::KdTree tree(points);
  std::vector<std::size_t> counts(points.size());
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 2048),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::vector<std::size_t> window;
                        window.reserve(256);
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          tree.indicesWithinRadius(points[i], f.radius, window);
                          counts[i] = window.size();
                        }
                      });
    benchmark::DoNotOptimize(counts.data());
  }
  report(state);
}
BENCHMARK(BM_RadiusQueries)->Unit(benchmark::kMillisecond)->UseRealTime();

// The serial-or-parallel set-up work smoothPointCloud does besides the pass.
void BM_KdTreeBuild(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  for (auto _ : state) {
    const icrkit::KdTree tree(f.cloud.positions);
    benchmark::DoNotOptimize(&tree);
  }
  report(state);
}
BENCHMARK(BM_KdTreeBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MedianSpacing(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  for (auto _ : state) benchmark::DoNotOptimize(icrkit::nearestNeighbourSpacing(f.cloud.positions).median);
  report(state);
}
BENCHMARK(BM_MedianSpacing)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_OrientNormals(benchmark::State& state) {
  const Fixture& f = fixture();
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  PointCloud smoothed = f.cloud;
  icrkit::ndt::SmoothingParameters params;
  params.radius = icrkit::Length::metres(f.radius);
  params.preselection.rule = icrkit::ndt::PreselectionRule::None;
  icrkit::ndt::smoothPointCloud(smoothed, params);
  for (auto _ : state) {
    state.PauseTiming();
    PointCloud cloud = smoothed;
    state.ResumeTiming();
    benchmark::DoNotOptimize(icrkit::ndt::orientNormals(cloud, std::nullopt));
  }
  report(state);
}
BENCHMARK(BM_OrientNormals)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const char* prefix = "--write-cloud=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], prefix, std::strlen(prefix)) != 0) {
      std::fprintf(stderr, "bench_smoothing: unknown argument '%s'\n", argv[i]);
      return 2;
    }
    const std::string path = argv[i] + std::strlen(prefix);
    const Fixture& f = fixture();
    icrkit::io::writePointCloud(path, f.cloud);
    std::printf("wrote %zu points to %s; median spacing %.9g m, r = %.9g m\n", f.cloud.size(), path.c_str(),
                f.median_spacing, f.radius);
    return 0;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
