// `icrkit evaluate --cad CAD --raw RAW --filtered FILTERED -o DIR`: the
// paper's experiment (Section IV) on one object, and `icrkit merge` which
// combines the run folders of shards into the same outputs.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "experiment_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/sensitivity_study.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/sensitivity_plot.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct EvaluateOptions {
  std::string cad, raw, filtered, name, output;
  bool compute_normals = false;
  ExperimentOptions experiment;
};

TriangleMesh readMeshWithNormals(const std::string& path, bool compute, CommandContext& context) {
  TriangleMesh mesh = io::readTriangleMesh(path);
  if (mesh.faces.empty()) throw InputError(path, "", "has no faces; the evaluation needs a triangle mesh");
  if (!mesh.vertices.hasNormals()) {
    if (!compute)
      throw InputError(path, "", "has no vertex normals (PLY nx/ny/nz or OBJ vn); pass --compute-normals to derive them");
    computeVertexNormals(mesh);
    context.note("icrkit: " + path + ": vertex normals computed from the faces");
  }
  return mesh;
}

void requireOutputFolder(const std::string& output) {
  std::error_code error;
  if (fs::exists(output, error) && !fs::is_directory(output, error))
    throw InputError(output, "", "exists and is not a directory");
}

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
  const auto experiment = namingMeshFiles(
      [&] { return std::make_unique<eval::DatasetExperiment>(eval::DatasetMeshes{name, &cad, &raw, &filtered}, config); },
      {{"CAD mesh", o.cad}, {"raw mesh", o.raw}, {"filtered mesh", o.filtered}});
  const double prepare_ms = context.elapsedMs() - prepare_start;
  const auto [begin, end] = shard.range(config.nominalItems());
  context.note("evaluating " + std::to_string(end - begin) + " of " + std::to_string(experiment->itemCount()) +
               " grasps on " + name);
  const double run_start = context.elapsedMs();
  std::vector<eval::GraspRecord> records = experiment->run(begin, end, context.progress());
  const double run_ms = context.elapsedMs() - run_start;
  const std::string warning = frameWarning(records, name);
  if (!warning.empty()) context.note(warning);

  nlohmann::json sampled;
  for (const std::size_t f : config.finger_counts) sampled[std::to_string(f)] = experiment->sampledGrasps(f);
  nlohmann::json run{{"command", "evaluate"},
                     {"config", nlohmann::json::parse(eval::experimentConfigJson(config))},
                     {"shard", {{"index", shard.index}, {"count", shard.count}}},
                     {"align", o.experiment.align},
                     {"renders", o.experiment.renders},
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
  const double render_start = context.elapsedMs();
  for (const std::string& f :
       writeGraspRenders(o.output, o.experiment, eval::DatasetMeshes{name, &cad, &raw, &filtered}, config, records))
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
            {"write", context.elapsedMs() - write_start - render_ms},
            {"render", render_ms},
            {"total", context.elapsedMs()}}}};
}

struct MergeOptions {
  std::vector<std::string> inputs;
  std::string output;
};

nlohmann::json readRunJson(const std::string& directory) {
  const std::string path = (fs::path(directory) / "run.json").string();
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot be read; expected the run folder of `icrkit evaluate` or `icrkit paper`");
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception& error) {
    throw InputError(path, "", std::string("is not valid JSON: ") + error.what());
  }
}

nlohmann::json merge(const MergeOptions& o, CommandContext& context) {
  requireOutputFolder(o.output);
  if (o.inputs.empty()) throw InputError("merge", "", "expected at least one run folder");
  std::vector<eval::GraspRecord> records;
  std::set<std::size_t> shards;
  nlohmann::json first;
  std::size_t count = 0;
  for (const std::string& input : o.inputs) {
    const nlohmann::json run = readRunJson(input);
    const std::size_t index = run.at("shard").at("index"), n = run.at("shard").at("count");
    nlohmann::json comparable = run;
    comparable.erase("shard");
    comparable.erase("time_ms");
    if (first.is_null()) {
      first = comparable;
      count = n;
    } else if (comparable != first || n != count) {
      throw InputError((fs::path(input) / "run.json").string(), "",
                       "its parameters, datasets or shard count differ from those of " + o.inputs.front());
    }
    if (!shards.insert(index).second)
      throw InputError(input, "", "shard " + std::to_string(index) + " is given twice");
    auto part = eval::readGraspRecords((fs::path(input) / "grasps.jsonl").string());
    records.insert(records.end(), part.begin(), part.end());
  }
  std::vector<std::size_t> missing;
  for (std::size_t i = 0; i < count; ++i)
    if (!shards.count(i)) missing.push_back(i);
  if (!missing.empty()) {
    std::string list;
    for (const std::size_t m : missing) list += (list.empty() ? "" : ",") + std::to_string(m);
    throw InputError("merge", "", "shards missing: " + list + " of " + std::to_string(count));
  }
  std::sort(records.begin(), records.end());
  for (std::size_t i = 1; i < records.size(); ++i)
    if (!(records[i - 1] < records[i]))
      throw InputError("merge", "",
                       "grasp " + records[i].dataset + "/" + std::to_string(records[i].fingers) + "/" +
                           std::to_string(records[i].index) + " appears in two shards");

  nlohmann::json run = first;
  run["shard"] = {{"index", 0}, {"count", 1}};
  run["merged_from"] = o.inputs;
  report::ExperimentOutputs outputs;
  for (const auto& dataset : first.at("datasets")) outputs.dataset_order.push_back(dataset.at("name"));
  for (const auto& f : first.at("config").at("finger_counts")) outputs.finger_counts.push_back(f);
  outputs.run_json = run.dump();
  std::vector<std::string> files = report::writeExperimentOutputs(o.output, records, outputs).files;
  if (first.contains("sensitivity")) {  // an `icrkit sensitivity` study: its own table from the merged records
    const nlohmann::json& study = first.at("sensitivity");
    const eval::SensitivityTable table = eval::computeSensitivityTable(
        records, study.at("object").get<std::string>(), study.at("spacing_m").get<double>(),
        study.at("noise_levels").get<std::vector<double>>(), study.at("rules").get<std::vector<std::string>>());
    for (const std::string& f : report::writeSensitivityOutputs(o.output, table)) files.push_back(f);
  }
  // Each shard rendered the first evaluated grasps of its own block; the
  // merged folder keeps those an unsharded run renders (the first `renders`
  // evaluated grasps of each dataset), so that it equals that run's folder.
  // Runs from before run.json recorded the count keep every shard's renders.
  std::set<std::string> wanted;
  const bool filter = first.contains("renders");
  if (filter) {
    std::map<std::string, long> left;
    for (const eval::GraspRecord& r : records) {
      if (!r.evaluated) continue;
      long& n = left.try_emplace(r.dataset, first.at("renders").get<long>()).first->second;
      if (n-- > 0) wanted.insert(r.dataset + "_" + std::to_string(r.fingers) + "fingers_grasp" + std::to_string(r.index) + "_");
    }
  }
  const auto keep = [&](const std::string& file) {
    if (!filter) return true;
    for (const std::string& stem : wanted)
      if (file.rfind(stem, 0) == 0) return true;
    return false;
  };
  for (const std::string& input : o.inputs) {
    const fs::path from = fs::path(input) / "renders";
    if (!fs::is_directory(from)) continue;
    for (const auto& entry : fs::directory_iterator(from)) {
      if (entry.path().extension() != ".png" || !keep(entry.path().filename().string())) continue;
      fs::create_directories(fs::path(o.output) / "renders");
      const fs::path to = fs::path(o.output) / "renders" / entry.path().filename();
      fs::copy_file(entry.path(), to, fs::copy_options::overwrite_existing);
      files.push_back(to.string());
    }
  }
  context.note("merged " + std::to_string(o.inputs.size()) + " shards, " + std::to_string(records.size()) + " grasps");
  return {{"output", o.output}, {"shards", o.inputs.size()}, {"grasps", records.size()}, {"files", files},
          {"time_ms", {{"total", context.elapsedMs()}}}};
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
  command->callback([&runner, o] { runner = [o](CommandContext& context) { context.mapFields({{"Shard", "--shard"}});
    context.emit(evaluate(*o, context)); }; });
}

void addMergeCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "merge", "Combine the run folders of `icrkit evaluate/paper --shard i/N` (all N of them) into one set of "
               "tables and figures, identical to an unsharded run (docs/scaling.md)");
  auto o = std::make_shared<MergeOptions>();
  command->add_option("inputs", o->inputs, "Shard run folders")->required();
  command->add_option("-o,--output", o->output, "Output folder")->required();
  command->callback([&runner, o] { runner = [o](CommandContext& context) { context.emit(merge(*o, context)); }; });
}

}  // namespace icrkit::app
