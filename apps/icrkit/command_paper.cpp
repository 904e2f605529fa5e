// `icrkit paper -o DIR`: the paper's whole study on simulated data — make the
// nine datasets, reconstruct each (raw and filtered meshes), run the
// experiment on each against its CAD mesh, and write Table I, the
// eligibility rates and both Fig. 8 histograms (docs/results.md).

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "experiment_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/sim/dataset.hpp>

#include <filesystem>
#include <memory>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct PaperOptions {
  std::string output;
  std::string datasets;  ///< empty: all nine
  int views = 0;         ///< 0: each dataset's own
  bool reuse = false;
  bool mesh_kept_points_only = false;
  ExperimentOptions experiment = [] {
    ExperimentOptions e;
    e.preselection = "default";
    return e;
  }();
};

std::vector<sim::DatasetSpec> chosenDatasets(const PaperOptions& o) {
  std::vector<sim::DatasetSpec> specs = sim::paperDatasets();
  if (!o.datasets.empty()) {
    std::vector<sim::DatasetSpec> chosen;
    for (const std::string& name : split(o.datasets, ',')) {
      const auto it = std::find_if(specs.begin(), specs.end(),
                                   [&](const sim::DatasetSpec& s) { return sim::datasetName(s) == name; });
      if (it == specs.end()) throw InputError("--datasets", "", "unknown dataset '" + name + "' (see icrkit datasets list)");
      chosen.push_back(*it);
    }
    specs = chosen;
  }
  if (o.views < 0) throw InputError("--views", "", "expected 0 (the dataset's own) or a positive count");
  if (o.views > 0)
    for (sim::DatasetSpec& s : specs) s.acquisition.views = o.views;
  return specs;
}

// A stage label with the dataset's place in the run, for the progress line.
ProgressCallback staged(const ProgressCallback& progress, const std::string& prefix) {
  if (!progress) return {};
  return [progress, prefix](const std::string& stage, std::size_t done, std::size_t total) {
    progress(prefix + stage, done, total);
  };
}

nlohmann::json paper(const PaperOptions& o, CommandContext& context) {
  const eval::ExperimentConfig config = o.experiment.config();
  const eval::Shard shard = o.experiment.parsedShard();
  const std::vector<sim::DatasetSpec> specs = chosenDatasets(o);
  std::error_code error;
  if (fs::exists(o.output, error) && !fs::is_directory(o.output, error))
    throw InputError(o.output, "", "exists and is not a directory");

  // Shards split the nominal work list (datasets x finger counts x grasps)
  // into contiguous blocks, so a shard only makes the datasets it needs.
  const std::size_t per_dataset = config.nominalItems();
  const auto [begin, end] = shard.range(per_dataset * specs.size());

  std::vector<eval::GraspRecord> records;
  nlohmann::json datasets = nlohmann::json::array();
  nlohmann::json stage_times = nlohmann::json::array();
  std::vector<std::string> order;
  std::vector<std::string> renders;
  std::vector<std::string> warnings;
  for (std::size_t d = 0; d < specs.size(); ++d) {
    const std::string name = sim::datasetName(specs[d]);
    order.push_back(name);
    const std::size_t first = d * per_dataset, last = first + per_dataset;
    if (last <= begin || first >= end) continue;
    const std::string prefix = "[" + std::to_string(d + 1) + "/" + std::to_string(specs.size()) + "] " + name + ": ";
    const fs::path data_dir = fs::path(o.output) / "datasets" / name;
    const fs::path rec_dir = fs::path(o.output) / "reconstructions" / name;
    nlohmann::json times;

    double start = context.elapsedMs();
    if (!(o.reuse && fs::exists(data_dir / "manifest.json"))) {
      context.note(prefix + "simulating");
      sim::simulateDataset(specs[d], data_dir.string(), staged(context.progress(), prefix));
    }
    times["simulate"] = context.elapsedMs() - start;

    start = context.elapsedMs();
    TriangleMesh raw, filtered;
    const bool reused = o.reuse && fs::exists(rec_dir / "filtered.ply") && fs::exists(rec_dir / "raw.ply");
    if (reused) {
      raw = io::readTriangleMesh((rec_dir / "raw.ply").string());
      filtered = io::readTriangleMesh((rec_dir / "filtered.ply").string());
    } else {
      context.note(prefix + "reconstructing");
      reconstruction::ReconstructionParameters params;
      params.mesh_kept_points_only = o.mesh_kept_points_only;
      const std::string rule = o.experiment.preselectionName();
      if (rule != "file") params.smoothing.preselection.rule = ndt::parsePreselectionRule(rule);
      reconstruction::ReconstructionResult result = reconstruction::reconstructRawlog(
          (data_dir / "scans.rawlog").string(), params,
          staged(context.progress(), prefix));
      fs::create_directories(rec_dir, error);
      if (error) throw InputError(rec_dir.string(), "", "cannot create the directory: " + error.message());
      io::writeTriangleMesh((rec_dir / "raw.ply").string(), result.raw_mesh);
      io::writeTriangleMesh((rec_dir / "filtered.ply").string(), result.filtered_mesh);
      raw = std::move(result.raw_mesh);
      filtered = std::move(result.filtered_mesh);
    }
    times["reconstruct"] = context.elapsedMs() - start;

    start = context.elapsedMs();
    // A reused reconstruction is decided again by the rule asked for (from
    // the smoothing's attributes), so one set of meshes serves every rule.
    const nlohmann::json preselection =
        reused ? o.experiment.applyPreselection(filtered, (rec_dir / "filtered.ply").string()) : nlohmann::json();
    const TriangleMesh cad = io::readTriangleMesh((data_dir / "object.ply").string());
    nlohmann::json alignment = nlohmann::json::array();
    for (auto [mesh, label] : {std::pair<TriangleMesh*, const char*>{&raw, "raw.ply"}, {&filtered, "filtered.ply"}}) {
      const nlohmann::json a = alignIfAsked(o.experiment, *mesh, cad, label, (rec_dir / label).string());
      if (!a.is_null()) alignment.push_back(a);
    }
    const auto experiment = namingMeshFiles(
        [&] { return std::make_unique<eval::DatasetExperiment>(eval::DatasetMeshes{name, &cad, &raw, &filtered}, config); },
        {{"CAD mesh", (data_dir / "object.ply").string()}, {"raw mesh", (rec_dir / "raw.ply").string()}, {"filtered mesh", (rec_dir / "filtered.ply").string()}});
    const std::size_t local_begin = std::max(begin, first) - first, local_end = std::min(end, last) - first;
    context.note(prefix + "evaluating grasps " + std::to_string(local_begin) + ".." + std::to_string(local_end));
    auto part = experiment->run(local_begin, local_end, staged(context.progress(), prefix));
    times["evaluate"] = context.elapsedMs() - start;
    const std::string warning = frameWarning(part, name);
    if (!warning.empty()) {
      context.note(warning);
      warnings.push_back(warning);
    }
    start = context.elapsedMs();
    for (const std::string& f : writeGraspRenders(o.output, o.experiment, {name, &cad, &raw, &filtered}, config, part))
      renders.push_back(f);
    times["render"] = context.elapsedMs() - start;
    records.insert(records.end(), part.begin(), part.end());

    nlohmann::json sampled;
    for (const std::size_t f : config.finger_counts) sampled[std::to_string(f)] = experiment->sampledGrasps(f);
    datasets.push_back({{"name", name},
                        {"alignment", alignment},
                        {"preselection", preselection},
                        {"cad_vertices", cad.vertexCount()},
                        {"raw_vertices", raw.vertexCount()},
                        {"filtered_vertices", filtered.vertexCount()},
                        {"lambda_m", experiment->cadLambda()},
                        {"grasps_sampled", sampled}});
    stage_times.push_back({{"dataset", name}, {"time_ms", times}});
  }

  // run.json must be the same for every shard of one study (merge checks):
  // all chosen datasets are listed by name, whatever this shard touched.
  nlohmann::json names = nlohmann::json::array();
  for (const std::string& n : order) names.push_back({{"name", n}});
  nlohmann::json run{{"command", "paper"},
                     {"config", nlohmann::json::parse(eval::experimentConfigJson(config))},
                     {"views", o.views},
                     {"reconstruction", "icrkit reconstruct defaults"},
                     {"preselection_rule", o.experiment.preselectionName()},
                     {"mesh_kept_points_only", o.mesh_kept_points_only},
                     {"align", o.experiment.align},
                     {"renders", o.experiment.renders},
                     {"shard", {{"index", shard.index}, {"count", shard.count}}},
                     {"datasets", names}};
  report::ExperimentOutputs outputs;
  outputs.dataset_order = order;
  outputs.finger_counts = config.finger_counts;
  outputs.run_json = run.dump();
  report::WrittenOutputs written = report::writeExperimentOutputs(o.output, records, outputs);
  std::vector<std::string>& files = written.files;
  files.insert(files.end(), renders.begin(), renders.end());

  return {{"output", o.output},
          {"warnings", warnings},
          {"datasets", datasets},
          {"grasps", records.size()},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"table1", nlohmann::json::parse(eval::tableOneJson(written.table))},
          {"eligibility", nlohmann::json::parse(eval::eligibilityJson(written.eligibility))["overall"]},
          {"files", files},
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
  command->add_option("--datasets", o->datasets, "Comma-separated dataset names (default: all nine)");
  command->add_option("--views", o->views, "Views per dataset (0: each dataset's own)")->capture_default_str();
  command->add_flag("--reuse", o->reuse, "Keep datasets and reconstructions already in DIR from an earlier run");
  command->add_flag("--mesh-kept-points-only", o->mesh_kept_points_only,
                    "Reconstruct the filtered meshes without their excluded points (with --reuse: only for "
                    "datasets reconstructed in this run)");
  o->experiment.addTo(*command);
  command->add_option("-o,--output", o->output, "Output folder")->required();
  command->callback([&runner, o] { runner = [o](CommandContext& context) { context.mapFields({{"AcquisitionParameters::views", "--views"}, {"Shard", "--shard"}});
    context.emit(paper(*o, context)); }; });
}

}  // namespace icrkit::app
