#pragma once
// Private to libs/ndt: the sums a window's plane fit needs, and a cube's
// candidate positions laid out for the distance test of every point of
// the cube (RadiusCells), shared by the normals and the smoothing pass.

#include <icrkit/core/radius_cells.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace icrkit::ndt {

// Count, sum and scatter of offsets d = q - p from a query point p, in the
// order added; the largest |d|^2.
struct WindowMoments {
  std::size_t count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  double reach_sq = 0;

  void add(const Eigen::Vector3d& d) {
    ++count;
    sum += d;
    xx += d.x() * d.x();
    xy += d.x() * d.y();
    xz += d.x() * d.z();
    yy += d.y() * d.y();
    yz += d.y() * d.z();
    zz += d.z() * d.z();
    reach_sq = std::max(reach_sq, d.squaredNorm());
  }
  Eigen::Matrix3d outer() const {
    Eigen::Matrix3d m;
    m << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return m;
  }
};

// The points of the cubes around one cube (RadiusCells), their positions
// copied side by side (x, y, z arrays), cube by cube: the distance test of
// every point of the cube then runs over contiguous memory, and skips the
// cubes too far from the point as a whole.
struct CandidatePositions {
  struct Span {
    std::size_t begin, end;
    Eigen::Vector3d min, max;  // the cube's box
  };
  std::vector<std::size_t> cubes;
  std::vector<Span> spans;
  std::vector<std::uint32_t> index;
  std::vector<double> x, y, z;

  void gather(const std::vector<Eigen::Vector3d>& points, const RadiusCells& cells, std::size_t c) {
    cells.neighbourCells(c, cubes);
    spans.clear();
    index.clear();
    for (std::size_t cube : cubes) {
      // The box a little larger than the cube: its corners are rounded, and
      // a point on a face must never be skipped.
      const Eigen::Vector3d min = cells.cellMin(cube);
      const double slack = 1e-9 * cells.edge() + 1e-12 * (1.0 + min.cwiseAbs().maxCoeff());
      spans.push_back({index.size(), index.size() + static_cast<std::size_t>(cells.cellEnd(cube) - cells.cellBegin(cube)),
                       min - Eigen::Vector3d::Constant(slack),
                       min + Eigen::Vector3d::Constant(cells.edge() + slack)});
      index.insert(index.end(), cells.cellBegin(cube), cells.cellEnd(cube));
    }
    x.resize(index.size());
    y.resize(index.size());
    z.resize(index.size());
    for (std::size_t k = 0; k < index.size(); ++k) {
      const Eigen::Vector3d& q = points[index[k]];
      x[k] = q.x();
      y[k] = q.y();
      z[k] = q.z();
    }
  }

  // The number of candidates within sqrt(radius_sq) of p (distance <=
  // radius); their slots (into index, x, y, z), in the candidates' order,
  // are the first that many of `slots`. Written without a branch per
  // candidate: about a third pass, which no predictor guesses.
  std::size_t within(const Eigen::Vector3d& p, double radius_sq, std::vector<std::uint32_t>& slots) const {
    if (slots.size() < index.size()) slots.resize(index.size());
    std::size_t count = 0;
    for (const Span& span : spans) {
      const double gap = (span.min - p).cwiseMax(p - span.max).cwiseMax(0.0).squaredNorm();
      if (gap > radius_sq) continue;
      for (std::size_t k = span.begin; k < span.end; ++k) {
        const double dx = x[k] - p.x(), dy = y[k] - p.y(), dz = z[k] - p.z();
        slots[count] = static_cast<std::uint32_t>(k);
        count += (dx * dx + dy * dy + dz * dz <= radius_sq) ? 1 : 0;
      }
    }
    return count;
  }

  Eigen::Vector3d offset(std::uint32_t slot, const Eigen::Vector3d& p) const {
    return Eigen::Vector3d(x[slot] - p.x(), y[slot] - p.y(), z[slot] - p.z());
  }
};

}  // namespace icrkit::ndt
