// `icrkit icr MESH --contacts i,j,k,l -o OUT.ply`: the Independent Contact
// Regions of one prototype grasp (icr::computeIndependentContactRegions, or
// computePatchContactRegions with --patch-radius), as a coloured PLY with a
// `region` vertex attribute (icr::regionMesh) and a JSON summary next to it.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "icr_options.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/contact_snapping.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/region_mesh.hpp>
#include <icrkit/icr/regions_file.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

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
  const icr::IcrParameters params = icrParameters(options);
  const std::optional<icr::PatchParameters> patch = patchParameters(options, params);

  const double read_start = context.elapsedMs();
  const GraspMesh input = loadGraspMesh(options.mesh, context);
  const double read_ms = context.elapsedMs() - read_start;
  const std::string& path = options.mesh.path;

  std::vector<int> contacts;
  nlohmann::json snap_distances;
  if (!options.contacts.empty()) {
    contacts = parseContactIndices(options.contacts);
  } else {
    const std::vector<Eigen::Vector3d> points = parseContactPoints(options.contact_points);
    const icr::SnappedContacts snapped =
        renamingInputErrors("mesh", path, [&] { return icr::snapToFaceVertices(input.mesh, points); });
    contacts = snapped.vertices;
    snap_distances = snapped.distances_m;
  }
  icr::IcrResult result;
  std::size_t unreferenced = 0;
  try {
    const icr::GraspableObject object =
        icr::GraspableObject::withDefaultFrame(input.mesh, input.excluded, options.mesh.torque_reference);
    unreferenced = object.unreferencedCount();
    result = patch ? icr::computePatchContactRegions(object, icr::ContactPatches(object, *patch), contacts, params)
                   : icr::computeIndependentContactRegions(object, contacts, params);
  } catch (const InputError& error) {
    throw namingMesh(path, error);
  }

  const std::string summary_path = summaryPathFor(options.output);
  // The regions file's format is icr's (regions_file.hpp); the rest is this command's summary.
  nlohmann::json summary{{"epsilon", result.epsilon},
                         {"lambda_m", result.lambda_m},
                         {"tws_radius", result.tws_radius},
                         {"gws_facets", result.gws_facets},
                         {"regions", nlohmann::json::parse(icr::regionsJson(result.regions))},
                         {"contacts", contacts},
                         {"model", nlohmann::json::parse(icr::contactModelJson(params.contact_model))},
                         {"alpha", options.tws_radius ? nlohmann::json(nullptr) : nlohmann::json(options.alpha)},
                         {"mode", options.mode == icr::GrowthMode::BreadthFirst ? "bfs" : "full"},
                         {"conservative", conservativeJson(params.conservative)},
                         {"patch", patch ? nlohmann::json{{"rule", "sphere"},
                                                          {"radius_m", patch->radius_m},
                                                          {"filter_border", patch->filter_border}}
                                         : nlohmann::json(nullptr)},
                         {"vertices_tested", result.vertices_tested},
                         {"mesh", path},
                         {"output", options.output},
                         {"summary", summary_path}};
  summary.update(graspMeshJson(input, options.mesh, unreferenced));
  if (!snap_distances.is_null()) summary["contact_snap_distance_m"] = snap_distances;
  summary["time_ms"] = {{"read", read_ms},
                        {"hull", result.timings.hull_ms},
                        {"zones", result.timings.zones_ms},
                        {"growth", result.timings.growth_ms},
                        {"icr", result.timings.total_ms},
                        {"total", context.elapsedMs()}};

  io::writeTriangleMesh(options.output, icr::regionMesh(input.mesh, result.regions));
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
  addIcrOptions(*command, *options);
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      context.mapFields({{"PatchParameters::radius_m", "--patch-radius"}});
      run(*options, context);
    };
  });
}

}  // namespace icrkit::app
