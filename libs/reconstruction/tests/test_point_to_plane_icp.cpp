// Point-to-plane ICP: known motions of sampled surfaces, partial overlap,
// and failure without overlap.

#include <icrkit/reconstruction/registration/point_to_plane_icp.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_sampling.hpp>
#include <icrkit/sim/cad_objects.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace icrkit::reconstruction {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d motion(const Eigen::Vector3d& t, const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  m.translation() = t;
  return m;
}

struct Surface {
  PointCloud target, source;  // two independent samplings of one CAD object
};

Surface sampledObject(std::size_t count) {
  const TriangleMesh mesh = sim::makeCadObject(sim::CadObject::WoodenToy1);
  return {samplePointsUniformly(mesh, count, 1), samplePointsUniformly(mesh, count / 4, 2)};
}

TEST(PointToPlaneIcp, RecoversAKnownMotionOfAnotherSampling) {
  const Surface s = sampledObject(40000);
  const IcpTarget target(s.target.positions, s.target.normals);
  // The source is the object moved by `truth`; ICP starts from 3 mm and 1.5 deg off.
  const Eigen::Isometry3d truth = motion({0.01, -0.02, 0.005}, {1, 2, 3}, 10 * kDeg);
  std::vector<Eigen::Vector3d> source;
  for (const Eigen::Vector3d& p : s.source.positions) source.push_back(truth.inverse() * p);
  const Eigen::Isometry3d start = motion({0.002, -0.002, 0.001}, {3, -1, 1}, 1.5 * kDeg) * truth;
  PointToPlaneIcpParameters params;
  params.max_distances = {0.01, 0.005, 0.002};
  const PointToPlaneIcpResult r = registerPointToPlane(source, target, start, params);
  ASSERT_FALSE(r.failed);
  EXPECT_TRUE(r.converged);
  const Eigen::Isometry3d error = r.pose * truth.inverse();
  // Two samplings of one surface differ only by the tangent planes' chords.
  EXPECT_LT(error.translation().norm(), 1e-4);
  EXPECT_LT(Eigen::AngleAxisd(error.rotation()).angle(), 0.02 * kDeg);
  EXPECT_GT(r.inlier_fraction, 0.95);
  EXPECT_LT(r.rms_m, 2e-4);
  // The Hessian is positive definite: every direction of a closed object is observed.
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6>(r.hessian).eigenvalues()(0), 0.0);
}

TEST(PointToPlaneIcp, PartialOverlapWithNoiseStillConverges) {
  const Surface s = sampledObject(40000);
  std::vector<Eigen::Vector3d> target_points, target_normals;
  const Eigen::Vector3d centre = s.target.bounds().center();
  // Target: one half of the object; source: the other half plus a third of the first.
  for (std::size_t i = 0; i < s.target.positions.size(); ++i)
    if (s.target.positions[i].x() < centre.x() + 0.01) {
      target_points.push_back(s.target.positions[i]);
      target_normals.push_back(s.target.normals[i]);
    }
  const IcpTarget target(target_points, target_normals);
  const Eigen::Isometry3d truth = motion({-0.004, 0.003, 0.002}, {0, 1, 1}, 4 * kDeg);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.0003);
  std::vector<Eigen::Vector3d> source;
  for (const Eigen::Vector3d& p : s.source.positions)
    if (p.x() > centre.x() - 0.015)
      source.push_back(truth.inverse() * (p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))));
  const Eigen::Isometry3d start = motion({0.002, 0.001, -0.002}, {1, 0, 1}, 1.0 * kDeg) * truth;
  const PointToPlaneIcpResult r = registerPointToPlane(source, target, start);
  ASSERT_FALSE(r.failed);
  const Eigen::Isometry3d error = r.pose * truth.inverse();
  EXPECT_LT((error * centre - centre).norm(), 2e-4);
  EXPECT_LT(Eigen::AngleAxisd(error.rotation()).angle(), 0.1 * kDeg);
  EXPECT_LT(r.inlier_fraction, 0.8);  // the non-overlap is left out, not pulled in
}

TEST(PointToPlaneIcp, FailsWithoutOverlapAndChecksItsInput) {
  const Surface s = sampledObject(8000);
  const IcpTarget target(s.target.positions, s.target.normals);
  std::vector<Eigen::Vector3d> far;
  for (const Eigen::Vector3d& p : s.source.positions) far.push_back(p + Eigen::Vector3d(1.0, 0, 0));
  EXPECT_TRUE(registerPointToPlane(far, target, Eigen::Isometry3d::Identity()).failed);
  EXPECT_TRUE(registerPointToPlane({}, target, Eigen::Isometry3d::Identity()).failed);
  EXPECT_THROW(IcpTarget({Eigen::Vector3d::Zero()}, {}), InputError);
  EXPECT_THROW(IcpTarget({}, {}), InputError);
  EXPECT_EQ(target.nearest(s.target.positions[17], 1e-9), 17);
  EXPECT_EQ(target.nearest(Eigen::Vector3d(5, 5, 5), 0.01), -1);
}

}  // namespace
}  // namespace icrkit::reconstruction
