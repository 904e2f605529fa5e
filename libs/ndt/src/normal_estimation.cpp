#include <icrkit/ndt/normal_estimation.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/radius_cells.hpp>
#include <icrkit/ndt/fit_uncertainty.hpp>
#include <icrkit/ndt/normal_orientation.hpp>
#include <icrkit/ndt/symmetric_eigen3.hpp>

#include "window_moments.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

namespace icrkit::ndt {

NormalEstimationReport estimateNormals(PointCloud& cloud, const NormalEstimationParameters& params) {
  const std::size_t n = cloud.size();
  if (n < 3) throw InputError("point cloud", "", "normal estimation needs at least 3 points, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i)
    if (!cloud.positions[i].allFinite())
      throw InputError("point cloud", "point " + std::to_string(i), "non-finite coordinate, expected finite x, y, z");
  if (!params.viewpoints.empty() && params.viewpoints.size() != n)
    throw InputError("viewpoints", "", "expected one viewpoint per point (" + std::to_string(n) + "), got " +
                                           std::to_string(params.viewpoints.size()));
  if (!params.radius.valid())
    throw InputError("NormalEstimationParameters::radius", "",
                     "the normal window radius must be positive, got " + formatLength(params.radius));

  NormalEstimationReport summary;
  summary.points = n;
  // One tree for the spacing and the small windows' nearest points.
  const KdTree tree(cloud.positions);
  summary.radius_m = params.radius.relative
                         ? params.radius.metresFor(spacingStatistics(nearestNeighbourDistances(cloud.positions, tree)).median)
                         : params.radius.value;
  const std::size_t k = std::max<std::size_t>(3, params.min_neighbours);

  std::vector<Eigen::Vector3d> normals(n, Eigen::Vector3d::UnitZ());
  std::vector<FitUncertainty> uncertainty(n);
  std::atomic<std::size_t> small{0};
  // The plane of one window: covariance about the query point.
  auto fit = [&](std::size_t i, const WindowMoments& m) {
    const double inv = 1.0 / static_cast<double>(m.count);
    const Eigen::Vector3d mean = m.sum * inv;
    const SymmetricEigen3 eigen = eigenSymmetric3(m.outer() * inv - mean * mean.transpose());
    const Eigen::Vector3d v3 = eigen.vectors.col(2);
    if (v3.allFinite() && v3.squaredNorm() > 0) normals[i] = v3.normalized();
    // The window actually used: the k nearest reach beyond the radius.
    const double reach = std::max(summary.radius_m, std::sqrt(m.reach_sq));
    uncertainty[i] = planeFitUncertainty(eigen.values, eigen.vectors, m.count, -mean, reach, FittedPoint::Measured);
  };
  // Too few points within the radius (or no radius): the k nearest.
  auto fitNearest = [&](std::size_t i, std::vector<std::size_t>& window) {
    ++small;
    window.clear();
    const Eigen::Vector3d& p = cloud.positions[i];
    for (const Neighbour& nb : tree.nearest(p, k)) window.push_back(nb.index);
    std::sort(window.begin(), window.end());
    WindowMoments m;
    for (std::size_t j : window) m.add(cloud.positions[j] - p);
    fit(i, m);
  };
  if (params.index_order || !(summary.radius_m > 0)) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<std::size_t> window;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const Eigen::Vector3d& p = cloud.positions[i];
        if (summary.radius_m > 0) tree.indicesWithinRadius(p, summary.radius_m, window);
        if (!(summary.radius_m > 0) || window.size() < k) {
          fitNearest(i, window);
          continue;
        }
        WindowMoments m;
        for (std::size_t j : window) m.add(cloud.positions[j] - p);
        fit(i, m);
      }
    });
  } else {
    const RadiusCells cells(cloud.positions, summary.radius_m);
    const double radius_sq = summary.radius_m * summary.radius_m;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cellCount(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      CandidatePositions near;
      std::vector<std::uint32_t> slots;
      std::vector<std::size_t> window;
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        near.gather(cloud.positions, cells, c);
        for (const std::uint32_t* it = cells.cellBegin(c); it != cells.cellEnd(c); ++it) {
          const std::size_t i = *it;
          const Eigen::Vector3d& p = cloud.positions[i];
          const std::size_t count = near.within(p, radius_sq, slots);
          if (count < k) {
            fitNearest(i, window);
            continue;
          }
          WindowMoments m;
          for (std::size_t s = 0; s < count; ++s) m.add(near.offset(slots[s], p));
          fit(i, m);
        }
      }
    });
  }
  summary.small_windows = small.load();
  cloud.normals = std::move(normals);
  auto& normal_sigma = cloud.attributes.add(kNormalSigmaAttribute, ScalarType::Float32, n);
  auto& position_sigma = cloud.attributes.add(kPositionSigmaAttribute, ScalarType::Float32, n);
  for (std::size_t i = 0; i < n; ++i) {
    normal_sigma.values[i] = representAs(ScalarType::Float32, uncertainty[i].normal_sigma);
    position_sigma.values[i] = representAs(ScalarType::Float32, uncertainty[i].position_sigma);
  }
  if (params.viewpoints.empty()) {
    summary.flipped = orientNormals(cloud, params.viewpoint);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (cloud.normals[i].dot(params.viewpoints[i] - cloud.positions[i]) < 0) {
        cloud.normals[i] = -cloud.normals[i];
        ++summary.flipped;
      }
  }
  return summary;
}

}  // namespace icrkit::ndt
