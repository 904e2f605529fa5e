// Ball pivoting (reconstruction::ballPivoting) on the bun_zipper points with
// estimated normals and the default radii (1.5x, 2.5x, 4x the median
// spacing), on 1 and 2 TBB threads. The side-by-side comparison with Open3D,
// on this cloud and on 1M points, is bench/ball_pivoting_vs_open3d.sh.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <string>

namespace {

const icrkit::PointCloud& bunny() {
  static const icrkit::PointCloud cloud = [] {
    icrkit::PointCloud c = icrkit::io::readPointCloud(std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply");
    icrkit::ndt::estimateNormals(c);
    return c;
  }();
  return cloud;
}

void BM_BallPivotingBunny(benchmark::State& state) {
  if (!std::filesystem::exists(std::string(ICRKIT_SHARED_DATA_DIR) + "/stanford-bunny/bun_zipper.ply")) {
    state.SkipWithError("shared data not found");
    return;
  }
  const icrkit::PointCloud& cloud = bunny();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  std::size_t triangles = 0;
  for (auto _ : state) {
    const auto result = icrkit::reconstruction::ballPivoting(cloud);
    triangles = result.report.triangles;
    benchmark::DoNotOptimize(triangles);
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * cloud.size()));
}
BENCHMARK(BM_BallPivotingBunny)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
