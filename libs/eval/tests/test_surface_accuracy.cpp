// Distance and normal error of a mesh against a reference surface, near the
// reference's sharp edges and elsewhere (surface_accuracy.hpp).

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/surface_accuracy.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace icrkit::eval {
namespace {

// An axis-aligned box [0, s]^3 of 12 triangles wound outwards.
TriangleMesh box(double s) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.positions.emplace_back(s * (i & 1), s * ((i >> 1) & 1), s * ((i >> 2) & 1));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

// A grid of vertices on the box's top face (z = s), lifted by `lift`, with
// normals tilted by `tilt` about x; spacing 1 mm.
TriangleMesh liftedTop(double s, double lift, double tilt) {
  TriangleMesh m;
  const int n = static_cast<int>(std::round(s / 0.001));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.vertices.positions.emplace_back(0.001 * i, 0.001 * j, s + lift);
      m.vertices.normals.emplace_back(0.0, -std::sin(tilt), std::cos(tilt));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      m.faces.emplace_back(a, a + 1, a + n + 2);
      m.faces.emplace_back(a, a + n + 2, a + n + 1);
    }
  return m;
}

TEST(SurfaceAccuracy, DistanceAndNormalErrorOfALiftedTiltedFace) {
  const double s = 0.04, lift = 0.001, tilt = 10.0 * M_PI / 180.0;
  const SurfaceAccuracy a = measureSurfaceAccuracy(liftedTop(s, lift, tilt), box(s));
  EXPECT_EQ(a.sharp_edges, 12u);  // the face diagonals are flat
  EXPECT_EQ(a.all.vertices, 41u * 41u);
  EXPECT_NEAR(a.all.mean_distance_m, lift, 1e-12);
  EXPECT_NEAR(a.all.median_normal_error_rad, tilt, 1e-9);
  // Near edges: the top face's points within 4 mm of its four border edges.
  // On the 1 mm grid: 41^2 - 33^2 (x, y in 4..36 mm are 33 values each; a
  // point exactly 4 mm away counts as near, to within the edge sampling).
  const std::size_t far = 31u * 31u;  // x, y in 5..35 mm
  EXPECT_GE(a.elsewhere.vertices, far);
  EXPECT_LE(a.elsewhere.vertices, 33u * 33u);
  EXPECT_EQ(a.near_edges.vertices + a.elsewhere.vertices, a.all.vertices);
  EXPECT_NEAR(a.near_edges.median_normal_error_rad, tilt, 1e-9);
}

TEST(SurfaceAccuracy, AThinWallsVertexIsComparedWithTheSideItsNormalFaces) {
  // A box 2 mm thick (a wall); the top face's grid sunk 1.7 mm, nearer the
  // bottom face, its normals up: compared with the top face (0 deg), not
  // with the bottom one (180 deg); the distance is to the nearest point.
  TriangleMesh wall = box(0.04);
  for (auto& p : wall.vertices.positions) p.z() *= 0.05;  // 2 mm thick
  const TriangleMesh sunk = liftedTop(0.04, -0.0017 - 0.038, 0.0);
  const SurfaceAccuracy a = measureSurfaceAccuracy(sunk, wall);
  EXPECT_NEAR(a.elsewhere.median_normal_error_rad, 0.0, 1e-9);
  EXPECT_NEAR(a.elsewhere.median_distance_m, 0.0003, 1e-9);
}

TEST(SurfaceAccuracy, ASphereHasNoSharpEdgesAndItsOwnNormalsAreExact) {
  const TriangleMesh sphere = makeIcosphere(4, 0.05);
  const SurfaceAccuracy a = measureSurfaceAccuracy(sphere, sphere);
  EXPECT_EQ(a.sharp_edges, 0u);
  EXPECT_EQ(a.near_edges.vertices, 0u);
  EXPECT_NEAR(a.all.mean_distance_m, 0.0, 1e-12);
  // Exact vertex normals against the faces around them: within the facets'
  // half width (edges span about 4.6 deg of the sphere at 4 subdivisions).
  EXPECT_LT(a.all.median_normal_error_rad, 3.0 * M_PI / 180.0);
  const nlohmann::json j = nlohmann::json::parse(surfaceAccuracyJson(a));
  EXPECT_EQ(j.at("all").at("vertices"), sphere.vertexCount());
  EXPECT_TRUE(j.at("all").contains("median_normal_error_deg"));
}

TEST(SurfaceAccuracy, RefusesAReferenceWithoutFacesAndBadParameters) {
  TriangleMesh empty;
  EXPECT_THROW(measureSurfaceAccuracy(box(0.01), empty), InputError);
  SurfaceAccuracyParameters bad;
  bad.crease_angle_rad = 0.0;
  EXPECT_THROW(measureSurfaceAccuracy(box(0.01), box(0.01), bad), InputError);
}

}  // namespace
}  // namespace icrkit::eval
