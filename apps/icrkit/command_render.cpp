// `icrkit render MESH [--regions JSON] [--compare OTHER --compare-regions JSON] -o PNG`:
// headless ray-traced views of a mesh with its ICRs (one colour per finger,
// prototype contacts and central points as dots), or the Fig. 6 comparison
// of CAD regions with the regions of a reconstructed mesh.

#include "argument_parsing.hpp"
#include "commands.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/icr/regions_file.hpp>
#include <icrkit/report/grasp_render.hpp>
#include <icrkit/report/mesh_render.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct RenderOptions {
  std::string mesh;
  std::string regions;
  std::string compare;
  std::string compare_regions;
  std::string contacts;
  bool compute_normals = false;
  int finger = -1;  ///< -1: every finger
  std::string size = "800x600";
  int views = 4;
  bool top_view = false;
  std::vector<std::string> cameras;
  std::string up = "0,0,1";
  int columns = 0;  ///< 0: automatic
  int samples = 2;
  bool central_points = true;
  std::string output;
};

// The regions of one mesh, as the regions file holds them, finger by finger.
struct RegionSet {
  std::vector<int> fingers;
  std::vector<int> contacts;  ///< -1 when the entry has none
  std::vector<std::vector<int>> vertices;
};

std::string lowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
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

// Reads `path` (a regions file, icr/regions_file.hpp) and checks every index against `mesh`.
RegionSet readRegions(const std::string& path, const TriangleMesh& mesh, const std::string& mesh_path) {
  RegionSet set;
  for (icr::StoredRegion& region : icr::readRegionsFile(path, mesh, mesh_path)) {
    set.fingers.push_back(region.finger);
    set.contacts.push_back(region.contact);
    set.vertices.push_back(std::move(region.vertices));
  }
  return set;
}

// Keeps only finger `finger` (all when -1); an absent finger is an error.
RegionSet onlyFinger(const RegionSet& set, int finger, const std::string& path) {
  if (finger < 0) return set;
  RegionSet out;
  for (std::size_t r = 0; r < set.fingers.size(); ++r)
    if (set.fingers[r] == finger) {
      out.fingers.push_back(set.fingers[r]);
      out.contacts.push_back(set.contacts[r]);
      out.vertices.push_back(set.vertices[r]);
    }
  if (out.fingers.empty()) throw InputError(path, "", "has no region for --finger " + std::to_string(finger));
  return out;
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
    throw InputError("--camera", location,
                     "expected eye_x,eye_y,eye_z or eye_x,eye_y,eye_z,target_x,target_y,target_z in metres, got '" +
                         text + "'");
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

nlohmann::json cameraJson(const report::RenderCamera& camera) {
  auto vec = [](const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  return {{"name", camera.name},
          {"eye", vec(camera.eye)},
          {"target", vec(camera.target)},
          {"up", vec(camera.up)},
          {"vertical_fov_deg", camera.vertical_fov_rad * 180.0 / kPi}};
}

// Central point (geodesic, as Q_n uses) of each region; -1 for an empty one.
std::vector<report::RgbImage> renderViews(const TriangleMesh& mesh, const std::vector<report::RenderCamera>& cameras,
                                        const report::RenderStyle& style, const report::SurfaceColours& colours,
                                        const std::vector<report::Marker>& markers, const std::string& caption_prefix,
                                        CommandContext& context) {
  const report::MeshRenderer renderer(mesh);
  std::vector<report::RgbImage> images;
  const ProgressCallback progress = context.progress();
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    report::RgbImage image = renderer.render(cameras[i], style, colours, markers);
    report::drawCaption(image, caption_prefix + cameras[i].name);
    images.push_back(std::move(image));
    if (progress) progress("render", i + 1, cameras.size());
  }
  return images;
}

// One finger's Algorithm 2 figures, as the summary's compare.fingers lists them.
nlohmann::json comparisonJson(int finger, const eval::RegionIntersection& result, std::size_t scan_vertices) {
  const std::size_t outside =
      static_cast<std::size_t>(std::count(result.inside.begin(), result.inside.end(), std::uint8_t{0}));
  const double cad_area = result.cad_region_area_m2;
  const auto percent = [&](double area) {
    return cad_area > 0 ? nlohmann::json(100.0 * area / cad_area) : nlohmann::json(nullptr);
  };
  return {{"finger", finger},
          {"cad_region_area_m2", cad_area},
          {"intersection_area_m2", result.intersection_area_m2},
          {"intersection_percent", percent(result.intersection_area_m2)},
          {"false_positive_area_m2", result.false_positive_area_m2},
          {"false_positive_percent", percent(result.false_positive_area_m2)},
          {"reconstructed_region_vertices", scan_vertices},
          {"false_positive_vertices", outside},
          {"unmapped_vertices", result.unmapped}};
}

std::vector<int> contactsOf(const RegionSet& set) {
  std::vector<int> contacts;
  for (int c : set.contacts)
    if (c >= 0) contacts.push_back(c);
  return contacts;
}

void run(const RenderOptions& options, CommandContext& context) {
  if (lowercaseExtension(options.output) != ".png") throw InputError(options.output, "", "the output must be a .png file");
  const auto [width, height] = parseSize(options.size);
  const bool comparing = !options.compare.empty();
  if (comparing && (options.regions.empty() || options.compare_regions.empty()))
    throw InputError("--compare", "", "needs --regions (of MESH, the CAD mesh) and --compare-regions (of OTHER)");
  if (!comparing && !options.compare_regions.empty())
    throw InputError("--compare-regions", "", "only makes sense with --compare OTHER");
  if (options.finger >= 0 && options.regions.empty())
    throw InputError("--finger", "", "needs --regions");

  const TriangleMesh mesh = readMesh(options.mesh, comparing, options.compute_normals, context);
  RegionSet regions;
  if (!options.regions.empty())
    regions = onlyFinger(readRegions(options.regions, mesh, options.mesh), options.finger, options.regions);
  std::vector<int> contacts = contactsOf(regions);
  if (!options.contacts.empty()) contacts = parseContacts(options.contacts, mesh);

  report::RenderStyle style;
  style.width = width;
  style.height = height;
  style.samples_per_axis = options.samples;
  const std::vector<report::RenderCamera> cameras = chooseCameras(options, mesh, width, height);
  const int view_count = static_cast<int>(cameras.size());

  nlohmann::json summary{{"mesh", options.mesh},
                         {"output", options.output},
                         {"view_size", {width, height}},
                         {"views", view_count}};
  nlohmann::json cameras_json = nlohmann::json::array();
  for (const report::RenderCamera& camera : cameras) cameras_json.push_back(cameraJson(camera));
  summary["cameras"] = cameras_json;

  const double setup_ms = context.elapsedMs();
  report::RgbImage image;
  int columns = std::min(options.columns, view_count);  // <= 0: chosen below

  if (!comparing) {
    const std::vector<int> centres =
        options.central_points ? report::regionCentralPoints(mesh, regions.vertices) : std::vector<int>(regions.vertices.size(), -1);
    report::SurfaceColours colours;
    if (!regions.fingers.empty())
      colours.per_vertex = report::regionColours(mesh, regions.fingers, regions.vertices, style.base_colour);
    const std::vector<report::RgbImage> views =
        renderViews(mesh, cameras, style, colours, report::graspMarkers(mesh, contacts, centres, width), "", context);
    if (columns <= 0) columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(view_count))));
    std::vector<report::LegendEntry> legend;
    nlohmann::json regions_json = nlohmann::json::array();
    std::vector<int> sorted = regions.fingers;
    std::sort(sorted.begin(), sorted.end());
    for (int finger : sorted) legend.push_back({report::fingerColour(finger), "finger " + std::to_string(finger), false});
    for (std::size_t r = 0; r < regions.fingers.size(); ++r)
      regions_json.push_back({{"finger", regions.fingers[r]},
                              {"contact", regions.contacts[r]},
                              {"vertices", regions.vertices[r].size()},
                              {"central_point", centres[r]}});
    summary["regions"] = regions_json;
    if (!contacts.empty() || !regions.fingers.empty())
      for (const report::LegendEntry& entry : report::graspMarkerLegend(options.central_points && !regions.fingers.empty()))
        legend.push_back(entry);
    image = report::appendLegend(report::tileImages(views, columns), legend);
  } else {
    const TriangleMesh other = readMesh(options.compare, false, options.compute_normals, context);
    const RegionSet other_regions = onlyFinger(readRegions(options.compare_regions, other, options.compare),
                                               options.finger, options.compare_regions);
    // Pair the regions by finger; each side must have the other's fingers.
    std::vector<std::vector<int>> cad_sets, scan_sets;
    std::vector<eval::RegionIntersection> intersections;
    nlohmann::json fingers_json = nlohmann::json::array();
    const eval::IntersectionEstimator estimator(mesh);
    for (std::size_t r = 0; r < regions.fingers.size(); ++r) {
      const int finger = regions.fingers[r];
      const auto it = std::find(other_regions.fingers.begin(), other_regions.fingers.end(), finger);
      if (it == other_regions.fingers.end())
        throw InputError(options.compare_regions, "", "has no region for finger " + std::to_string(finger) +
                                                          ", which " + options.regions + " has");
      const std::size_t s = static_cast<std::size_t>(it - other_regions.fingers.begin());
      eval::RegionIntersection result = estimator.estimate(regions.vertices[r], other, other_regions.vertices[s]);
      fingers_json.push_back(comparisonJson(finger, result, other_regions.vertices[s].size()));
      cad_sets.push_back(regions.vertices[r]);
      scan_sets.push_back(other_regions.vertices[s]);
      intersections.push_back(std::move(result));
    }
    for (int finger : other_regions.fingers)
      if (std::find(regions.fingers.begin(), regions.fingers.end(), finger) == regions.fingers.end())
        throw InputError(options.regions, "", "has no region for finger " + std::to_string(finger) + ", which " +
                                                  options.compare_regions + " has");
    if (columns <= 0) columns = view_count;
    report::ComparisonLayout layout;
    layout.columns = columns;
    layout.central_points = options.central_points;
    // Both rows use the cameras fitted to MESH.
    image = report::renderRegionComparison(mesh, cad_sets, contacts, other, scan_sets, contactsOf(other_regions),
                                           intersections, cameras, style, layout, context.progress());
    summary["compare"] = {{"mesh", options.compare}, {"regions", options.compare_regions}, {"fingers", fingers_json}};
  }
  const double render_ms = context.elapsedMs() - setup_ms;

  summary["columns"] = columns;
  summary["image_size"] = {image.width, image.height};
  report::writePng(options.output, image);
  summary["time_ms"] = {{"setup", setup_ms}, {"render", render_ms}, {"total", context.elapsedMs()}};
  context.emit(summary);
}

}  // namespace

void addRenderCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "render",
      "Headless ray-traced views of MESH as one PNG: regions coloured per finger (Okabe-Ito), prototype contacts "
      "(dark dots) and central points (white dots); with --compare, MESH is the CAD mesh and OTHER the "
      "reconstruction: a row of CAD views (I_n green, rest of the CAD region blue) above a row of reconstructed "
      "views (region inside the CAD region green, false positive vermillion)");
  auto options = std::make_shared<RenderOptions>();
  command->add_option("MESH", options->mesh, "Mesh to render (the CAD mesh with --compare)")->required();
  command->add_option("--regions", options->regions, "Regions of MESH: the JSON summary of `icrkit icr`");
  command->add_option("--compare", options->compare,
                      "Reconstructed mesh OTHER, in MESH's frame, whose regions are compared with MESH's (Fig. 6)");
  command->add_option("--compare-regions", options->compare_regions, "Regions of OTHER (`icrkit icr` JSON)");
  command->add_option("--contacts", options->contacts,
                      "Prototype contacts to mark, vertex indices of MESH i,j,... (default: those in --regions)");
  command->add_flag("--compute-normals", options->compute_normals,
                    "Derive vertex normals from the faces (needed with --compare when MESH has none)");
  command->add_option("--finger", options->finger, "Only this finger's region")->check(CLI::NonNegativeNumber);
  command->add_option("--size", options->size, "Size of each view in pixels, WIDTHxHEIGHT")->capture_default_str();
  auto* views = command->add_option("--views", options->views, "Number of automatic views around the mesh")
                    ->check(CLI::Range(1, 64))
                    ->capture_default_str();
  command->add_flag("--top-view", options->top_view, "Make the last automatic view look straight down");
  auto* camera = command->add_option(
      "--camera", options->cameras,
      "A view from eye_x,eye_y,eye_z[,target_x,target_y,target_z] (metres; target default: the mesh's centre), "
      "fitted to the mesh; repeatable; replaces the automatic views");
  camera->excludes(views);
  command->add_option("--up", options->up, "The object's up axis x,y,z")->capture_default_str();
  command->add_option("--columns", options->columns, "Views per row (default: about square; with --compare all)")
      ->check(CLI::Range(1, 64));
  command->add_option("--samples", options->samples, "Rays per pixel along each axis (anti-aliasing)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  command->add_flag("!--no-central-points", options->central_points, "Do not mark the regions' central points");
  command->add_option("-o,--output", options->output, "Output .png")->required();
  command->callback([&runner, options] { runner = [options](CommandContext& context) { run(*options, context); }; });
}

}  // namespace icrkit::app
