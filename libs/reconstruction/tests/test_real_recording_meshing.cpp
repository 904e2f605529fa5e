// Meshing a real fused cloud: the PrimeSense bunny
// (../shared/data/primesense-bunny) reconstructed end to end, both meshes
// judged as issue 17 asks. Skipped without the data.

#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <icrkit/core/mesh_topology.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace icrkit::reconstruction {
namespace {

double largestComponentShare(const TriangleMesh& mesh) {
  const MeshComponents parts = meshComponents(mesh);
  std::vector<std::size_t> sizes(parts.count, 0);
  for (int c : parts.face_component) ++sizes[static_cast<std::size_t>(c)];
  return sizes.empty() ? 0.0 : double(*std::max_element(sizes.begin(), sizes.end())) / double(mesh.faces.size());
}

TEST(RealRecordingMeshing, PrimeSenseBunnyFilteredMeshIsOnePiece) {
  const std::string dir = std::string(ICRKIT_SHARED_DATA_DIR) + "/primesense-bunny";
  if (!std::filesystem::exists(dir + "/scans.rawlog")) GTEST_SKIP() << "shared test data not found: " << dir;
  const ReconstructionResult r = reconstructRawlog(dir + "/scans.rawlog", {});
  // bun_zipper's frame has +y up, read from the poses. Its views hold no
  // table (no point lies below the bunny's lowest centimetre). A filter that
  // looked for the table along z took up to 60 % of a view (ears, flanks);
  // one along y without the facing test took the bunny's lowest 8 mm as a
  // "plane". Nothing of the bunny is a support now.
  EXPECT_TRUE(r.up_automatic);
  EXPECT_EQ(r.up, Eigen::Vector3d::UnitY());
  for (const ScanFilterRecord& f : r.filters) {
    EXPECT_FALSE(f.plane_found) << "scan " << f.index;
    EXPECT_EQ(f.removed_plane, 0u) << "scan " << f.index;
  }
  for (const auto* m : {&r.raw_meshing, &r.filtered_meshing})
    std::printf("%s: %zu faces, %zu boundary loops, %zu components, %zu holes filled, %zu flake faces removed, "
                "layer %.3f mm, %zu thinned\n",
                m == &r.raw_meshing ? "raw" : "filtered", m->triangles, m->boundary_loops, m->components,
                m->closed_holes, m->removed_faces, m->layer_thickness * 1e3, m->thinned_points);
  // Measured: 36 loops (763 before hole filling, 41 before folded holes
  // were filled), 99.9 % in one piece, while the support-plane filter cut
  // the ears and flanks away; the whole bunny (444k faces against 283k, two
  // thin ears, its open bottom rim) has 93, in one piece.
  const BallPivotingReport& f = r.filtered_meshing;
  EXPECT_LE(f.boundary_loops, 120u);
  // Folded rims are closed on the smoothed layer, never on the raw
  // baseline; their faces against the normals are few.
  EXPECT_GT(f.folded_holes, 0u);
  EXPECT_EQ(r.raw_meshing.folded_holes, 0u);
  std::size_t against = 0;
  const auto& p = r.filtered_mesh.vertices.positions;
  const auto& n = r.filtered_mesh.vertices.normals;
  for (const Triangle& t : r.filtered_mesh.faces)
    against += (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(n[t[0]] + n[t[1]] + n[t[2]]) <= 0.0;
  std::printf("filtered: %zu folded holes filled, %zu faces against their normals\n", f.folded_holes, against);
  EXPECT_LE(against, r.filtered_mesh.faces.size() / 200);
  EXPECT_EQ(f.non_manifold_edges, 0u);
  EXPECT_EQ(edgeStatistics(r.filtered_mesh).non_manifold_edges, 0u);
  EXPECT_EQ(edgeStatistics(r.filtered_mesh).misoriented_edges, 0u);
  EXPECT_GE(largestComponentShare(r.filtered_mesh), 0.98);
  EXPECT_EQ(edgeStatistics(r.raw_mesh).non_manifold_edges, 0u);
  EXPECT_GE(largestComponentShare(r.raw_mesh), 0.95);
}

}  // namespace
}  // namespace icrkit::reconstruction
