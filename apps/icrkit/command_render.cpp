// `icrkit render MESH [--regions JSON] [--compare OTHER --compare-regions JSON] -o PNG`:
// headless ray-traced views of a mesh with its ICRs (report::renderRegionViews:
// one colour per finger, prototype contacts and central points as dots), or
// the Fig. 6 comparison of CAD regions with the regions of a reconstructed
// mesh (eval::intersectByFinger, report::renderRegionComparison).

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <icrkit/eval/finger_intersections.hpp>
#include <icrkit/report/grasp_render.hpp>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

nlohmann::json cameraJson(const report::RenderCamera& camera) {
  auto vec = [](const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  return {{"name", camera.name},
          {"eye", vec(camera.eye)},
          {"target", vec(camera.target)},
          {"up", vec(camera.up)},
          {"vertical_fov_deg", camera.vertical_fov_rad * 180.0 / kPi}};
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
  if (!options.regions.empty()) regions = readRegions(options.regions, mesh, options.mesh, options.finger);
  const std::vector<int> contacts =
      options.contacts.empty() ? regions.setContacts() : parseContacts(options.contacts, mesh);

  report::RenderStyle style;
  style.width = width;
  style.height = height;
  style.samples_per_axis = options.samples;
  const std::vector<report::RenderCamera> cameras = chooseCameras(options, mesh, width, height);
  const int view_count = static_cast<int>(cameras.size());
  nlohmann::json summary{{"mesh", options.mesh},
                         {"output", options.output},
                         {"view_size", {width, height}},
                         {"views", view_count},
                         {"cameras", nlohmann::json::array()}};
  for (const report::RenderCamera& camera : cameras) summary["cameras"].push_back(cameraJson(camera));

  const double setup_ms = context.elapsedMs();
  report::RgbImage image;
  int columns = std::min(options.columns, view_count);  // <= 0: automatic
  if (!comparing) {
    const report::RegionPicture picture =
        report::renderRegionViews(mesh, regions.fingers, regions.vertices, contacts, cameras, style, columns,
                                  options.central_points, context.progress());
    image = picture.image;
    columns = picture.columns;
    summary["regions"] = nlohmann::json::array();
    for (std::size_t r = 0; r < regions.fingers.size(); ++r)
      summary["regions"].push_back({{"finger", regions.fingers[r]},
                                    {"contact", regions.contacts[r]},
                                    {"vertices", regions.vertices[r].size()},
                                    {"central_point", picture.central_points[r]}});
  } else {
    const TriangleMesh other = readMesh(options.compare, false, options.compute_normals, context);
    const RegionSet other_regions = readRegions(options.compare_regions, other, options.compare, options.finger);
    context.mapFields({{"CAD regions", options.regions}, {"reconstructed regions", options.compare_regions}});
    const std::vector<eval::FingerIntersection> pairs =
        eval::intersectByFinger(eval::IntersectionEstimator(mesh), regions.fingers, regions.vertices, other,
                                other_regions.fingers, other_regions.vertices);
    std::vector<std::vector<int>> cad_sets, scan_sets;
    std::vector<eval::RegionIntersection> intersections;
    nlohmann::json fingers_json = nlohmann::json::array();
    for (const eval::FingerIntersection& pair : pairs) {
      fingers_json.push_back(
          comparisonJson(pair.finger, pair.intersection, other_regions.vertices[pair.scan_region].size()));
      cad_sets.push_back(regions.vertices[pair.cad_region]);
      scan_sets.push_back(other_regions.vertices[pair.scan_region]);
      intersections.push_back(pair.intersection);
    }
    report::ComparisonLayout layout;
    layout.columns = columns = columns <= 0 ? view_count : columns;
    layout.central_points = options.central_points;
    // Both rows use the cameras fitted to MESH.
    image = report::renderRegionComparison(mesh, cad_sets, contacts, other, scan_sets, other_regions.setContacts(),
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
  addRenderOptions(*command, *options);
  command->callback([&runner, options] { runner = [options](CommandContext& context) { run(*options, context); }; });
}

}  // namespace icrkit::app
