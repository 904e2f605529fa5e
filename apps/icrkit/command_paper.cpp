// `icrkit paper -o DIR`: the paper's whole study on simulated data — make the
// nine datasets, reconstruct each (raw and filtered meshes), run the
// experiment on each against its CAD mesh, and write Table I, the
// eligibility rates and both Fig. 8 histograms (docs/results.md).

#include "commands.hpp"
#include "experiment_options.hpp"
#include "paper_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/study.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/grasp_render.hpp>
#include <icrkit/sim/dataset.hpp>

#include <filesystem>
#include <map>
#include <memory>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

nlohmann::json paper(const PaperOptions& o, CommandContext& context) {
  const eval::ExperimentConfig config = o.experiment.config();
  const eval::Shard shard = o.experiment.parsedShard();
  const std::vector<sim::DatasetSpec> specs = chosenDatasets(o);
  requireOutputFolder(o.output);
  std::vector<std::string> order;
  for (const sim::DatasetSpec& spec : specs) order.push_back(sim::datasetName(spec));

  std::map<std::string, nlohmann::json> infos, times;
  std::vector<std::string> renders, warnings;
  eval::StudyStages stages;
  stages.meshes = [&](const std::string& name, std::size_t d, const ProgressCallback& progress) {
    const std::string prefix = "[" + std::to_string(d + 1) + "/" + std::to_string(specs.size()) + "] " + name + ": ";
    return datasetMeshes(o, specs[d], prefix, progress, context, infos[name], times[name]);
  };
  stages.after = [&](const eval::DatasetMeshes& meshes, const std::vector<eval::GraspRecord>& part) {
    const std::string warning = frameWarning(part, meshes.name);
    if (!warning.empty()) {
      context.note(warning);
      warnings.push_back(warning);
    }
    for (const std::string& f : report::writeGraspRenders(o.output, meshes, config, part, o.experiment.renders))
      renders.push_back(f);
  };
  std::vector<std::string> planned, surface;
  stages.first_shard = [&](const eval::DatasetExperiment& experiment) {
    const std::string line = runPlannedStudy(o.experiment, experiment, context);
    if (!line.empty()) planned.push_back(line);
    surface.push_back(runSurfaceStudy(experiment));
  };
  stages.note = [&](const std::string& message) { context.note(message); };
  const eval::StudyResult study = eval::runStudy(order, config, shard, stages, context.progress());

  nlohmann::json datasets = nlohmann::json::array(), stage_times = nlohmann::json::array();
  for (const eval::StudyDatasetReport& d : study.datasets) {
    nlohmann::json sampled;
    for (const auto& [fingers, count] : d.grasps_sampled) sampled[std::to_string(fingers)] = count;
    datasets.push_back({{"name", d.name},
                        {"alignment", infos[d.name]["alignment"]},
                        {"preselection", infos[d.name]["preselection"]},
                        {"cad_vertices", d.cad_vertices},
                        {"raw_vertices", d.raw_vertices},
                        {"filtered_vertices", d.filtered_vertices},
                        {"lambda_m", d.lambda_m},
                        {"grasps_sampled", sampled}});
    nlohmann::json t = times[d.name];
    t["evaluate"] = d.evaluate_ms;
    t["render"] = d.after_ms;
    stage_times.push_back({{"dataset", d.name}, {"time_ms", t}});
  }
  // run.json must be the same for every shard of one study (merge checks):
  // all chosen datasets are listed by name, whatever this shard touched.
  nlohmann::json names = nlohmann::json::array();
  for (const std::string& n : order) names.push_back({{"name", n}});
  const nlohmann::json run{{"command", "paper"},
                           {"config", nlohmann::json::parse(eval::experimentConfigJson(config))},
                           {"views", o.views},
                           {"reconstruction", "icrkit reconstruct defaults"},
                           {"smoothing", o.smoothing},
                           {"preselection_rule", o.experiment.preselectionName()},
                           {"mesh_kept_points_only", o.mesh_kept_points_only},
                           {"align", o.experiment.align},
                           {"renders", o.experiment.renders},
                           {"plan", plannedStudyJson(o.experiment)},
                           {"shard", {{"index", shard.index}, {"count", shard.count}}},
                           {"datasets", names}};
  report::ExperimentOutputs outputs;
  outputs.dataset_order = order;
  outputs.finger_counts = config.finger_counts;
  outputs.run_json = run.dump();
  report::WrittenOutputs written = report::writeExperimentOutputs(o.output, study.records, outputs);
  written.files.insert(written.files.end(), renders.begin(), renders.end());
  for (const std::string& f : writePlannedStudies(o.output, planned)) written.files.push_back(f);
  for (const std::string& f : writeSurfaceStudies(o.output, surface)) written.files.push_back(f);
  return {{"output", o.output},
          {"warnings", warnings},
          {"datasets", datasets},
          {"grasps", study.records.size()},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"table1", nlohmann::json::parse(eval::tableOneJson(written.table))},
          {"eligibility", nlohmann::json::parse(eval::eligibilityJson(written.eligibility))["overall"]},
          {"files", written.files},
          {"time_ms", {{"stages", stage_times}, {"total", context.elapsedMs()}}}};
}

}  // namespace

void addPaperCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "paper",
      "The paper's whole study on simulated data: make the nine datasets (DIR/datasets), reconstruct them "
      "(DIR/reconstructions), run the experiment of `icrkit evaluate` on each and write Table I, eligibility.json, "
      "the Fig. 8 histograms, grasps.jsonl and run.json to DIR (docs/results.md)");
  auto o = std::make_shared<PaperOptions>();
  addPaperOptions(*command, *o);
  command->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      ExperimentOptions::mapFieldsTo(context);
      context.mapFields({{"AcquisitionParameters::views", "--views"}, {"dataset names", "--datasets"}});
      context.emit(paper(*o, context));
    };
  });
}

}  // namespace icrkit::app
