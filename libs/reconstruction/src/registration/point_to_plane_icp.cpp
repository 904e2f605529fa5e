#include <icrkit/reconstruction/registration/point_to_plane_icp.hpp>

#include <icrkit/core/error.hpp>

#include <icrkit/core/kd_tree.hpp>

#include "nearest_tracker.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace icrkit::reconstruction {

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Isometry3d exponential(const Vector6d& x) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const double angle = x.tail<3>().norm();
  if (angle > 0) t.linear() = Eigen::AngleAxisd(angle, x.tail<3>() / angle).toRotationMatrix();
  t.translation() = x.head<3>();
  return t;
}

using Tracker = NearestTracker<KdTree>;

double tukeyWeight(double r, double width) {
  const double u = r / width;
  if (std::abs(u) >= 1.0) return 0.0;
  const double a = 1.0 - u * u;
  return a * a;
}

struct Normal {
  Matrix6d hessian = Matrix6d::Zero();
  Vector6d gradient = Vector6d::Zero();
  double weighted_sq = 0.0, weight = 0.0;
  std::size_t count = 0;
};

// The normal equations of the point-to-plane residuals at `pose`.
Normal accumulate(const std::vector<Eigen::Vector3d>& source, const IcpTarget& target, const Eigen::Isometry3d& pose,
                  double max_distance, double width, Tracker& tracker) {
  Normal eq;
  const auto& points = target.points();
  const auto& normals = target.normals();
  auto correspond = [&](std::size_t, const Eigen::Vector3d& p, long k) {
    const Eigen::Vector3d& n = normals[static_cast<std::size_t>(k)];
    const double r = n.dot(p - points[static_cast<std::size_t>(k)]);
    const double w = tukeyWeight(r, width);
    if (!(w > 0)) return;
    Vector6d j;
    j.head<3>() = n;
    j.tail<3>() = p.cross(n);
    eq.hessian.noalias() += w * j * j.transpose();
    eq.gradient.noalias() += w * r * j;
    eq.weighted_sq += w * r * r;
    eq.weight += w;
    ++eq.count;
  };
  tracker.forEachNearest(source, pose, max_distance, points, target.tree(), correspond);
  return eq;
}

}  // namespace

struct IcpTarget::Impl {
  std::vector<Eigen::Vector3d> points, normals;
  KdTree tree;  // over `points`, which the Impl owns and never moves
  Impl(std::vector<Eigen::Vector3d> p, std::vector<Eigen::Vector3d> n)
      : points(std::move(p)), normals(std::move(n)), tree(points) {}
};

IcpTarget::IcpTarget(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals) {
  if (points.empty()) throw InputError("ICP target", "", "no points");
  if (points.size() != normals.size())
    throw InputError("ICP target", "", std::to_string(points.size()) + " points but " +
                                           std::to_string(normals.size()) + " normals");
  impl_ = std::make_unique<Impl>(std::move(points), std::move(normals));
}

IcpTarget::~IcpTarget() = default;
IcpTarget::IcpTarget(IcpTarget&&) noexcept = default;
IcpTarget& IcpTarget::operator=(IcpTarget&&) noexcept = default;

const std::vector<Eigen::Vector3d>& IcpTarget::points() const { return impl_->points; }
const std::vector<Eigen::Vector3d>& IcpTarget::normals() const { return impl_->normals; }

long IcpTarget::nearest(const Eigen::Vector3d& query, double max_distance) const {
  return impl_->tree.nearestWithin(query, max_distance);
}

const KdTree& IcpTarget::tree() const { return impl_->tree; }

PointToPlaneIcpResult registerPointToPlane(const std::vector<Eigen::Vector3d>& source, const IcpTarget& target,
                                           const Eigen::Isometry3d& initial_guess,
                                           const PointToPlaneIcpParameters& params) {
  PointToPlaneIcpResult result;
  result.pose = initial_guess;
  if (source.empty() || params.max_distances.empty()) {
    result.failed = true;
    return result;
  }
  Tracker tracker(source, Tracker::Parameters{});
  for (double max_distance : params.max_distances) {
    const double width = std::min(params.kernel_width, max_distance);
    result.converged = false;
    for (int it = 0; it < params.max_iterations; ++it) {
      const Normal eq = accumulate(source, target, result.pose, max_distance, width, tracker);
      if (eq.count < params.min_correspondences) {
        result.failed = true;
        return result;
      }
      ++result.iterations;
      // A tiny ridge keeps the step finite along directions the overlap
      // does not constrain (a planar patch slides); the pose graph is told
      // about them through the Hessian.
      Matrix6d h = eq.hessian;
      h.diagonal().array() += 1e-9 * std::max(1.0, h.diagonal().maxCoeff());
      const Vector6d step = -h.ldlt().solve(eq.gradient);
      if (!step.allFinite()) {
        result.failed = true;
        return result;
      }
      result.pose = exponential(step) * result.pose;
      if (step.head<3>().norm() < params.translation_epsilon && step.tail<3>().norm() < params.rotation_epsilon) {
        result.converged = true;
        break;
      }
    }
  }
  const double last = params.max_distances.back();
  const Normal eq = accumulate(source, target, result.pose, last, std::min(params.kernel_width, last), tracker);
  result.correspondences = eq.count;
  result.inlier_fraction = double(eq.count) / double(source.size());
  result.rms_m = eq.weight > 0 ? std::sqrt(eq.weighted_sq / eq.weight) : 0.0;
  result.hessian = 0.5 * (eq.hessian + eq.hessian.transpose());
  if (eq.count < params.min_correspondences) result.failed = true;
  return result;
}

}  // namespace icrkit::reconstruction
