/// \file
/// Range image filters. They work on pixels (range set to 0) so that the
/// image stays the single source of truth; points follow by pixel index.

#include <icrkit/reconstruction/input/scan_filters.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
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
  const double z_min = box.min().z(), z_max = box.min().z() + params.band;
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    const Eigen::Vector3d& q = scan.points[k];
    if (q.z() >= z_min && q.z() <= z_max && q.x() >= box.min().x() && q.x() <= box.max().x() &&
        q.y() >= box.min().y() && q.y() <= box.max().y())
      candidates.push_back(k);
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
    if (n.z() < 0) n = -n;
    if (n.z() < cos_tilt) continue;
    const double d = -n.dot(a);
    std::size_t count = 0;
    for (std::size_t k : candidates) count += std::abs(n.dot(scan.points[k]) + d) <= params.inlier_distance;
    if (count > best_count) {
      best_count = count;
      best << n, d;
    }
  }
  if (best_count < params.min_inliers) return report;

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
    if (n.z() < 0) n = -n;
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
