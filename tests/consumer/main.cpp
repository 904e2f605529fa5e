// Uses the installed headers and library: builds a mesh, measures it, writes
// and reads it back.
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <cmath>
#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  icrkit::TriangleMesh mesh;
  mesh.vertices.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.faces = {icrkit::Triangle(0, 1, 2)};
  const std::string path = std::string(argv[1]) + "/triangle.ply";
  icrkit::io::writeTriangleMesh(path, mesh);
  const icrkit::TriangleMesh back = icrkit::io::readTriangleMesh(path);
  const double area = icrkit::surfaceArea(back);
  std::printf("area %g\n", area);
  return std::abs(area - 0.5) < 1e-12 && back.faceCount() == 1 ? 0 : 1;
}
