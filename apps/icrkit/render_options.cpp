#include "render_options.hpp"

#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/icr/regions_file.hpp>

#include <cmath>

namespace icrkit::app {
namespace {

// --camera eye_x,eye_y,eye_z[,target_x,target_y,target_z], fitted to the mesh.
report::RenderCamera parseCamera(const std::string& text, std::size_t index, const report::BoundingSphere& sphere,
                                 const Eigen::Vector3d& up, double aspect) {
  const std::vector<std::string> parts = split(text, ',');
  std::vector<double> values;
  for (const std::string& part : parts) {
    double value = 0.0;
    if (!parseNumber(part, value)) {
      values.clear();
      break;
    }
    values.push_back(value);
  }
  const std::string location = "camera " + std::to_string(index + 1);
  if (values.size() != 3 && values.size() != 6)
    throw InputError(
        "--camera", location,
        "expected eye_x,eye_y,eye_z or eye_x,eye_y,eye_z,target_x,target_y,target_z in metres, got '" + text + "'");
  const Eigen::Vector3d eye(values[0], values[1], values[2]);
  const Eigen::Vector3d target = values.size() == 6 ? Eigen::Vector3d(values[3], values[4], values[5]) : sphere.centre;
  if ((target - eye).norm() == 0.0) throw InputError("--camera", location, "the eye is at the target");
  // Looking straight along --up: take another up so that the view is defined.
  Eigen::Vector3d camera_up = up;
  if ((target - eye).normalized().cross(up.normalized()).norm() < 1e-6)
    camera_up = std::abs(up.normalized().y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  report::RenderCamera camera = report::fittedCamera(sphere, eye, target, camera_up, aspect);
  camera.name = location;
  return camera;
}

}  // namespace

std::vector<report::RenderCamera> chooseCameras(const RenderOptions& options, const TriangleMesh& mesh, int width,
                                                int height) {
  const Eigen::Vector3d up = parsePoint("--up", options.up);
  if (up.norm() == 0.0) throw InputError("--up", "", "must be a non-zero vector");
  const double aspect = static_cast<double>(width) / height;
  if (!options.cameras.empty()) {
    const report::BoundingSphere sphere = report::boundingSphere(mesh);
    std::vector<report::RenderCamera> cameras;
    for (std::size_t i = 0; i < options.cameras.size(); ++i)
      cameras.push_back(parseCamera(options.cameras[i], i, sphere, up, aspect));
    return cameras;
  }
  report::OrbitParameters orbit;
  orbit.count = options.views;
  orbit.top_view = options.top_view;
  orbit.aspect = aspect;
  orbit.up = up;
  return report::orbitCameras(mesh, orbit);
}

std::pair<int, int> parseSize(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  double w = 0.0, h = 0.0;
  const bool ok = x != std::string::npos && parseNumber(text.substr(0, x), w) && parseNumber(text.substr(x + 1), h) &&
                  w == std::floor(w) && h == std::floor(h) && w >= 1 && h >= 1 && w <= 16384 && h <= 16384;
  if (!ok)
    throw InputError("--size", "", "expected WIDTHxHEIGHT in pixels (1..16384 each), e.g. 800x600, got '" + text + "'");
  return {static_cast<int>(w), static_cast<int>(h)};
}

std::vector<int> parseContacts(const std::string& text, const TriangleMesh& mesh) {
  const std::size_t vertex_count = mesh.vertexCount();
  const std::vector<std::uint8_t> referenced = referencedVertices(mesh);
  std::vector<int> contacts;
  const std::vector<std::string> parts = split(text, ',');
  for (std::size_t i = 0; i < parts.size(); ++i) {
    double value = 0.0;
    if (!parseNumber(parts[i], value) || value != std::floor(value) || value < 0 ||
        value >= static_cast<double>(vertex_count))
      throw InputError("--contacts", "item " + std::to_string(i + 1),
                       "expected a vertex index in 0.." + std::to_string(static_cast<long long>(vertex_count) - 1) +
                           ", got '" + parts[i] + "'");
    if (!referenced[static_cast<std::size_t>(value)])
      throw InputError("--contacts", "item " + std::to_string(i + 1),
                       "vertex " + parts[i] + " is used by no face, so it cannot be a contact");
    contacts.push_back(static_cast<int>(value));
  }
  return contacts;
}

std::vector<int> RegionSet::setContacts() const {
  std::vector<int> set;
  for (int c : contacts)
    if (c >= 0) set.push_back(c);
  return set;
}

RegionSet readRegions(const std::string& path, const TriangleMesh& mesh, const std::string& mesh_path, int finger) {
  RegionSet set;
  for (icr::StoredRegion& region : icr::readRegionsFile(path, mesh, mesh_path))
    if (finger < 0 || region.finger == finger) {
      set.fingers.push_back(region.finger);
      set.contacts.push_back(region.contact);
      set.vertices.push_back(std::move(region.vertices));
    }
  if (finger >= 0 && set.fingers.empty())
    throw InputError(path, "", "has no region for --finger " + std::to_string(finger));
  return set;
}

TriangleMesh readMesh(const std::string& path, bool need_normals, bool compute_normals, CommandContext& context) {
  TriangleMesh mesh = io::readTriangleMesh(path);
  if (mesh.faces.empty()) throw InputError(path, "", "has no faces to render");
  if (compute_normals) {
    const OrientationReport report = computeVertexNormals(mesh);
    if (report.flipped_faces > 0 || report.conflicting_edges > 0)
      context.note("icrkit: " + path + ": " + std::to_string(report.flipped_faces) + " faces flipped, " +
                   std::to_string(report.conflicting_edges) + " edges without a consistent winding");
  } else if (need_normals && !mesh.vertices.hasNormals()) {
    throw InputError(path, "",
                     "has no vertex normals, which the intersection estimation (normal lines of the CAD mesh) needs; "
                     "pass --compute-normals to derive them from the faces");
  }
  return mesh;
}

void addRenderOptions(CLI::App& command, RenderOptions& options) {
  command.add_option("MESH", options.mesh, "Mesh to render (the CAD mesh with --compare)")->required();
  command.add_option("--regions", options.regions, "Regions of MESH: the JSON summary of `icrkit icr`");
  command.add_option("--compare", options.compare,
                     "Reconstructed mesh OTHER, in MESH's frame, whose regions are compared with MESH's (Fig. 6)");
  command.add_option("--compare-regions", options.compare_regions, "Regions of OTHER (`icrkit icr` JSON)");
  command.add_option("--contacts", options.contacts,
                     "Prototype contacts to mark, vertex indices of MESH i,j,... (default: those in --regions)");
  command.add_flag("--compute-normals", options.compute_normals,
                   "Derive vertex normals from the faces (needed with --compare when MESH has none)");
  command.add_option("--finger", options.finger, "Only this finger's region")->check(CLI::NonNegativeNumber);
  command.add_option("--size", options.size, "Size of each view in pixels, WIDTHxHEIGHT")->capture_default_str();
  auto* views = command.add_option("--views", options.views, "Number of automatic views around the mesh")
                    ->check(CLI::Range(1, 64))
                    ->capture_default_str();
  command.add_flag("--top-view", options.top_view, "Make the last automatic view look straight down");
  auto* camera = command.add_option(
      "--camera", options.cameras,
      "A view from eye_x,eye_y,eye_z[,target_x,target_y,target_z] (metres; target default: the mesh's centre), "
      "fitted to the mesh; repeatable; replaces the automatic views");
  camera->excludes(views);
  command.add_option("--up", options.up, "The object's up axis x,y,z")->capture_default_str();
  command.add_option("--columns", options.columns, "Views per row (default: about square; with --compare all)")
      ->check(CLI::Range(1, 64));
  command.add_option("--samples", options.samples, "Rays per pixel along each axis (anti-aliasing)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  command.add_flag("!--no-central-points", options.central_points, "Do not mark the regions' central points");
  command.add_option("-o,--output", options.output, "Output .png")->required();
}

}  // namespace icrkit::app
