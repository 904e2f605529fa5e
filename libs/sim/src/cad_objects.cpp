#include <icrkit/sim/cad_objects.hpp>

#include "cad_object_shapes.hpp"
#include "implicit_surface_mesher.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_normals.hpp>

#include <stdexcept>

namespace icrkit::sim {

const std::vector<std::string>& cadObjectNames() {
  static const std::vector<std::string> names = {"cup",        "paper_cup",    "bottle",
                                                 "coffee_pot", "wooden_toy_1", "wooden_toy_2"};
  return names;
}

std::string cadObjectName(CadObject object) {
  const auto index = static_cast<std::size_t>(object);
  if (index >= cadObjectNames().size()) throw std::invalid_argument("cadObjectName: unknown object");
  return cadObjectNames()[index];
}

CadObject parseCadObject(const std::string& name) {
  const auto& names = cadObjectNames();
  std::string expected;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<CadObject>(i);
    expected += (i ? ", " : "") + names[i];
  }
  throw InputError("object name", "", "unknown object '" + name + "', expected one of " + expected);
}

TriangleMesh makeCadObject(CadObject object) {
  const CadShape shape = cadShape(object);
  TriangleMesh mesh = meshImplicitSurface(shape.field, cadShapeGrid(shape));
  // Into the object frame: lowest point on z = 0, bounding box centred on
  // the z axis. Measured on the mesh, not the design, so that it holds
  // exactly for what the caller gets.
  const Eigen::AlignedBox3d box = mesh.vertices.bounds();
  const Eigen::Vector3d shift(-0.5 * (box.min().x() + box.max().x()), -0.5 * (box.min().y() + box.max().y()),
                              -box.min().z());
  for (Eigen::Vector3d& p : mesh.vertices.positions) p += shift;
  // The winding is outward by construction; orienting again would only cost time.
  computeVertexNormals(mesh, VertexNormalParameters{false});
  return mesh;
}

}  // namespace icrkit::sim
