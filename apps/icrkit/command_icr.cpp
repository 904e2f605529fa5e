// `icrkit icr MESH --contacts i,j,k,l -o OUT.ply`: the Independent Contact
// Regions of one prototype grasp, as a coloured PLY with a `region` vertex
// attribute and a JSON summary next to it.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "conservative_options.hpp"
#include "contact_model_options.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/icr/patch_contacts.hpp>
#include <icrkit/icr/regions_file.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct IcrOptions {
  GraspMeshOptions mesh;
  ContactModelOptions contact_model;
  std::string contacts;
  std::string contact_points;
  double alpha = 0.5;
  double tws_radius = 0.0;
  icr::GrowthMode mode = icr::GrowthMode::BreadthFirst;
  ConservativeOptions conservative;
  std::optional<double> patch_radius;
  bool patch_all_points = false;
  std::string output;
};

// Tableau 10 without its grey, which marks vertices in no region: distinct
// hues that stay apart for the usual 3-5 fingers; more fingers reuse them.
constexpr std::array<Colour, 9> kPalette{{{31, 119, 180},
                                         {255, 127, 14},
                                         {44, 160, 44},
                                         {214, 39, 40},
                                         {148, 103, 189},
                                         {140, 86, 75},
                                         {227, 119, 194},
                                         {188, 189, 34},
                                         {23, 190, 207}}};
constexpr Colour kNoRegion{190, 190, 190};
constexpr Colour kRecommended{0, 0, 0};

std::vector<int> parseContactIndices(const std::string& text) {
  std::vector<int> contacts;
  const std::vector<std::string> parts = split(text, ',');
  for (std::size_t i = 0; i < parts.size(); ++i) {
    double value = 0.0;
    if (!parseNumber(parts[i], value) || value != std::floor(value) || std::abs(value) > 2e9)
      throw InputError("--contacts", "item " + std::to_string(i + 1),
                       "expected a vertex index, got '" + parts[i] + "'");
    contacts.push_back(static_cast<int>(value));
  }
  return contacts;
}

std::vector<Eigen::Vector3d> parseContactPoints(const std::string& text) {
  std::vector<Eigen::Vector3d> points;
  const std::vector<std::string> items = split(text, ';');
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::vector<std::string> coordinates = split(items[i], ',');
    Eigen::Vector3d p;
    bool ok = coordinates.size() == 3;
    for (std::size_t k = 0; ok && k < 3; ++k) ok = parseNumber(coordinates[k], p[static_cast<Eigen::Index>(k)]);
    if (!ok)
      throw InputError("--contact-points", "point " + std::to_string(i + 1),
                       "expected x,y,z in metres, got '" + items[i] + "'");
    points.push_back(p);
  }
  return points;
}

std::string lowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// The input mesh with one colour per region and the `region` attribute.
TriangleMesh regionMesh(const TriangleMesh& mesh, const icr::IcrResult& result) {
  TriangleMesh out = mesh;
  std::vector<double> region(mesh.vertexCount(), -1.0);
  // Later fingers first, so that a vertex in several regions ends up with the
  // lowest finger index, as documented.
  for (auto it = result.regions.rbegin(); it != result.regions.rend(); ++it)
    for (int v : it->vertices) region[static_cast<std::size_t>(v)] = static_cast<double>(it->finger);
  out.vertices.colours.assign(mesh.vertexCount(), kNoRegion);
  for (std::size_t v = 0; v < region.size(); ++v)
    if (region[v] >= 0) out.vertices.colours[v] = kPalette[static_cast<std::size_t>(region[v]) % kPalette.size()];
  out.vertices.attributes.add("region", ScalarType::Int32, std::move(region));
  // The marker: where each finger should aim, black, with its finger index.
  std::vector<double> recommended(mesh.vertexCount(), -1.0);
  for (auto it = result.regions.rbegin(); it != result.regions.rend(); ++it)
    if (it->recommended.vertex >= 0) {
      recommended[static_cast<std::size_t>(it->recommended.vertex)] = static_cast<double>(it->finger);
      out.vertices.colours[static_cast<std::size_t>(it->recommended.vertex)] = kRecommended;
    }
  out.vertices.attributes.add("recommended", ScalarType::Int32, std::move(recommended));
  return out;
}

void printHumanSummary(const nlohmann::json& summary) {
  std::cout << "mesh: " << summary["mesh"].get<std::string>() << " (" << summary["vertices"].get<std::size_t>()
            << " vertices)\n"
            << "epsilon: " << summary["epsilon"].get<double>() << "\n"
            << "lambda_m: " << summary["lambda_m"].get<double>() << "\n"
            << "tws_radius: " << summary["tws_radius"].get<double>() << "\n"
            << "gws_facets: " << summary["gws_facets"].get<std::size_t>() << "\n";
  for (const auto& region : summary["regions"])
    std::cout << "finger " << region["finger"].get<std::size_t>() << ": contact " << region["contact"].get<int>()
              << ", " << region["vertices"].size() << " vertices, area " << region["area_m2"].get<double>()
              << " m2, aim at " << region["recommended"]["vertex"].get<int>() << " (depth "
              << region["recommended"]["depth_m"].get<double>() << " m)\n";
  const auto& time = summary["time_ms"];
  std::cout << "time_ms: " << time["total"].get<double>() << " (hull " << time["hull"].get<double>() << ", zones "
            << time["zones"].get<double>() << ", growth " << time["growth"].get<double>() << ")\n"
            << "output: " << summary["output"].get<std::string>() << ", " << summary["summary"].get<std::string>()
            << "\n";
  std::cout.flush();
}

void run(const IcrOptions& options, CommandContext& context) {
  if (lowercaseExtension(options.output) != ".ply")
    throw InputError(options.output, "", "the output must be a .ply file (it carries the `region` vertex property)");
  if (options.contacts.empty() == options.contact_points.empty())
    throw InputError("--contacts", "", "give the grasp either as --contacts i,j,... or as --contact-points x,y,z;...");

  const double read_start = context.elapsedMs();
  const GraspMesh input = loadGraspMesh(options.mesh, context);
  const double read_ms = context.elapsedMs() - read_start;
  const std::string& path = options.mesh.path;

  std::vector<int> contacts;
  nlohmann::json snap_distances;
  if (!options.contacts.empty()) {
    contacts = parseContactIndices(options.contacts);
  } else {
    // Only vertices of faces can be contacts, so only they attract a point.
    const std::vector<std::uint8_t> referenced = referencedVertices(input.mesh);
    std::vector<int> surface;
    std::vector<Eigen::Vector3d> positions;
    for (std::size_t v = 0; v < referenced.size(); ++v)
      if (referenced[v]) {
        surface.push_back(static_cast<int>(v));
        positions.push_back(input.mesh.vertices.positions[v]);
      }
    if (surface.empty()) throw InputError(path, "", "has no vertex of a face to snap --contact-points to");
    const KdTree tree(positions);
    snap_distances = nlohmann::json::array();
    for (const Eigen::Vector3d& p : parseContactPoints(options.contact_points)) {
      const Neighbour nearest = tree.nearest(p, 1).front();
      contacts.push_back(surface[nearest.index]);
      snap_distances.push_back(nearest.distance);
    }
  }

  icr::IcrParameters params;
  params.contact_model = options.contact_model.model();
  params.alpha = options.alpha;
  params.tws_radius = options.tws_radius;
  params.mode = options.mode;
  params.conservative = options.conservative.growth();
  std::optional<icr::PatchParameters> patch;
  if (options.patch_radius) {
    patch.emplace();
    patch->radius_m = *options.patch_radius;
    patch->filter_border = !options.patch_all_points;
    if (!(patch->radius_m > 0) || !std::isfinite(patch->radius_m))
      throw InputError("--patch-radius", "", "expected a radius > 0 in metres, got " + std::to_string(patch->radius_m));
    if (params.conservative)
      throw InputError("--patch-radius", "", "patch contacts cannot be combined with --conservative yet");
  } else if (options.patch_all_points) {
    throw InputError("--patch-all-points", "", "only with --patch-radius");
  }
  icr::IcrResult result;
  std::size_t unreferenced = 0;
  try {
    const icr::GraspableObject object =
        icr::GraspableObject::withDefaultFrame(input.mesh, input.excluded, options.mesh.torque_reference);
    unreferenced = object.unreferencedCount();
    if (patch) {
      const icr::ContactPatches patches(object, *patch);
      result = icr::computePatchContactRegions(object, patches, contacts, params);
    } else {
      result = icr::computeIndependentContactRegions(object, contacts, params);
    }
  } catch (const InputError& error) {
    throw namingMesh(path, error);
  }

  const std::string summary_path = summaryPathFor(options.output);
  // The regions file's format is icr's (regions_file.hpp); the rest is this command's summary.
  const nlohmann::json regions = nlohmann::json::parse(icr::regionsJson(result.regions));
  nlohmann::json summary{
      {"epsilon", result.epsilon},
      {"lambda_m", result.lambda_m},
      {"tws_radius", result.tws_radius},
      {"gws_facets", result.gws_facets},
      {"regions", regions},
      {"contacts", contacts},
      {"model", nlohmann::json::parse(icr::contactModelJson(params.contact_model))},
      {"alpha", options.tws_radius > 0 ? nlohmann::json(nullptr) : nlohmann::json(options.alpha)},
      {"mode", options.mode == icr::GrowthMode::BreadthFirst ? "bfs" : "full"},
      {"conservative", conservativeJson(params.conservative)},
      {"patch", patch ? nlohmann::json{{"rule", "sphere"}, {"radius_m", patch->radius_m}, {"filter_border", patch->filter_border}}
                      : nlohmann::json(nullptr)},
      {"torque_reference", icr::torqueReferenceName(options.mesh.torque_reference)},
      {"normals", input.normals_computed ? "computed" : "file"},
      {"exclusion", input.exclusion_source},
      {"excluded_vertices", countExcluded(input.excluded)},
      {"vertices", input.mesh.vertexCount()},
      {"unreferenced_vertices", unreferenced},
      {"vertices_tested", result.vertices_tested},
      {"mesh", path},
      {"output", options.output},
      {"summary", summary_path}};
  if (!snap_distances.is_null()) summary["contact_snap_distance_m"] = snap_distances;
  summary["time_ms"] = {{"read", read_ms},
                        {"hull", result.timings.hull_ms},
                        {"zones", result.timings.zones_ms},
                        {"growth", result.timings.growth_ms},
                        {"icr", result.timings.total_ms},
                        {"total", context.elapsedMs()}};

  io::writeTriangleMesh(options.output, regionMesh(input.mesh, result));
  writeSummaryFile(summary_path, summary);

  if (context.options().json)
    context.emit(summary);
  else
    printHumanSummary(summary);
}

}  // namespace

void addIcrCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "icr",
      "Independent Contact Regions of a force-closure grasp. Writes OUT (.ply: one colour per region, grey "
      "outside, int vertex property `region` = finger index or -1; a vertex in several regions gets the lowest "
      "finger index; each region's recommended contact, its deepest vertex, black with int property "
      "`recommended` = finger index, -1 elsewhere) and the JSON summary next to it (OUT with .json)");
  auto options = std::make_shared<IcrOptions>();
  options->mesh.addTo(*command);
  auto* contacts = command->add_option("--contacts", options->contacts, "Prototype grasp: vertex indices i,j,k,...");
  auto* points = command->add_option("--contact-points", options->contact_points,
                                     "Prototype grasp as points \"x,y,z;x,y,z;...\" (metres), each snapped to the "
                                     "nearest vertex of a face");
  contacts->excludes(points);
  options->contact_model.addTo(*command);
  auto* alpha = command
                    ->add_option("--alpha", options->alpha,
                                 "TWS: an origin-centred ball of radius alpha * epsilon of the prototype, alpha in (0, 1]")
                    ->check(CLI::Validator(
                        [](std::string& value) -> std::string {
                          double a = 0.0;
                          if (!CLI::detail::lexical_cast(value, a) || !(a > 0.0 && a <= 1.0))
                            return "alpha must be in (0, 1], got " + value;
                          return {};
                        },
                        "(0,1]"))
                    ->capture_default_str();
  auto* radius = command->add_option("--tws-radius", options->tws_radius,
                                     "TWS: an origin-centred ball of this absolute radius (instead of --alpha)")
                     ->check(CLI::PositiveNumber);
  alpha->excludes(radius);
  command
      ->add_option_function<std::string>(
          "--mode",
          [options](const std::string& name) {
            options->mode = name == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
          },
          "Region growth: bfs (over mesh neighbours from each contact) or full (test every vertex); default bfs")
      ->check(CLI::IsMember({"bfs", "full"}));
  options->conservative.addTo(*command);
  command->add_option("--patch-radius", options->patch_radius,
                      "Multi-point (patch) contacts of the reference ICR library: each contact is the connected piece "
                      "of the mesh within this distance (metres) of its vertex, every point at full strength "
                      "(docs/icr.md: epsilon and regions then grow with the mesh density)");
  command->add_flag("--patch-all-points", options->patch_all_points,
                    "Keep every point of a patch (default: its centre and border points, as the reference library)");
  command->add_option("-o,--output", options->output, "Output .ply (the summary goes to the same name with .json)")
      ->required();
  command->callback([&runner, options] { runner = [options](CommandContext& context) { run(*options, context); }; });
}

}  // namespace icrkit::app
