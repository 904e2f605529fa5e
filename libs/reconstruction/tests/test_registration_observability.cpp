// Surface observability (Gelfand et al. stability) on shapes whose
// unconstrained motions are known.

#include "registration/registration_observability.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace icrkit::reconstruction {
namespace {

struct Samples {
  std::vector<Eigen::Vector3d> points, normals;
};

Samples plane() {
  Samples s;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      s.points.emplace_back(0.01 * i, 0.01 * j, 0.0);
      s.normals.emplace_back(0, 0, 1);
    }
  return s;
}

Samples cylinder(const Eigen::Vector3d& offset) {  // axis parallel to z through `offset`
  Samples s;
  for (int i = 0; i < 60; ++i)
    for (int k = 0; k < 20; ++k) {
      const double a = 2 * M_PI * i / 60;
      s.points.push_back(offset + Eigen::Vector3d(0.05 * std::cos(a), 0.05 * std::sin(a), 0.01 * k));
      s.normals.emplace_back(std::cos(a), std::sin(a), 0);
    }
  return s;
}

Samples sphere() {
  Samples s;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    s.points.push_back(Eigen::Vector3d(0.3, 0.1, 0.2) + 0.05 * n);
    s.normals.push_back(-n);  // the sign does not matter
  }
  return s;
}

Samples boxCorner() {
  Samples s;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const double u = 0.005 * i, v = 0.005 * j;
      s.points.emplace_back(u, v, 0);
      s.normals.emplace_back(0, 0, 1);
      s.points.emplace_back(u, 0, v);
      s.normals.emplace_back(0, 1, 0);
      s.points.emplace_back(0, u, 2 * v);  // unequal faces: no symmetry
      s.normals.emplace_back(1, 0, 0);
    }
  return s;
}

// How far a small motion x = [t; theta] (about the origin) moves the
// samples, RMS: compares motions in metres whatever their mix.
double rmsDisplacement(const Samples& s, const Vector6& x) {
  double sum = 0.0;
  for (const Eigen::Vector3d& p : s.points)
    sum += (x.head<3>() + x.tail<3>().cross(p)).squaredNorm();
  return std::sqrt(sum / double(s.points.size()));
}

// The projector keeps x (observed) or removes it (unobserved), up to
// `tolerance` of the displacement x causes.
bool keeps(const Samples& s, const Observability& o, const Vector6& x, double tolerance = 1e-6) {
  return rmsDisplacement(s, o.projector * x - x) < tolerance * rmsDisplacement(s, x);
}
bool removes(const Samples& s, const Observability& o, const Vector6& x, double tolerance = 1e-6) {
  return rmsDisplacement(s, o.projector * x) < tolerance * rmsDisplacement(s, x);
}

Vector6 motion(double tx, double ty, double tz, double rx, double ry, double rz) {
  Vector6 x;
  x << tx, ty, tz, rx, ry, rz;
  return x;
}

TEST(SurfaceObservability, PlaneLeavesItsThreeInPlaneMotionsFree) {
  const Samples s = plane();
  const Observability o = surfaceObservability(s.points, s.normals, 0.01);
  EXPECT_EQ(o.degenerate_directions, 3);
  EXPECT_TRUE(removes(s, o, motion(1, 0, 0, 0, 0, 0)));
  EXPECT_TRUE(removes(s, o, motion(0, 1, 0, 0, 0, 0)));
  EXPECT_TRUE(keeps(s, o, motion(0, 0, 1, 0, 0, 0)));
}

TEST(SurfaceObservability, CylinderLeavesSlidingAndSpinningAboutItsAxisFree) {
  const Eigen::Vector3d offset(0.4, -0.2, 0.1);
  const Samples s = cylinder(offset);
  const Observability o = surfaceObservability(s.points, s.normals, 0.01);
  EXPECT_EQ(o.degenerate_directions, 2);
  EXPECT_TRUE(removes(s, o, motion(0, 0, 1, 0, 0, 0)));
  // A spin about the axis through `offset`, written about the origin:
  // theta = z, t = offset x ... = -theta x offset.
  const Eigen::Vector3d theta(0, 0, 1), t = -theta.cross(offset);
  EXPECT_TRUE(removes(s, o, motion(t.x(), t.y(), t.z(), 0, 0, 1)));
  EXPECT_TRUE(keeps(s, o, motion(1, 0, 0, 0, 0, 0)));
}

TEST(SurfaceObservability, SphereLeavesRotationsAboutItsCentreFree) {
  const Samples s = sphere();
  const Observability o = surfaceObservability(s.points, s.normals, 0.01);
  EXPECT_EQ(o.degenerate_directions, 3);
  // The samples' centroid lies ~1 mm off the centre (random points), so the
  // eigen-directions mix translation and rotation by a few per cent.
  EXPECT_TRUE(keeps(s, o, motion(1, 2, 3, 0, 0, 0), 0.05));
  const Eigen::Vector3d centre(0.3, 0.1, 0.2), theta(0.2, -1, 0.5), t = -theta.cross(centre);
  EXPECT_TRUE(removes(s, o, motion(t.x(), t.y(), t.z(), theta.x(), theta.y(), theta.z()), 0.05));
}

TEST(SurfaceObservability, ThreeFacesOfABoxFixEverything) {
  const Samples s = boxCorner();
  const Observability o = surfaceObservability(s.points, s.normals, 0.01);
  EXPECT_EQ(o.degenerate_directions, 0);
  EXPECT_GT(o.weakest_ratio, 0.01);
  EXPECT_TRUE(o.projector.isApprox(Matrix6::Identity(), 1e-9));
}

}  // namespace
}  // namespace icrkit::reconstruction
