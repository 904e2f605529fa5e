#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_sampling.hpp>
#include <icrkit/core/ray_caster.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <stdexcept>

namespace icrkit {
namespace {

using test::unitCube;

TEST(MeshSampling, PointsLieOnTheSurfaceWithTheirNormals) {
  const TriangleMesh sphere = makeIcosphere(3, 2.0, {1, 2, 3});
  const PointCloud cloud = samplePointsUniformly(sphere, 5000, 7);
  ASSERT_EQ(cloud.size(), 5000u);
  ASSERT_EQ(cloud.normals.size(), 5000u);
  EXPECT_FALSE(cloud.hasColours());
  EXPECT_NO_THROW(cloud.validate());
  const RayCaster caster(sphere);
  const auto closest = caster.closestPoints(cloud.positions);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_LE(closest[i].distance, 1e-14);
    EXPECT_NEAR(cloud.normals[i].norm(), 1.0, 1e-14);
    // Blended from the exact radial vertex normals: close to radial, and
    // closer to it than the face normal can be.
    const Eigen::Vector3d radial = (cloud.positions[i] - Eigen::Vector3d(1, 2, 3)).normalized();
    EXPECT_GT(cloud.normals[i].dot(radial), 0.999);
  }
}

TEST(MeshSampling, FaceNormalsWithoutVertexNormals) {
  const TriangleMesh cube = unitCube();
  const PointCloud cloud = samplePointsUniformly(cube, 600, 3);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    // The side a point lies on is the coordinate at 0 or 1, and its normal
    // the outward axis of that side.
    const Eigen::Vector3d& p = cloud.positions[i];
    const Eigen::Vector3d& n = cloud.normals[i];
    int axis;
    n.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(std::abs(n[axis]), 1.0, 1e-15);
    EXPECT_EQ(p[axis], n[axis] > 0 ? 1.0 : 0.0) << p.transpose() << " / " << n.transpose();
  }
}

TEST(MeshSampling, DensityIsUniformOverTheArea) {
  // Each side of the cube holds 1/6 of the area; each half of a sphere 1/2.
  const std::size_t n = 60000;
  const PointCloud cube = samplePointsUniformly(unitCube(), n, 11);
  int per_side[6] = {};
  for (std::size_t i = 0; i < n; ++i) {
    int axis;
    cube.normals[i].cwiseAbs().maxCoeff(&axis);
    ++per_side[2 * axis + (cube.normals[i][axis] > 0)];
  }
  const double sigma_side = std::sqrt(n * (1.0 / 6) * (5.0 / 6));  // binomial
  for (const int count : per_side) EXPECT_NEAR(count, n / 6.0, 5 * sigma_side);

  // Within one side: each quarter of the unit square holds 1/4, and the
  // mean is the centre (the two faces split it along a diagonal, so a
  // non-uniform draw inside a face would show).
  int quarter[4] = {};
  int on_top = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (cube.normals[i].z() != 1.0) continue;
    ++on_top;
    const Eigen::Vector2d xy = cube.positions[i].head<2>();
    mean += xy;
    ++quarter[2 * (xy.x() > 0.5) + (xy.y() > 0.5)];
  }
  mean /= on_top;
  EXPECT_NEAR(mean.x(), 0.5, 5 * std::sqrt(1.0 / 12 / on_top));
  EXPECT_NEAR(mean.y(), 0.5, 5 * std::sqrt(1.0 / 12 / on_top));
  const double sigma_quarter = std::sqrt(on_top * 0.25 * 0.75);
  for (const int count : quarter) EXPECT_NEAR(count, on_top / 4.0, 5 * sigma_quarter);

  const PointCloud sphere = samplePointsUniformly(makeIcosphere(4), n, 13);
  for (int axis = 0; axis < 3; ++axis) {
    int upper = 0;
    for (const auto& p : sphere.positions) upper += p[axis] > 0;
    EXPECT_NEAR(upper, n / 2.0, 5 * std::sqrt(n * 0.25)) << "axis " << axis;
  }
}

TEST(MeshSampling, DeterministicForASeedWhateverTheThreads) {
  const TriangleMesh sphere = makeIcosphere(2);
  const PointCloud a = samplePointsUniformly(sphere, 20000, 42);
  const PointCloud b = samplePointsUniformly(sphere, 20000, 42);
  PointCloud serial;
  tbb::task_arena(1).execute([&] { serial = samplePointsUniformly(sphere, 20000, 42); });
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.positions, serial.positions);
  EXPECT_EQ(a.normals, serial.normals);
  // A prefix does not depend on the count.
  const PointCloud fewer = samplePointsUniformly(sphere, 100, 42);
  EXPECT_TRUE(std::equal(fewer.positions.begin(), fewer.positions.end(), a.positions.begin()));
  EXPECT_NE(samplePointsUniformly(sphere, 100, 43).positions, fewer.positions);
}

TEST(MeshSampling, DegenerateFacesAreNeverPicked) {
  TriangleMesh mesh = unitCube();
  mesh.vertices.positions.push_back({5, 5, 5});
  mesh.faces.insert(mesh.faces.begin(), Triangle(8, 8, 8));   // a point
  mesh.faces.push_back(Triangle(0, 1, 0));                    // a segment
  const PointCloud cloud = samplePointsUniformly(mesh, 2000, 5);
  for (const auto& p : cloud.positions) EXPECT_LE(p.maxCoeff(), 1.0);
}

TEST(MeshSampling, PoissonDiskKeepsItsDistanceAndCoversTheSurface) {
  // A unit cube, d = 2 cm: no pair closer than d, median spacing near d,
  // and no point of the surface farther than 2 d from a sample.
  const TriangleMesh cube = unitCube();
  const double d = 0.02;
  const PointCloud cloud = samplePointsPoissonDisk(cube, d, 5);
  const KdTree tree(cloud.positions);
  std::vector<double> spacing;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto nearest = tree.nearest(cloud.positions[i], 2);
    spacing.push_back(nearest[1].distance);
  }
  std::sort(spacing.begin(), spacing.end());
  EXPECT_GE(spacing.front(), d);
  EXPECT_LE(spacing[spacing.size() / 2], 1.3 * d);
  // Area 6 m^2: a dense packing holds 6 / (0.866 d^2) = 17,300 disks.
  EXPECT_GT(cloud.size(), 8000u);
  EXPECT_LT(cloud.size(), 17321u);
  const PointCloud probes = samplePointsUniformly(cube, 2000, 99);
  for (const Eigen::Vector3d& p : probes.positions) EXPECT_LT(tree.nearest(p, 1)[0].distance, 2 * d);
  for (const Eigen::Vector3d& n : cloud.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  // Serial elimination over a seeded pool: the same points every run.
  const PointCloud again = samplePointsPoissonDisk(cube, d, 5);
  EXPECT_EQ(again.positions, cloud.positions);
  EXPECT_THROW(samplePointsPoissonDisk(cube, 0.0), std::invalid_argument);
}

TEST(MeshSampling, Errors) {
  EXPECT_EQ(samplePointsUniformly(TriangleMesh{}, 0).size(), 0u);
  EXPECT_THROW(samplePointsUniformly(TriangleMesh{}, 1), std::invalid_argument);
  TriangleMesh flat;
  flat.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.faces = {{0, 1, 2}};
  EXPECT_THROW(samplePointsUniformly(flat, 10), std::invalid_argument);
  TriangleMesh broken = unitCube();
  broken.faces.emplace_back(0, 1, 9);
  EXPECT_THROW(samplePointsUniformly(broken, 10), std::invalid_argument);
}

}  // namespace
}  // namespace icrkit
