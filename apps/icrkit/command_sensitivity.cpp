// `icrkit sensitivity (--cad FILE | --object NAME) -o DIR`: the paper's
// Section III-A as a study (eval/sensitivity_study.hpp). The meshes of each
// noise level are made here, from the libraries `icrkit reconstruct` uses:
// raw = ball pivoting with estimated normals, filtered = smoothing, the
// preselection rule, ball pivoting.

#include "commands.hpp"
#include "experiment_options.hpp"
#include "sensitivity_options.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/sensitivity_study.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/sensitivity_plot.hpp>
#include <icrkit/sim/cad_objects.hpp>

#include <cmath>
#include <filesystem>
#include <memory>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

nlohmann::json sensitivity(const SensitivityOptions& o, CommandContext& context) {
  const eval::SensitivityParameters params = sensitivityParameters(o);
  const eval::Shard shard = o.experiment.parsedShard();
  if (o.cad.empty() == o.object.empty()) throw InputError("--cad/--object", "", "give exactly one of --cad FILE and --object NAME");
  requireOutputFolder(o.output);

  TriangleMesh cad;
  std::string object = o.name;
  if (!o.object.empty()) {
    cad = sim::makeCadObject(sim::parseCadObject(o.object));
    if (object.empty()) object = o.object;
  } else {
    cad = readMeshWithNormals(o.cad, true, context);
    if (object.empty()) object = fs::path(o.cad).stem().string();
  }

  const std::vector<std::string> rules = params.rules;
  const bool kept_only = o.mesh_kept_points_only;
  const double window_angle = checkedWindowNormalAngle(o.window_normal_angle);
  const eval::SensitivityResult result = eval::runSensitivityStudy(
      cad, object, params,
      [&](const PointCloud& noisy, double, double) { return buildMeshes(noisy, rules, kept_only, window_angle); }, shard,
      context.progress());

  nlohmann::json levels = nlohmann::json::array();
  for (const eval::SensitivityLevelReport& l : result.levels) {
    nlohmann::json excluded;
    for (std::size_t r = 0; r < rules.size() && r < l.excluded_vertices.size(); ++r)
      excluded[rules[r]] = l.excluded_vertices[r];
    levels.push_back({{"noise_level", l.noise_level},
                      {"sigma_m", l.sigma_m},
                      {"built", l.built},
                      {"sample_points", l.sample_points},
                      {"raw_faces", l.raw_faces},
                      {"filtered_faces", l.filtered_faces},
                      {"excluded_vertices", excluded},
                      {"time_ms", {{"meshes", l.build_ms}, {"evaluate", l.evaluate_ms}}}});
  }
  // run.json must be the same for every shard (merge checks it): levels'
  // per-shard details stay in the command's summary.
  nlohmann::json datasets = nlohmann::json::array();
  std::vector<std::string> order;
  for (const double level : params.noise_levels)
    for (const std::string& rule : rules) {
      order.push_back(eval::sensitivityDatasetName(object, level, rule));
      datasets.push_back({{"name", order.back()}});
    }
  nlohmann::json run{{"command", "sensitivity"},
                     {"config", nlohmann::json::parse(eval::experimentConfigJson(params.experiment))},
                     {"shard", {{"index", shard.index}, {"count", shard.count}}},
                     {"sensitivity",
                      {{"object", object},
                       {"cad", o.cad.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.cad)},
                       {"spacing_m", result.spacing_m},
                       {"noise_levels", params.noise_levels},
                       {"rules", rules},
                       {"seed", params.seed},
                       {"mesh_kept_points_only", kept_only}}},
                     {"datasets", datasets}};
  // Only when asked for: runs without it keep their run.json.
  if (window_angle < M_PI) run["sensitivity"]["window_normal_angle_rad"] = window_angle;
  report::ExperimentOutputs outputs;
  outputs.dataset_order = order;
  outputs.finger_counts = params.experiment.finger_counts;
  outputs.run_json = run.dump();
  report::WrittenOutputs written = report::writeExperimentOutputs(o.output, result.records, outputs);
  const eval::SensitivityTable table =
      eval::computeSensitivityTable(result.records, object, result.spacing_m, params.noise_levels, rules);
  for (const std::string& f : report::writeSensitivityOutputs(o.output, table)) written.files.push_back(f);
  return {{"output", o.output},
          {"object", object},
          {"spacing_m", result.spacing_m},
          {"grasps", result.records.size()},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"levels", levels},
          {"sensitivity", nlohmann::json::parse(eval::sensitivityJson(table))["rows"]},
          {"files", written.files},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addSensitivityCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "sensitivity",
      "The paper's noise study (Section III-A): sample a CAD mesh (Poisson disk), add Gaussian noise along the "
      "normals at each level, build the raw mesh (estimated normals) and the filtered mesh (smoothing + each "
      "preselection rule), run the experiment of `icrkit evaluate` on each and write DIR/sensitivity.{md,json,svg,"
      "png} beside the usual Table I files and grasps.jsonl (docs/results.md)");
  auto o = std::make_shared<SensitivityOptions>();
  addSensitivityOptions(*command, *o);
  command->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      ExperimentOptions::mapFieldsTo(context);
      context.mapFields({{"SensitivityParameters::noise_levels", "--noise"},
                         {"SensitivityParameters::rules", "--preselection"},
                         {"SensitivityParameters::spacing_m", "--spacing"},
                         {"object name", "--object"}});
      context.emit(sensitivity(*o, context));
    };
  });
}

}  // namespace icrkit::app
