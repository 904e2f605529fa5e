/// \file
/// Range image filters. They work on pixels (range set to 0) so that the
/// image stays the single source of truth; points follow by pixel index.

#include <icrkit/reconstruction/input/scan_filters.hpp>

#include <icrkit/core/kd_tree.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace icrkit::reconstruction {
namespace {

// Invalidates the marked pixels, drops their points, fills the report.
FilterReport apply(RangeScan& scan, const std::vector<std::uint8_t>& reject, std::size_t before) {
  FilterReport report;
  report.pixels_before = before;
  for (std::size_t i = 0; i < scan.range.size(); ++i)
    if (reject[i] && scan.range[i] > 0.0f) {
      scan.range[i] = 0.0f;
      ++report.removed;
    }
  scan.dropInvalidPoints();
  return report;
}

}  // namespace

FilterReport filterConfidence(RangeScan& scan, const ConfidenceFilterParameters& params) {
  const std::size_t before = scan.validPixels();
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  const std::size_t n = scan.range.size();
  if (params.min_confidence > 0 && scan.confidence.data.size() == n)
    for (std::size_t i = 0; i < n; ++i) reject[i] |= scan.confidence.data[i] < params.min_confidence;
  if (params.min_amplitude > 0 && scan.intensity_is_ir && scan.intensity.channels == 1 &&
      scan.intensity.data.size() == n)
    for (std::size_t i = 0; i < n; ++i) reject[i] |= scan.intensity.data[i] < params.min_amplitude;
  return apply(scan, reject, before);
}

FilterReport filterJumpEdges(RangeScan& scan, const JumpEdgeParameters& params) {
  const std::size_t before = scan.validPixels();
  const int w = scan.width, h = scan.height;
  std::vector<Eigen::Vector3d> p(scan.range.size());
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      if (scan.range[i] > 0.0f) p[i] = opticalPoint(scan, r, c, scan.range[i]);
    }
  const double cos_limit = std::cos(params.min_angle);
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      if (!(scan.range[i] > 0.0f)) continue;
      const Eigen::Vector3d sight = p[i].normalized();
      for (int dr = -1; dr <= 1 && !reject[i]; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if ((dr == 0 && dc == 0) || rr < 0 || rr >= h || cc < 0 || cc >= w) continue;
          const std::size_t j = static_cast<std::size_t>(rr) * w + cc;
          if (!(scan.range[j] > 0.0f)) continue;
          const Eigen::Vector3d d = p[j] - p[i];
          const double length = d.norm();
          if (length < params.min_jump) continue;
          // |cos| of the angle between the segment and the line of sight:
          // close to 1 when the neighbour lies (almost) on the same ray.
          if (std::abs(d.dot(sight)) / length > cos_limit) {
            reject[i] = 1;
            break;
          }
        }
    }
  return apply(scan, reject, before);
}

FilterReport filterForegroundEdges(RangeScan& scan, const ForegroundEdgeParameters& params) {
  const std::size_t before = scan.validPixels();
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  if (params.pixels <= 0) return apply(scan, reject, before);
  const int w = scan.width, h = scan.height, k = params.pixels;
  // Pixels without a range, labelled by the size of their 4-connected gap.
  std::vector<std::uint8_t> wide_gap(scan.range.size(), 0);
  {
    std::vector<std::uint8_t> seen(scan.range.size(), 0);
    std::vector<std::size_t> gap, stack;
    for (std::size_t start = 0; start < scan.range.size(); ++start) {
      if (seen[start] || scan.range[start] > 0.0f) continue;
      gap.clear();
      stack.assign(1, start);
      seen[start] = 1;
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        gap.push_back(i);
        const int r = static_cast<int>(i / static_cast<std::size_t>(w)), c = static_cast<int>(i % static_cast<std::size_t>(w));
        const int next[4][2] = {{r - 1, c}, {r + 1, c}, {r, c - 1}, {r, c + 1}};
        for (const auto& n : next) {
          if (n[0] < 0 || n[0] >= h || n[1] < 0 || n[1] >= w) continue;
          const std::size_t j = static_cast<std::size_t>(n[0]) * w + n[1];
          if (seen[j] || scan.range[j] > 0.0f) continue;
          seen[j] = 1;
          stack.push_back(j);
        }
      }
      if (gap.size() >= params.min_gap_pixels)
        for (std::size_t i : gap) wide_gap[i] = 1;
    }
  }
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      const float range = scan.range[i];
      if (!(range > 0.0f)) continue;
      const double background = static_cast<double>(range) + params.min_jump;
      for (int rr = std::max(0, r - k); rr <= std::min(h - 1, r + k) && !reject[i]; ++rr)
        for (int cc = std::max(0, c - k); cc <= std::min(w - 1, c + k); ++cc) {
          const std::size_t j = static_cast<std::size_t>(rr) * w + cc;
          const float other = scan.range[j];
          if (wide_gap[j] || (other > 0.0f && static_cast<double>(other) > background)) {
            reject[i] = 1;
            break;
          }
        }
    }
  return apply(scan, reject, before);
}

FilterReport filterRange(RangeScan& scan, const RangeGateParameters& params) {
  const std::size_t before = scan.validPixels();
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  for (int r = 0; r < scan.height; ++r)
    for (int c = 0; c < scan.width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * scan.width + c;
      if (!(scan.range[i] > 0.0f)) continue;
      const double distance = opticalPoint(scan, r, c, scan.range[i]).norm();
      reject[i] = distance < params.min_range || (params.max_range > 0 && distance > params.max_range);
    }
  return apply(scan, reject, before);
}

FilterReport filterCropBox(RangeScan& scan, const Eigen::AlignedBox3d& box) {
  const std::size_t before = scan.validPixels();
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  // Pixels without a point (MRPT skipped them) cannot be located: keep the
  // image consistent with the points by rejecting them too.
  std::vector<std::uint8_t> located(scan.range.size(), 0);
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    located[scan.pixels[k]] = 1;
    if (!box.contains(scan.points[k])) reject[scan.pixels[k]] = 1;
  }
  for (std::size_t i = 0; i < reject.size(); ++i)
    if (!located[i]) reject[i] = 1;
  return apply(scan, reject, before);
}

PlaneRemovalReport removeSupportPlane(RangeScan& scan, const Eigen::AlignedBox3d& box,
                                      const PlaneRemovalParameters& params) {
  PlaneRemovalReport report;
  report.pixels_before = scan.validPixels();
  std::vector<std::size_t> candidates;
  const Eigen::Vector3d up = params.up.normalized();
  double lowest = std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner)
    lowest = std::min(lowest, up.dot(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner))));
  const double highest = lowest + params.band;
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    const Eigen::Vector3d& q = scan.points[k];
    const double height = up.dot(q);
    if (height >= lowest && height <= highest && box.contains(q)) candidates.push_back(k);
  }
  if (candidates.size() < std::max<std::size_t>(3, params.min_inliers)) return report;

  // A fixed-seed engine and modulo draws: the same input gives the same
  // plane on every standard library (distributions are not portable).
  std::mt19937_64 rng(params.seed);
  const double cos_tilt = std::cos(params.max_tilt);
  Eigen::Vector4d best = Eigen::Vector4d::Zero();
  std::size_t best_count = 0;
  for (int it = 0; it < params.iterations; ++it) {
    const Eigen::Vector3d& a = scan.points[candidates[rng() % candidates.size()]];
    const Eigen::Vector3d& b = scan.points[candidates[rng() % candidates.size()]];
    const Eigen::Vector3d& c = scan.points[candidates[rng() % candidates.size()]];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    n.normalize();
    if (n.dot(up) < 0) n = -n;
    if (n.dot(up) < cos_tilt) continue;
    const double d = -n.dot(a);
    std::size_t count = 0;
    for (std::size_t k : candidates) count += std::abs(n.dot(scan.points[k]) + d) <= params.inlier_distance;
    if (count > best_count) {
      best_count = count;
      best << n, d;
    }
  }
  if (best_count < params.min_inliers) return report;

  // A support faces up. The candidates near the plane, an even stride of
  // at most `normal_samples` of them, each get the normal of its nearest
  // candidates (turned towards the sensor): enough of them must face up,
  // and make most of those near the plane. An object's lowest slab of
  // sides fits a horizontal plane 4 mm thick but faces sideways.
  std::vector<Eigen::Vector3d> band(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) band[k] = scan.points[candidates[k]];
  std::vector<std::size_t> near_plane;
  for (std::size_t k = 0; k < band.size(); ++k)
    if (std::abs(best.head<3>().dot(band[k]) + best[3]) <= params.inlier_distance) near_plane.push_back(k);
  const KdTree tree(band);
  const std::size_t stride = std::max<std::size_t>(1, (near_plane.size() + params.normal_samples - 1) /
                                                          std::max<std::size_t>(1, params.normal_samples));
  const double cos_normal = std::cos(params.max_normal_angle);
  const Eigen::Vector3d sensor = scan.sensor_pose.translation();
  std::size_t sampled = 0, facing = 0;
  for (std::size_t s = 0; s < near_plane.size(); s += stride) {
    const Eigen::Vector3d& q = band[near_plane[s]];
    const std::vector<Neighbour> near = tree.nearest(q, params.normal_neighbours);
    ++sampled;
    if (near.size() < 3) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Neighbour& n : near) mean += band[n.index];
    mean /= static_cast<double>(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Neighbour& n : near) cov += (band[n.index] - mean) * (band[n.index] - mean).transpose();
    Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0).normalized();
    if (normal.dot(sensor - q) < 0) normal = -normal;
    facing += normal.dot(best.head<3>()) >= cos_normal && normal.dot(up) >= cos_normal;
  }
  if (static_cast<double>(facing) < params.min_facing_share * static_cast<double>(sampled) ||
      static_cast<double>(facing * stride) < static_cast<double>(params.min_inliers))
    return report;

  // Least-squares refinement on the inliers (smallest eigenvector of the covariance).
  for (int round = 0; round < 2; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::size_t count = 0;
    for (std::size_t k : candidates)
      if (std::abs(best.head<3>().dot(scan.points[k]) + best[3]) <= params.inlier_distance) {
        mean += scan.points[k];
        ++count;
      }
    if (count < 3) break;
    mean /= static_cast<double>(count);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t k : candidates)
      if (std::abs(best.head<3>().dot(scan.points[k]) + best[3]) <= params.inlier_distance) {
        const Eigen::Vector3d e = scan.points[k] - mean;
        cov += e * e.transpose();
      }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
    Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
    if (n.dot(up) < 0) n = -n;
    best << n, -n.dot(mean);
    report.inliers = count;
  }

  report.found = true;
  report.plane = best;
  std::vector<std::uint8_t> reject(scan.range.size(), 0);
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    const double s = best.head<3>().dot(scan.points[k]) + best[3];
    if (std::abs(s) <= params.inlier_distance || (params.remove_below && s < 0)) reject[scan.pixels[k]] = 1;
  }
  const FilterReport applied = apply(scan, reject, report.pixels_before);
  report.removed = applied.removed;
  return report;
}

}  // namespace icrkit::reconstruction
