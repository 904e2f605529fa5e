#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/reconstruction/meshing/raw_and_filtered_meshes.hpp>

#include <chrono>

namespace icrkit::reconstruction {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

RawAndFilteredMeshes meshRawAndFiltered(const PointCloud& cloud, const RawAndFilteredParameters& params,
                                        const std::vector<Eigen::Vector3d>& viewpoints,
                                        const ProgressCallback& progress) {
  if (!cloud.hasNormals()) throw InputError("point cloud", "", "the raw mesh needs normals; estimate them first");
  RawAndFilteredMeshes out;
  auto start = Clock::now();
  if (params.make_raw) {
    reportProgress(progress, "raw mesh", 0, 1);
    BallPivotingParameters raw_meshing = params.meshing;
    if (!params.thin_raw_cloud) {
      raw_meshing.thinning_factor = 0.0;
      raw_meshing.fill_folded_holes = false;
    }
    BallPivotingResult raw = ballPivoting(cloud, raw_meshing);
    out.raw = std::move(raw.mesh);
    out.raw_meshing = raw.report;
    out.times.raw_mesh_ms = millisecondsSince(start);
  }

  start = Clock::now();
  PointCloud smoothed = cloud;
  ndt::SmoothingParameters smoothing = params.smoothing;
  if (smoothing.radius.relative && params.reference_spacing && *params.reference_spacing > 0)
    smoothing.radius = Length::metres(smoothing.radius.metresFor(*params.reference_spacing));
  // v3 normals face each point's own sensor, like the raw cloud's; with
  // them the smoothing skips orienting its normals over a neighbour graph
  // (a third of its time on 36 views), which the sensors would overrule.
  if (viewpoints.size() == smoothed.size()) {
    smoothing.viewpoints = viewpoints;
    smoothing.viewpoint.reset();  // it would take precedence over them
  }
  out.smoothing = ndt::smoothPointCloud(smoothed, smoothing, [&](const std::string&, std::size_t d, std::size_t t) {
    reportProgress(progress, "smoothing", d, t);
  });
  if (params.mesh_kept_points_only && smoothed.attributes.has("excluded")) {
    std::vector<std::size_t> kept;
    kept.reserve(smoothed.size());
    for (std::size_t i = 0; i < smoothed.size(); ++i)
      if (!smoothed.flag("excluded", i)) kept.push_back(i);
    out.dropped_excluded = smoothed.size() - kept.size();
    smoothed.select(kept);
  }
  out.times.smoothing_ms = millisecondsSince(start);

  start = Clock::now();
  reportProgress(progress, "filtered mesh", 0, 1);
  if (smoothed.size() < 3)
    throw InputError("point cloud", "", "fewer than 3 points are left to mesh after the preselection");
  BallPivotingResult filtered = ballPivoting(smoothed, params.meshing);
  out.filtered = std::move(filtered.mesh);
  out.filtered_meshing = filtered.report;
  out.times.filtered_mesh_ms = millisecondsSince(start);
  return out;
}

}  // namespace icrkit::reconstruction
