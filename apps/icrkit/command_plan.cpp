// `icrkit plan MESH -o plan.json`: grasps a robot can execute on a
// (reconstructed) mesh (planning::planGrasps), best first, as plan.json
// (planning/plan_file.hpp), the best grasp's regions as a coloured PLY
// (icr::regionMesh) and a render of the best grasps (report::renderRegionViews).

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "plan_options.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/icr/region_mesh.hpp>
#include <icrkit/planning/plan_file.hpp>
#include <icrkit/report/grasp_render.hpp>

#include <iostream>
#include <memory>
#include <string>

namespace icrkit::app {
namespace {

std::string withExtension(const std::string& path, const std::string& extension) {
  const std::string summary = summaryPathFor(path);  // PATH with .json
  return summary.substr(0, summary.size() - 5) + extension;
}

report::RgbImage renderBest(const TriangleMesh& mesh, const planning::PlanResult& plan, int count) {
  report::RenderStyle style;
  style.width = 400;
  style.height = 300;
  report::OrbitParameters orbit;
  orbit.count = 3;
  const std::vector<report::RenderCamera> cameras = report::orbitCameras(mesh, orbit);
  std::vector<report::RgbImage> rows;
  for (std::size_t g = 0; g < plan.grasps.size() && static_cast<int>(g) < count; ++g) {
    const planning::PlannedGrasp& grasp = plan.grasps[g];
    std::vector<int> fingers, aims;
    std::vector<std::vector<int>> regions;
    for (const icr::ContactRegion& r : grasp.regions.regions) {
      fingers.push_back(static_cast<int>(r.finger));
      regions.push_back(r.vertices);
      aims.push_back(r.recommended.vertex);
    }
    report::RgbImage row =
        report::renderRegionViews(mesh, fingers, regions, aims, cameras, style, 3, false).image;
    report::drawCaption(row, "rank " + std::to_string(grasp.rank) + ", score " + std::to_string(grasp.score.probability));
    rows.push_back(std::move(row));
  }
  return report::tileImages(rows, 1);
}

void run(const PlanOptions& options, CommandContext& context) {
  if (lowercaseExtension(options.output) != ".json")
    throw InputError(options.output, "", "the plan must be a .json file");
  const planning::PlanningParameters params = planningParameters(options);
  params.validate();

  const GraspMesh input = loadGraspMesh(options.mesh, context);
  const std::string& path = options.mesh.path;
  planning::PlanResult plan;
  std::string plan_text;
  try {
    const icr::GraspableObject object =
        icr::GraspableObject::withDefaultFrame(input.mesh, input.excluded, options.mesh.torque_reference);
    plan = planning::planGrasps(object, params, context.progress());
    const nlohmann::json extra{{"placement_error_m", params.placement.placement_error_m},
                               {"task_margin", params.task_margin},
                               {"seed", params.seed}};
    plan_text = planning::planJson(path, object, params.regions.contact_model, plan, extra.dump());
  } catch (const InputError& error) {
    throw namingMesh(path, error);
  }

  const double plan_ms = context.elapsedMs();
  const std::string ply_path = withExtension(options.output, ".ply");
  const std::string png_path = withExtension(options.output, ".png");
  io::writeTriangleMesh(ply_path, icr::regionMesh(input.mesh, plan.grasps.front().regions.regions));
  if (options.renders > 0) report::writePng(png_path, renderBest(input.mesh, plan, options.renders));
  writeFileAtomically(options.output, plan_text + "\n");

  const planning::PlanReport& r = plan.report;
  nlohmann::json counts = nlohmann::json::array();
  for (const planning::FingerCountReport& f : r.finger_counts)
    counts.push_back({{"fingers", f.fingers},
                      {"drawn", f.drawn},
                      {"rejected_by_precheck", f.rejected_by_precheck},
                      {"rejected_by_bound", f.rejected_by_bound},
                      {"hulls_built", f.hulls_built},
                      {"not_force_closure", f.not_force_closure},
                      {"below_task", f.below_task},
                      {"small_regions", f.small_regions},
                      {"with_regions", f.with_regions}});
  nlohmann::json grasps = nlohmann::json::array();
  for (const planning::PlannedGrasp& g : plan.grasps) {
    std::vector<double> areas;
    for (const icr::ContactRegion& region : g.regions.regions) areas.push_back(region.area_m2);
    grasps.push_back({{"rank", g.rank},
                      {"fingers", g.fingers},
                      {"score", g.score.probability},
                      {"min_depth_m", g.score.min_depth_m},
                      {"epsilon", g.epsilon},
                      {"area_m2", areas}});
  }
  nlohmann::json summary{{"mesh", path},
                         {"output", options.output},
                         {"regions_ply", ply_path},
                         {"render", options.renders > 0 ? nlohmann::json(png_path) : nlohmann::json(nullptr)},
                         {"tws_radius", plan.grasps.front().tws_radius},
                         {"trust",
                          {{"vertices", r.trust.vertices},
                           {"trusted", r.trust.trusted},
                           {"excluded", r.trust.excluded},
                           {"near_rim", r.trust.near_rim},
                           {"normal_spread", r.trust.normal_spread},
                           {"normal_sigma", r.trust.normal_sigma},
                           {"weak_support", r.trust.weak_support},
                           {"low_flatness", r.trust.low_flatness}}},
                         {"finger_counts", counts},
                         {"grasps", grasps}};
  summary.update(graspMeshJson(input, options.mesh, 0));
  summary.erase("unreferenced_vertices");
  summary["time_ms"] = {{"trust", r.trust_ms},  {"screening", r.screening_ms}, {"regions", r.regions_ms},
                        {"plan", r.total_ms},   {"outputs", context.elapsedMs() - plan_ms},
                        {"total", context.elapsedMs()}};
  if (context.options().json) {
    context.emit(summary);
    return;
  }
  std::cout << "plan: " << plan.grasps.size() << " grasps on " << path << " (" << r.trust.trusted << " of "
            << r.trust.vertices << " vertices trusted), " << r.total_ms << " ms\n";
  for (const auto& g : summary["grasps"])
    std::cout << "rank " << g["rank"] << ": " << g["fingers"] << " fingers, score " << g["score"] << ", epsilon "
              << g["epsilon"] << ", shallowest aim " << g["min_depth_m"] << " m\n";
  std::cout << "output: " << options.output << ", " << ply_path << (options.renders > 0 ? ", " + png_path : "") << "\n";
  std::cout.flush();
}

}  // namespace

void addPlanCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "plan",
      "Grasps a robot can execute on a mesh: candidate prototypes on the trusted surface, their Independent "
      "Contact Regions, ranked by the probability that every finger lands in its region under the placement "
      "error (docs/planning.md). Writes OUT (plan.json), OUT with .ply (the best grasp's regions) and .png");
  auto options = std::make_shared<PlanOptions>();
  addPlanOptions(*command, *options);
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      mapPlanFields(context);
      run(*options, context);
    };
  });
}

}  // namespace icrkit::app
