// Point-to-plane ICP to the CAD surface: a known displacement is undone.

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/rigid_alignment.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace icrkit::eval {
namespace {

TriangleMesh ellipsoid() {
  TriangleMesh mesh = makeIcosphere(5, 0.04);
  for (auto& p : mesh.vertices.positions) p = p.cwiseProduct(Eigen::Vector3d(1.5, 1.0, 0.7));
  computeVertexNormals(mesh);
  return mesh;
}

Eigen::Isometry3d displacement() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();  // 2.9 deg
  t.translation() = Eigen::Vector3d(0.003, -0.002, 0.004);
  return t;
}

void expectRecovers(const TriangleMesh& cad, double noise, double tolerance_m, double tolerance_rad) {
  TriangleMesh moving = cad;
  std::mt19937 random(11);
  std::normal_distribution<double> gauss(0.0, noise);
  for (std::size_t v = 0; v < moving.vertexCount(); ++v)
    moving.vertices.positions[v] += gauss(random) * moving.vertices.normals[v];
  const Eigen::Isometry3d truth = displacement();
  transformMesh(moving, truth);
  const AlignmentResult result = alignToCad(moving, cad);
  EXPECT_TRUE(result.converged);
  const Eigen::Isometry3d error = result.transform * truth;  // identity when exact
  EXPECT_LT(error.translation().norm(), tolerance_m);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), tolerance_rad);
  EXPECT_LT(result.rms_after_m, result.rms_before_m);
}

TEST(RigidAlignment, UndoesAKnownDisplacementOfAnEllipsoid) { expectRecovers(ellipsoid(), 0.0, 1e-6, 1e-5); }

TEST(RigidAlignment, UndoesItUnderSurfaceNoise) { expectRecovers(ellipsoid(), 5e-4, 1e-4, 2e-3); }

TEST(RigidAlignment, TheRealBunnyMesh) {
  const auto path = std::filesystem::path(ICRKIT_SHARED_DATA_DIR) / "stanford-bunny" / "bun_zipper.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  TriangleMesh bunny = io::readTriangleMesh(path.string());
  computeVertexNormals(bunny);
  for (auto& n : bunny.vertices.normals)
    if (n.squaredNorm() == 0.0) n = Eigen::Vector3d::UnitZ();  // the few unreferenced vertices
  expectRecovers(bunny, 3e-4, 2e-4, 3e-3);
}

TEST(RigidAlignment, BadInputIsAnInputError) {
  const TriangleMesh cad = ellipsoid();
  AlignmentParameters bad;
  bad.min_distance = 0.1;
  EXPECT_THROW(alignToCad(cad, cad, bad), InputError);
  TriangleMesh far = cad;
  Eigen::Isometry3d away = Eigen::Isometry3d::Identity();
  away.translation() = Eigen::Vector3d(1, 0, 0);
  transformMesh(far, away);
  EXPECT_THROW(alignToCad(far, cad), InputError);
  EXPECT_THROW(alignToCad(TriangleMesh{}, cad), InputError);
}

}  // namespace
}  // namespace icrkit::eval
