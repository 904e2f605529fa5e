// `icrkit evaluate --cad CAD --raw RAW --filtered FILTERED -o DIR`: the
// paper's experiment (Section IV, eval::DatasetExperiment) on one object.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "experiment_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/study.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/grasp_render.hpp>

#include <filesystem>
#include <memory>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct EvaluateOptions {
  std::string cad, raw, filtered, name, output;
  bool compute_normals = false;
  ExperimentOptions experiment;
};

nlohmann::json evaluate(const EvaluateOptions& o, CommandContext& context) {
  const eval::ExperimentConfig config = o.experiment.config();
  const eval::Shard shard = o.experiment.parsedShard();
  requireOutputFolder(o.output);
  const std::string name = o.name.empty() ? fs::path(o.cad).stem().string() : o.name;

  const double read_start = context.elapsedMs();
  const TriangleMesh cad = readMeshWithNormals(o.cad, o.compute_normals, context);
  TriangleMesh raw = readMeshWithNormals(o.raw, o.compute_normals, context);
  TriangleMesh filtered = readMeshWithNormals(o.filtered, o.compute_normals, context);
  const double read_ms = context.elapsedMs() - read_start;
  const nlohmann::json preselection = o.experiment.applyPreselection(filtered, o.filtered);
  nlohmann::json alignment = nlohmann::json::array();
  const double align_start = context.elapsedMs();
  for (auto [mesh, path] : {std::pair<TriangleMesh*, const std::string*>{&raw, &o.raw}, {&filtered, &o.filtered}}) {
    const nlohmann::json a = alignIfAsked(o.experiment, *mesh, cad, *path, *path);
    if (!a.is_null()) alignment.push_back(a);
  }
  const double align_ms = context.elapsedMs() - align_start;

  const double prepare_start = context.elapsedMs();
  const auto experiment =
      eval::experimentNamingFiles(eval::DatasetMeshes{name, &cad, &raw, &filtered}, config, {o.cad, o.raw, o.filtered});
  const double prepare_ms = context.elapsedMs() - prepare_start;
  const auto [begin, end] = shard.range(config.nominalItems());
  context.note("evaluating " + std::to_string(end - begin) + " of " + std::to_string(experiment->itemCount()) +
               " grasps on " + name);
  const double run_start = context.elapsedMs();
  std::vector<eval::GraspRecord> records = experiment->run(begin, end, context.progress());
  const double run_ms = context.elapsedMs() - run_start;
  const std::string warning = frameWarning(records, name);
  if (!warning.empty()) context.note(warning);

  const double plan_start = context.elapsedMs();
  std::vector<std::string> planned, surface;
  if (begin == 0) {
    const std::string line = runPlannedStudy(o.experiment, *experiment, context);
    if (!line.empty()) planned.push_back(line);
    surface.push_back(runSurfaceStudy(*experiment));
  }
  const double plan_ms = context.elapsedMs() - plan_start;

  nlohmann::json sampled;
  for (const std::size_t f : config.finger_counts) sampled[std::to_string(f)] = experiment->sampledGrasps(f);
  nlohmann::json run{{"command", "evaluate"},
                     {"config", nlohmann::json::parse(eval::experimentConfigJson(config))},
                     {"shard", {{"index", shard.index}, {"count", shard.count}}},
                     {"align", o.experiment.align},
                     {"renders", o.experiment.renders},
                     {"plan", plannedStudyJson(o.experiment)},
                     {"preselection_rule", o.experiment.preselectionName()},
                     {"datasets",
                      {{{"name", name},
                        {"preselection", preselection},
                        {"alignment", alignment},
                        {"cad", o.cad},
                        {"raw", o.raw},
                        {"filtered", o.filtered},
                        {"cad_vertices", cad.vertexCount()},
                        {"raw_vertices", raw.vertexCount()},
                        {"filtered_vertices", filtered.vertexCount()},
                        {"lambda_m", experiment->cadLambda()},
                        {"grasps_sampled", sampled},
                        {"items", experiment->itemCount()}}}}};

  report::ExperimentOutputs outputs;
  outputs.dataset_order = {name};
  outputs.finger_counts = config.finger_counts;
  outputs.run_json = run.dump();
  const double write_start = context.elapsedMs();
  report::WrittenOutputs written = report::writeExperimentOutputs(o.output, records, outputs);
  std::vector<std::string>& files = written.files;
  for (const std::string& f : writePlannedStudies(o.output, planned)) files.push_back(f);
  for (const std::string& f : writeSurfaceStudies(o.output, surface)) files.push_back(f);
  const double render_start = context.elapsedMs();
  for (const std::string& f : report::writeGraspRenders(o.output, eval::DatasetMeshes{name, &cad, &raw, &filtered},
                                                        config, records, o.experiment.renders))
    files.push_back(f);
  const double render_ms = context.elapsedMs() - render_start;

  nlohmann::json summary = nlohmann::json::parse(eval::tableOneJson(written.table));
  return {{"output", o.output},
          {"dataset", name},
          {"warnings", warning.empty() ? nlohmann::json::array() : nlohmann::json::array({warning})},
          {"grasps", records.size()},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"table1", summary},
          {"eligibility", nlohmann::json::parse(eval::eligibilityJson(written.eligibility))["overall"]},
          {"files", files},
          {"time_ms",
           {{"read", read_ms},
            {"align", align_ms},
            {"prepare", prepare_ms},
            {"grasps", run_ms},
            {"plan", plan_ms},
            {"write", context.elapsedMs() - write_start - render_ms},
            {"render", render_ms},
            {"total", context.elapsedMs()}}}};
}

}  // namespace

void addEvaluateCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "evaluate",
      "The paper's experiment on one object: random force-closure grasps on the CAD mesh, moved onto the raw and "
      "filtered meshes by eq. (2); where both still meet the task, ICRs on all three meshes compared by Algorithm 2 "
      "(Int, FP) and Q_n. Writes DIR/table1.{md,csv,json}, eligibility.json, fig8_<N>fingers.{svg,png,json}, "
      "grasps.jsonl and run.json (docs/evaluation.md)");
  auto o = std::make_shared<EvaluateOptions>();
  command->add_option("--cad", o->cad, "Ground-truth CAD mesh (with vertex normals)")->required();
  command->add_option("--raw", o->raw, "Raw reconstructed mesh (icrkit reconstruct: raw.ply)")->required();
  command->add_option("--filtered", o->filtered,
                      "Filtered reconstructed mesh with the `excluded` attribute (icrkit reconstruct: filtered.ply)")
      ->required();
  command->add_option("--name", o->name, "Dataset name in the tables (default: the CAD file's stem)");
  command->add_flag("--compute-normals", o->compute_normals, "Derive missing vertex normals from the faces");
  o->experiment.addTo(*command);
  command->add_option("-o,--output", o->output, "Output folder (created; files replaced atomically)")->required();
  command->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      ExperimentOptions::mapFieldsTo(context);
      context.emit(evaluate(*o, context));
    };
  });
}

}  // namespace icrkit::app
