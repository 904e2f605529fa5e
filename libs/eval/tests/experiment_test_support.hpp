#pragma once
// Shared by the experiment's tests: a test object without symmetry, its
// noisy "reconstruction", and records in the form they are compared in.

#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/experiment_records.hpp>

#include <random>
#include <string>
#include <vector>

namespace icrkit::eval::test {

/// An ellipsoid: no symmetry that would make every grasp alike.
inline TriangleMesh ellipsoid(int subdivisions) {
  TriangleMesh mesh = makeIcosphere(subdivisions, 0.04);
  for (auto& p : mesh.vertices.positions) p = p.cwiseProduct(Eigen::Vector3d(1.4, 1.0, 0.8));
  computeVertexNormals(mesh);
  return mesh;
}

/// Vertices pushed along their normals by seeded noise, normals recomputed:
/// what a reconstruction does to a surface, in its simplest form.
inline TriangleMesh noisyCopy(const TriangleMesh& mesh, double sigma, unsigned seed) {
  TriangleMesh copy = mesh;
  std::mt19937 random(seed);
  std::normal_distribution<double> gauss(0.0, sigma);
  for (std::size_t v = 0; v < copy.vertexCount(); ++v)
    copy.vertices.positions[v] += gauss(random) * copy.vertices.normals[v];
  computeVertexNormals(copy);
  return copy;
}

/// The records as grasps.jsonl lines: equal lines mean bit-identical records.
inline std::vector<std::string> recordLines(const std::vector<GraspRecord>& records) {
  std::vector<std::string> out;
  for (const GraspRecord& r : records) out.push_back(toJsonLine(r));
  return out;
}

}  // namespace icrkit::eval::test
