#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/grasp_transfer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <icrkit/core/mesh_primitives.hpp>

#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::icr {
namespace {

// A geodesic sphere of radius r with exact outward normals.
TriangleMesh unitSphereMesh(int levels, double r) { return makeIcosphere(levels, r); }

// A point set only (the mapping needs no faces).
TriangleMesh pointsMesh(std::vector<Eigen::Vector3d> points) {
  TriangleMesh mesh;
  mesh.vertices.positions = std::move(points);
  return mesh;
}

double medianSpacing(const TriangleMesh& mesh) { return nearestNeighbourSpacing(mesh.vertices.positions).median; }

TEST(NormalLineMapping, DefaultRadiusIsTenMedianSpacings) {
  const TriangleMesh sphere = unitSphereMesh(3, 0.05);
  const NormalLineMapping mapping(sphere);
  EXPECT_DOUBLE_EQ(mapping.searchRadius(), 10.0 * medianSpacing(sphere));
  NormalLineMappingParameters params;
  params.search_radius = 0.003;
  EXPECT_DOUBLE_EQ(NormalLineMapping(sphere, params).searchRadius(), 0.003);
}

TEST(NormalLineMapping, RejectsBadRadiusTargetAndNormal) {
  const TriangleMesh sphere = unitSphereMesh(1, 0.05);
  NormalLineMappingParameters params;
  params.search_radius = -1.0;
  EXPECT_THROW(NormalLineMapping(sphere, params), InputError);
  params.search_radius = std::nan("");
  EXPECT_THROW(NormalLineMapping(sphere, params), InputError);
  EXPECT_THROW(NormalLineMapping(pointsMesh({})), InputError);
  // One vertex has no spacing to scale a default radius by...
  EXPECT_THROW(NormalLineMapping(pointsMesh({Eigen::Vector3d::Zero()})), InputError);
  // ...but an explicit radius works.
  params.search_radius = 1.0;
  const TriangleMesh single = pointsMesh({Eigen::Vector3d::Zero()});
  EXPECT_EQ(NormalLineMapping(single, params).map(Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d::UnitZ()), 0);

  const NormalLineMapping mapping(sphere);
  EXPECT_THROW(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), InputError);
  EXPECT_THROW(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d(std::nan(""), 0, 1)), InputError);
}

TEST(NormalLineMapping, PicksTheVertexNearestTheLineNotThePoint) {
  // p at the origin, normal +x: vertex 0 is nearest p but 0.1 off the line;
  // vertex 1 is farther but only 0.01 off it.
  const TriangleMesh target = pointsMesh({{0, 0.1, 0}, {0.5, 0.01, 0}, {0, 0, 0.3}});
  NormalLineMappingParameters params;
  params.search_radius = 1.0;
  const NormalLineMapping mapping(target, params);
  EXPECT_EQ(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 1);
  // The normal's length and sign do not matter: it is a line.
  EXPECT_EQ(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d(-7, 0, 0)), 1);
  EXPECT_EQ(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1e-9)), 2);
}

TEST(NormalLineMapping, TheFarSideIsOutsideTheRadius) {
  // A slab 1 thick: the line through the top vertex along +z passes exactly
  // through the bottom vertex 2, but only the top ones are near enough.
  const TriangleMesh target = pointsMesh({{0.02, 0, 0}, {-0.05, 0.03, 0}, {0, 0, -1}});
  NormalLineMappingParameters params;
  params.search_radius = 0.2;
  const NormalLineMapping mapping(target, params);
  EXPECT_EQ(mapping.map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()), 0);
  params.search_radius = 2.0;
  EXPECT_EQ(NormalLineMapping(target, params).map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()), 2);
  // Nothing within the radius: -1.
  EXPECT_EQ(mapping.map(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d::UnitZ()), -1);
}

TEST(NormalLineMapping, TiesGoToTheNearerPointThenTheSmallerIndex) {
  // All three on the line along +z through the origin.
  const TriangleMesh line = pointsMesh({{0, 0, 0.3}, {0, 0, -0.2}, {0, 0, 0.2}});
  NormalLineMappingParameters params;
  params.search_radius = 1.0;
  EXPECT_EQ(NormalLineMapping(line, params).map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()), 1);
  // Equal distance to the line and to p: the smaller index.
  const TriangleMesh mirrored = pointsMesh({{0, 0.1, 0.3}, {0, 0.1, -0.2}, {0, -0.1, 0.2}, {0, 0.1, 0.2}});
  EXPECT_EQ(NormalLineMapping(mirrored, params).map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()), 1);
  const TriangleMesh pair = pointsMesh({{0, 0.1, 0.3}, {0, 0.1, 0.2}, {0, -0.1, 0.2}});
  EXPECT_EQ(NormalLineMapping(pair, params).map(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()), 1);
}

TEST(NormalLineMapping, ScaledNoisySphereMapsEachVertexToItself) {
  // Scaling about the centre moves every vertex along its own normal, so the
  // normal line of vertex v passes through the scaled v; noise well under
  // the spacing does not change which vertex is nearest the line.
  const TriangleMesh source = unitSphereMesh(4, 0.05);
  TriangleMesh target = source;
  const double noise = 0.02 * medianSpacing(source);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  for (auto& q : target.vertices.positions) q = 1.01 * q + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  const NormalLineMapping mapping(target);
  for (std::size_t v = 0; v < source.vertexCount(); ++v)
    ASSERT_EQ(mapping.map(source.vertices.positions[v], source.vertices.normals[v]), static_cast<int>(v)) << v;
}

TEST(TransferGrasp, MapsContactsAndChecksInput) {
  const TriangleMesh source = unitSphereMesh(3, 0.05);
  TriangleMesh target = source;
  for (auto& q : target.vertices.positions) q *= 0.995;
  target.vertices.normals.clear();  // the target's normals are never used
  const std::vector<int> contacts = {3, 100, 641, 17};
  EXPECT_EQ(transferGrasp(source, contacts, target), contacts);
  EXPECT_TRUE(transferGrasp(source, {}, target).empty());

  EXPECT_THROW(transferGrasp(source, {3, 642}, target), InputError);
  EXPECT_THROW(transferGrasp(source, {-1}, target), InputError);
  EXPECT_THROW(transferGrasp(target, {3}, source), InputError);  // no source normals

  // A target far away has nothing within the radius.
  TriangleMesh far = source;
  for (auto& q : far.vertices.positions) q += Eigen::Vector3d(1, 0, 0);
  try {
    transferGrasp(source, {3}, far);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.location().find("contact 0"), std::string::npos) << e.location();
  }
}

TEST(TransferGrasp, RealModelOntoANoisyCopyOfItself) {
  for (const std::string name : {"CokePlasticSmall_5k", "Fish_5k"}) {
    const std::string path = std::string(ICRKIT_SHARED_DATA_DIR) + "/icr-models/" + name + ".obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
    const TriangleMesh source = io::readTriangleMesh(path);
    ASSERT_TRUE(source.vertices.hasNormals()) << name;
    TriangleMesh target = source;
    const double noise = 0.01 * medianSpacing(source);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-noise, noise);
    for (auto& q : target.vertices.positions) q += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    const NormalLineMapping mapping(target);
    // On a real mesh another vertex can sit nearly on a vertex's normal line
    // (thin walls, coarse triangles), so only nearly every vertex must map
    // to itself; every image must be near the source vertex.
    std::size_t self = 0;
    for (std::size_t v = 0; v < source.vertexCount(); ++v) {
      const int image = mapping.map(source.vertices.positions[v], source.vertices.normals[v]);
      ASSERT_GE(image, 0) << name << " vertex " << v;
      self += image == static_cast<int>(v);
      EXPECT_LE((target.vertices.positions[static_cast<std::size_t>(image)] - source.vertices.positions[v]).norm(),
                mapping.searchRadius());
    }
    const double fraction = static_cast<double>(self) / static_cast<double>(source.vertexCount());
    std::printf("[ transfer ] %s: %.2f%% of %zu vertices map to themselves\n", name.c_str(), 100.0 * fraction,
                source.vertexCount());
    EXPECT_GT(fraction, 0.98) << name;
  }
}

}  // namespace
}  // namespace icrkit::icr
