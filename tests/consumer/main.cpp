// Uses the installed headers and libraries: builds a mesh, measures it, writes
// and reads it back (icrkit::core), and renders it to a PNG (icrkit::report,
// whose private link dependencies, Embree and OpenCV among them, the installed
// package must bring along).
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/report/mesh_render.hpp>

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

  icrkit::report::OrbitParameters orbit;
  orbit.count = 1;
  icrkit::report::RenderStyle style;
  style.width = 64;
  style.height = 48;
  const icrkit::report::RgbImage image =
      icrkit::report::renderMesh(back, icrkit::report::orbitCameras(back, orbit)[0], style);
  const std::string png = icrkit::report::encodePng(image);
  std::printf("png %zu bytes\n", png.size());
  const bool is_png = png.size() > 8 && png.compare(1, 3, "PNG") == 0;
  return std::abs(area - 0.5) < 1e-12 && back.faceCount() == 1 && is_png ? 0 : 1;
}
