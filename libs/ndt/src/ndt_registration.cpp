#include "more_thuente_line_search.hpp"
#include "ndt_voxel_grid.hpp"

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/ndt/ndt_registration.hpp>

#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

namespace icrkit::ndt {

namespace {

// Points per accumulation block. Fixed (not derived from the thread count) so
// the partial sums, and the order they are added in, never change.
constexpr std::size_t kBlockSize = 512;
constexpr std::size_t kSerialBlocks = 4;

void validateCloud(const std::vector<Eigen::Vector3d>& points, const std::string& name) {
  if (points.empty()) throw InputError(name, "", "the cloud is empty; nothing to register");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw InputError(name, "point " + std::to_string(i), "non-finite coordinate, expected finite x, y, z");
}

void validateParameters(const NdtParameters& p) {
  if (p.resolutions.empty()) throw InputError("resolutions", "", "at least one resolution is needed");
  for (double r : p.resolutions)
    if (!(r > 0) || !std::isfinite(r))
      throw InputError("resolutions", "", "a resolution must be a positive length in metres, got " + std::to_string(r));
  if (!(p.outlier_ratio > 0 && p.outlier_ratio < 1))
    throw InputError("outlier_ratio", "", "expected a value in (0, 1), got " + std::to_string(p.outlier_ratio));
  if (p.min_points_per_cell < 3)
    throw InputError("min_points_per_cell", "", "a covariance needs at least 3 points, got " +
                                                     std::to_string(p.min_points_per_cell));
  if (!(p.min_eigenvalue_ratio > 0 && p.min_eigenvalue_ratio <= 1))
    throw InputError("min_eigenvalue_ratio", "", "expected a value in (0, 1], got " + std::to_string(p.min_eigenvalue_ratio));
  if (p.max_iterations < 1) throw InputError("max_iterations", "", "at least one iteration");
  if (!(p.max_step_cells > 0) || !(p.max_step_rotation > 0))
    throw InputError("max_step_cells", "", "the step limits must be positive");
  if (p.max_line_search_evaluations < 1) throw InputError("max_line_search_evaluations", "", "at least one evaluation");
}

// Rotation about one axis with its first and second derivative w.r.t. the angle.
struct AxisRotation {
  Eigen::Matrix3d r, d1, d2;
};

AxisRotation axisRotation(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  AxisRotation a;
  a.r.setZero();
  a.d1.setZero();
  a.d2.setZero();
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane the axis rotates
  a.r(axis, axis) = 1.0;
  a.r(i, i) = c, a.r(i, j) = -s, a.r(j, i) = s, a.r(j, j) = c;
  a.d1(i, i) = -s, a.d1(i, j) = -c, a.d1(j, i) = c, a.d1(j, j) = -s;
  a.d2(i, i) = -c, a.d2(i, j) = s, a.d2(j, i) = -s, a.d2(j, j) = -c;
  return a;
}

// R(phi) = Rx Ry Rz and its partial derivatives: these 3 + 6 matrices,
// applied to a point, are Magnusson's Jacobian columns (Eq. 6.18-6.19) and
// second-derivative vectors (Eq. 6.20-6.21) without expanding the products.
struct RotationDerivatives {
  Eigen::Matrix3d r;
  std::array<Eigen::Matrix3d, 3> first;
  std::array<std::array<Eigen::Matrix3d, 3>, 3> second;  // symmetric
};

RotationDerivatives rotationDerivatives(const Vector6d& x) {
  const std::array<AxisRotation, 3> a{axisRotation(0, x(3)), axisRotation(1, x(4)), axisRotation(2, x(5))};
  // Product of the three factors, factor k differentiated `order[k]` times.
  auto product = [&](const std::array<int, 3>& order) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
    for (int k = 0; k < 3; ++k) {
      const AxisRotation& f = a[static_cast<std::size_t>(k)];
      m = m * (order[static_cast<std::size_t>(k)] == 0 ? f.r : order[static_cast<std::size_t>(k)] == 1 ? f.d1 : f.d2);
    }
    return m;
  };
  RotationDerivatives d;
  d.r = product({0, 0, 0});
  for (int i = 0; i < 3; ++i) {
    std::array<int, 3> o{0, 0, 0};
    o[static_cast<std::size_t>(i)] = 1;
    d.first[static_cast<std::size_t>(i)] = product(o);
    for (int j = 0; j < 3; ++j) {
      std::array<int, 3> oo{0, 0, 0};
      ++oo[static_cast<std::size_t>(i)];
      ++oo[static_cast<std::size_t>(j)];
      d.second[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = product(oo);
    }
  }
  return d;
}

// The objective at one resolution over source points already moved by the
// current estimate; x is the left perturbation.
class Objective {
public:
  Objective(std::vector<Eigen::Vector3d> points, const NdtVoxelGrid& grid, NdtConstants constants,
            NdtNeighbourhood neighbourhood)
      : points_(std::move(points)), grid_(grid), c_(constants), neighbourhood_(neighbourhood) {}

  NdtEvaluation operator()(const Vector6d& x, bool with_hessian) const {
    const RotationDerivatives rd = rotationDerivatives(x);
    const Eigen::Vector3d t = x.head<3>();
    const double amplitude = -c_.d1;  // > 0
    const double d2 = c_.d2;
    const std::size_t n = points_.size();
    const std::size_t blocks = (n + kBlockSize - 1) / kBlockSize;
    std::vector<NdtEvaluation> partial(blocks);
    auto evaluate = [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<int> cells;
      cells.reserve(27);
      for (std::size_t b = range.begin(); b != range.end(); ++b) {
        NdtEvaluation& acc = partial[b];
        const std::size_t end = std::min(n, (b + 1) * kBlockSize);
        for (std::size_t i = b * kBlockSize; i < end; ++i) {
          const Eigen::Vector3d& p = points_[i];
          const Eigen::Vector3d y = rd.r * p + t;
          grid_.lookup(y, neighbourhood_, cells);
          if (cells.empty()) continue;
          ++acc.points_scored;
          // The Jacobian is [I | B], B's columns the rotation derivatives
          // applied to p: its identity block is used as such (J^T C J =
          // [C, C B; B^T C, B^T C B]), and the second-derivative vectors,
          // which depend on the point alone, are made once for all its cells.
          Eigen::Matrix3d b;
          for (int k = 0; k < 3; ++k) b.col(k) = rd.first[static_cast<std::size_t>(k)] * p;
          std::array<Eigen::Vector3d, 9> second;
          if (with_hessian)
            for (int a = 0; a < 3; ++a)
              for (int bb = 0; bb < 3; ++bb)
                second[static_cast<std::size_t>(3 * a + bb)] =
                    rd.second[static_cast<std::size_t>(a)][static_cast<std::size_t>(bb)] * p;
          for (int c : cells) {
            const NdtCell& cell = grid_.cells()[static_cast<std::size_t>(c)];
            const Eigen::Vector3d q = y - cell.mean;
            const Eigen::Vector3d cq = cell.inverse_covariance * q;
            const double e = std::exp(-0.5 * d2 * q.dot(cq));
            acc.value -= amplitude * e;
            Vector6d gq;  // q^T C J_i
            gq.head<3>() = cq;
            gq.tail<3>() = b.transpose() * cq;
            const double w = amplitude * d2 * e;
            acc.gradient.noalias() += w * gq;
            if (!with_hessian) continue;
            const Eigen::Matrix3d btc = b.transpose() * cell.inverse_covariance;
            Matrix6d h;
            h.topLeftCorner<3, 3>() = cell.inverse_covariance;
            h.topRightCorner<3, 3>() = cell.inverse_covariance * b;
            h.bottomLeftCorner<3, 3>() = btc;
            h.bottomRightCorner<3, 3>() = btc * b;
            h.noalias() -= d2 * gq * gq.transpose();
            for (int a = 0; a < 3; ++a)
              for (int bb = 0; bb < 3; ++bb) h(3 + a, 3 + bb) += cq.dot(second[static_cast<std::size_t>(3 * a + bb)]);
            acc.hessian.noalias() += w * h;
          }
        }
      }
    };
    // The same blocks either way (the sums do not depend on it); a few
    // blocks are not worth the tasks, and a registration run per view in
    // parallel (the model alignment) keeps the cores busy already.
    if (blocks <= kSerialBlocks)
      evaluate(tbb::blocked_range<std::size_t>(0, blocks, 1));
    else
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), evaluate);
    NdtEvaluation total;
    for (const NdtEvaluation& e : partial) {  // in block order: deterministic
      total.value += e.value;
      total.gradient += e.gradient;
      total.hessian += e.hessian;
      total.points_scored += e.points_scored;
    }
    return total;
  }

private:
  std::vector<Eigen::Vector3d> points_;
  const NdtVoxelGrid& grid_;
  NdtConstants c_;
  NdtNeighbourhood neighbourhood_;
};

// Centroid per occupied cube, cubes in order of first occurrence (serial:
// the same points whatever the thread count).
std::vector<Eigen::Vector3d> voxelCentroids(const std::vector<Eigen::Vector3d>& points, double size) {
  std::unordered_map<std::int64_t, std::size_t> slot;
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  constexpr std::int64_t kHalf = 1 << 20;
  for (const Eigen::Vector3d& p : points) {
    std::int64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      const double c = std::clamp(std::floor(p(k) / size), -double(kHalf), double(kHalf - 1));
      key = (key << 21) | (static_cast<std::int64_t>(c) + kHalf);
    }
    const auto [it, added] = slot.emplace(key, sums.size());
    if (added) {
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[it->second] += p;
    ++counts[it->second];
  }
  for (std::size_t i = 0; i < sums.size(); ++i) sums[i] /= counts[i];
  return sums;
}

std::vector<Eigen::Vector3d> transformed(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& pose) {
  std::vector<Eigen::Vector3d> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = pose * points[i];
  return out;
}

// A Newton direction from a Hessian that may be indefinite away from the
// optimum: eigenvalues are replaced by their magnitudes (floored relative to
// the largest), which keeps the curvature scaling and guarantees descent.
Vector6d newtonDirection(const Matrix6d& hessian, const Vector6d& gradient) {
  Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 * (hessian + hessian.transpose()));
  Vector6d values = eigen.eigenvalues().cwiseAbs();
  const double largest = values.maxCoeff();
  if (!(largest > 0)) return -gradient;
  values = values.cwiseMax(1e-9 * largest);
  return -(eigen.eigenvectors() * values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose() * gradient);
}

}  // namespace

NdtConstants ndtConstants(double resolution, const NdtParameters& params) {
  // Magnusson Eq. 6.8: -log(c1 exp(-m/2) + c2) ~ d1 exp(-d2 m / 2) + d3,
  // matched at m = 0, m = 1 and m -> infinity. c1 = 10 (1 - p) is his
  // choice for the Gaussian's weight, c2 = p / V the uniform density.
  const double volume = params.scale_invariant_constants ? 1.0 : resolution * resolution * resolution;
  const double c1 = 10.0 * (1.0 - params.outlier_ratio);
  const double c2 = params.outlier_ratio / volume;
  const double d3 = -std::log(c2);
  NdtConstants k;
  k.d1 = -std::log(c1 + c2) - d3;
  k.d2 = -2.0 * std::log((-std::log(c1 * std::exp(-0.5) + c2) - d3) / k.d1);
  return k;
}

Eigen::Isometry3d ndtPoseFromParameters(const Vector6d& x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotationDerivatives(x).r;
  pose.translation() = x.head<3>();
  return pose;
}

NdtTarget::NdtTarget(const PointCloud& cloud, const NdtParameters& params)
    : points_(cloud.positions), min_points_(params.min_points_per_cell), min_eigenvalue_ratio_(params.min_eigenvalue_ratio) {
  validateCloud(points_, "target cloud");
  validateParameters(params);
  for (double r : params.resolutions)
    if (!grid(r)) grids_.push_back(std::make_unique<NdtVoxelGrid>(points_, r, min_points_, min_eigenvalue_ratio_));
}

NdtTarget::~NdtTarget() = default;
NdtTarget::NdtTarget(NdtTarget&&) noexcept = default;
NdtTarget& NdtTarget::operator=(NdtTarget&&) noexcept = default;

const NdtVoxelGrid* NdtTarget::grid(double resolution) const {
  for (const auto& g : grids_)
    if (g->resolution() == resolution) return g.get();
  return nullptr;
}

std::size_t NdtTarget::cellCount(double resolution) const {
  const NdtVoxelGrid* g = grid(resolution);
  return g ? g->size() : 0;
}

namespace {

// The prebuilt grid, or one built into `storage` with the target's settings.
const NdtVoxelGrid& gridFor(const NdtTarget& target, double resolution, std::unique_ptr<NdtVoxelGrid>& storage) {
  if (const NdtVoxelGrid* g = target.grid(resolution)) return *g;
  storage = std::make_unique<NdtVoxelGrid>(target.points(), resolution, target.minPointsPerCell(),
                                           target.minEigenvalueRatio());
  return *storage;
}

}  // namespace

NdtEvaluation evaluateNdt(const PointCloud& source, const NdtTarget& target, double resolution,
                          const Eigen::Isometry3d& pose, const Vector6d& x, const NdtParameters& params) {
  validateCloud(source.positions, "source cloud");
  validateParameters(params);
  std::unique_ptr<NdtVoxelGrid> storage;
  const NdtVoxelGrid& grid = gridFor(target, resolution, storage);
  const Objective objective(transformed(source.positions, pose), grid, ndtConstants(resolution, params),
                            params.neighbourhood);
  return objective(x, true);
}

NdtResult registerNdt(const PointCloud& source, const NdtTarget& target, const Eigen::Isometry3d& initial_guess,
                      const NdtParameters& params) {
  const auto start = std::chrono::steady_clock::now();
  validateCloud(source.positions, "source cloud");
  validateParameters(params);
  if (!initial_guess.matrix().allFinite()) throw InputError("initial guess", "", "non-finite pose");

  if (!(params.source_voxel_size >= 0) || !std::isfinite(params.source_voxel_size))
    throw InputError("source_voxel_size", "", "expected 0 (off) or a positive length in metres");
  const std::vector<Eigen::Vector3d> points =
      params.source_voxel_size > 0 ? voxelCentroids(source.positions, params.source_voxel_size) : source.positions;

  NdtResult result;
  Eigen::Isometry3d pose = initial_guess;
  for (std::size_t level = 0; level < params.resolutions.size(); ++level) {
    const double resolution = params.resolutions[level];
    std::unique_ptr<NdtVoxelGrid> storage;
    const NdtVoxelGrid& grid = gridFor(target, resolution, storage);
    const NdtConstants constants = ndtConstants(resolution, params);
    const bool last = level + 1 == params.resolutions.size();
    int iterations = 0;
    bool converged = false;
    while (iterations < params.max_iterations) {
      const Objective objective(transformed(points, pose), grid, constants, params.neighbourhood);
      const NdtEvaluation here = objective(Vector6d::Zero(), true);
      if (here.points_scored == 0) {
        if (level == 0)
          throw InputError("initial guess", "",
                           "no source point falls near a target Gaussian; the clouds do not overlap at " +
                               std::to_string(resolution) + " m");
        break;  // a finer grid lost the cloud: keep the coarser result
      }
      const Vector6d direction = newtonDirection(here.hessian, here.gradient);
      const double slope = here.gradient.dot(direction);
      if (!(slope < 0)) {  // zero gradient: at a stationary point already
        converged = true;
        break;
      }
      // Longest step: a fraction of a cell and a bounded rotation.
      const double translation = direction.head<3>().norm(), rotation = direction.tail<3>().norm();
      double step_max = 2.0;
      if (translation > 0) step_max = std::min(step_max, params.max_step_cells * resolution / translation);
      if (rotation > 0) step_max = std::min(step_max, params.max_step_rotation / rotation);
      LineSearchParameters ls;
      ls.step_max = step_max;
      ls.max_evaluations = params.max_line_search_evaluations;
      const LineSearchResult found = moreThuenteLineSearch(
          [&](double a, double* derivative) {
            const NdtEvaluation e = objective(a * direction, false);
            *derivative = e.gradient.dot(direction);
            return e.value;
          },
          here.value, slope, std::min(1.0, step_max), ls);
      ++iterations;
      const Vector6d delta = found.step * direction;
      pose = ndtPoseFromParameters(delta) * pose;
      // No decrease found along a descent direction (step 0) means the
      // optimum is closer than rounding can resolve: the step criterion holds.
      if (delta.head<3>().norm() < params.translation_epsilon && delta.tail<3>().norm() < params.rotation_epsilon) {
        converged = true;
        break;
      }
    }
    result.iterations.push_back(iterations);
    if (last) {
      result.converged = converged;
      const Objective objective(transformed(points, pose), grid, constants, params.neighbourhood);
      const NdtEvaluation final_eval = objective(Vector6d::Zero(), true);
      result.score = -final_eval.value;
      result.normalized_score = result.score / (-constants.d1 * static_cast<double>(points.size()));
      result.hessian = final_eval.hessian;
      result.points_scored = final_eval.points_scored;
    }
  }
  // Re-orthonormalise: many small left-multiplied steps drift by rounding.
  pose.linear() = Eigen::Quaterniond(pose.rotation()).normalized().toRotationMatrix();
  result.pose = pose;
  result.time_ms = millisecondsSince(start);
  return result;
}

}  // namespace icrkit::ndt
