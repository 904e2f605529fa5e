#include "registration_observability.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace icrkit::reconstruction {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace

Matrix6 adjoint(const Eigen::Isometry3d& t) {
  Matrix6 ad = Matrix6::Zero();
  const Eigen::Matrix3d r = t.rotation();
  ad.topLeftCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = skew(t.translation()) * r;
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

Vector6 smallMotionLog(const Eigen::Isometry3d& t) {
  Vector6 x;
  const Eigen::AngleAxisd aa(t.rotation());
  x.head<3>() = t.translation();
  x.tail<3>() = aa.angle() * aa.axis();
  return x;
}

Eigen::Isometry3d smallMotionExp(const Vector6& x) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const double angle = x.tail<3>().norm();
  if (angle > 0) t.linear() = Eigen::AngleAxisd(angle, x.tail<3>() / angle).toRotationMatrix();
  t.translation() = x.head<3>();
  return t;
}

namespace {

struct CentredFrame {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Matrix6 to_origin = Matrix6::Identity();  // x (about the origin) = to_origin * u
};

// u = [t about the centroid; radius * theta]: metres in every component.
CentredFrame centredFrame(const std::vector<Eigen::Vector3d>& points) {
  CentredFrame f;
  if (points.empty()) return f;
  for (const Eigen::Vector3d& p : points) f.centroid += p;
  f.centroid /= double(points.size());
  double radius2 = 0.0;
  for (const Eigen::Vector3d& p : points) radius2 += (p - f.centroid).squaredNorm();
  f.radius = std::sqrt(radius2 / double(points.size()));
  if (!(f.radius > 0)) return f;
  Eigen::Isometry3d to_centroid = Eigen::Isometry3d::Identity();
  to_centroid.translation() = f.centroid;
  Matrix6 scale = Matrix6::Identity();
  scale.bottomRightCorner<3, 3>() /= f.radius;
  f.to_origin = adjoint(to_centroid) * scale;
  return f;
}

// Keeps the eigen-directions of `h` (in u coordinates) above `ratio` times
// the largest eigenvalue.
Observability fromCentredMatrix(const Matrix6& h, const Matrix6& to_origin, double ratio) {
  Observability result;
  const Eigen::SelfAdjointEigenSolver<Matrix6> eigen(0.5 * (h + h.transpose()));
  const double largest = eigen.eigenvalues()(5);
  if (!(largest > 0)) return result;
  result.weakest_ratio = std::max(0.0, eigen.eigenvalues()(0)) / largest;
  Matrix6 keep = Matrix6::Zero();
  for (int k = 0; k < 6; ++k) {
    if (eigen.eigenvalues()(k) >= ratio * largest) {
      keep += eigen.eigenvectors().col(k) * eigen.eigenvectors().col(k).transpose();
    } else {
      ++result.degenerate_directions;
    }
  }
  result.projector = to_origin * keep * to_origin.inverse();
  return result;
}

}  // namespace

Observability surfaceObservability(const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<Eigen::Vector3d>& normals, double ratio) {
  const CentredFrame f = centredFrame(points);
  if (!(f.radius > 0) || normals.size() != points.size()) return {};
  Matrix6 c = Matrix6::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double length = normals[i].norm();
    if (!(length > 0)) continue;
    const Eigen::Vector3d n = normals[i] / length;
    Vector6 row;
    // A small motion u moves p by t + theta x (p - c); along the normal
    // that is n.t + ((p - c) x n).theta, with theta = u_rot / radius.
    row.head<3>() = n;
    row.tail<3>() = (points[i] - f.centroid).cross(n) / f.radius;
    c.noalias() += row * row.transpose();
  }
  return fromCentredMatrix(c, f.to_origin, ratio);
}

}  // namespace icrkit::reconstruction
