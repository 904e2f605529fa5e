// `icrkit info FILE`: what a geometry file holds and how it is shaped.

#include "commands.hpp"

#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>

#include <memory>
#include <string>

namespace icrkit::app {
namespace {

nlohmann::json vectorJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json describe(const std::string& path, CommandContext& context) {
  const auto format = io::formatFromPath(path);
  const double start = context.elapsedMs();
  const TriangleMesh mesh = io::readTriangleMesh(path);
  const double read_ms = context.elapsedMs() - start;
  const PointCloud& v = mesh.vertices;

  nlohmann::json out;
  out["file"] = path;
  out["format"] = io::formatName(format);
  out["vertices"] = v.size();
  out["faces"] = mesh.faces.size();
  out["has_normals"] = v.hasNormals();
  out["has_colors"] = v.hasColours();
  nlohmann::json attributes = nlohmann::json::array();
  for (const Attribute& a : v.attributes) attributes.push_back({{"name", a.name}, {"type", plyTypeName(a.type)}});
  out["attributes"] = attributes;
  if (!v.empty()) {
    const Eigen::AlignedBox3d box = v.bounds();
    out["bounding_box_m"] = {{"min", vectorJson(box.min())}, {"max", vectorJson(box.max())}};
    out["extent_m"] = vectorJson(box.sizes());
  }
  const SpacingStatistics spacing = nearestNeighbourSpacing(v.positions);
  out["mean_spacing_m"] = spacing.mean;
  out["median_spacing_m"] = spacing.median;
  if (!mesh.faces.empty()) {
    const EdgeStatistics edges = edgeStatistics(mesh);
    const MeshComponents components = meshComponents(mesh);
    out["area_m2"] = surfaceArea(mesh);
    out["edges"] = edges.edges;
    out["boundary_edges"] = edges.boundary_edges;
    out["non_manifold_edges"] = edges.non_manifold_edges;
    out["connected_components"] = components.count;
    out["unreferenced_vertices"] = components.unreferenced_vertices;
  }
  out["time_ms"] = {{"read", read_ms}, {"total", context.elapsedMs() - start}};
  return out;
}

}  // namespace

void addInfoCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand("info", "Counts, bounding box, spacing and mesh topology of a PLY/OBJ/PCD/XYZ file");
  auto path = std::make_shared<std::string>();
  command->add_option("file", *path, "Mesh or point cloud (.ply, .obj, .pcd, .xyz)")->required();
  command->callback([&runner, path] { runner = [path](CommandContext& context) { context.emit(describe(*path, context)); }; });
}

}  // namespace icrkit::app
