// `icrkit merge SHARD_DIR... -o DIR`: the run folders of the shards of one
// study (eval::mergeRunFolders) written as the unsharded run's outputs.

#include "commands.hpp"
#include "experiment_options.hpp"

#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/run_merge.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/sensitivity_plot.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct MergeOptions {
  std::vector<std::string> inputs;
  std::string output;
};

nlohmann::json merge(const MergeOptions& o, CommandContext& context) {
  requireOutputFolder(o.output);
  const eval::MergedRun merged = eval::mergeRunFolders(o.inputs);
  report::ExperimentOutputs outputs;
  outputs.dataset_order = merged.dataset_order;
  outputs.finger_counts = merged.finger_counts;
  outputs.run_json = merged.run_json;
  std::vector<std::string> files = report::writeExperimentOutputs(o.output, merged.records, outputs).files;
  if (merged.sensitivity)  // an `icrkit sensitivity` study: its own table from the merged records
    for (const std::string& f : report::writeSensitivityOutputs(o.output, *merged.sensitivity)) files.push_back(f);
  for (const std::string& f : writePlannedStudies(o.output, merged.planned_lines)) files.push_back(f);
  for (const std::string& f : writeSurfaceStudies(o.output, merged.surface_lines)) files.push_back(f);
  for (const std::string& from : merged.render_files) {
    const fs::path to = fs::path(eval::RunFolder{o.output}.renders()) / fs::path(from).filename();
    fs::create_directories(to.parent_path());
    fs::copy_file(from, to, fs::copy_options::overwrite_existing);
    files.push_back(to.string());
  }
  context.note("merged " + std::to_string(o.inputs.size()) + " shards, " + std::to_string(merged.records.size()) +
               " grasps");
  return {{"output", o.output},
          {"shards", o.inputs.size()},
          {"grasps", merged.records.size()},
          {"files", files},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addMergeCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "merge",
      "Combine the run folders of `icrkit evaluate/paper --shard i/N` (all N of them) into one set of "
      "tables and figures, identical to an unsharded run (docs/scaling.md)");
  auto o = std::make_shared<MergeOptions>();
  command->add_option("inputs", o->inputs, "Shard run folders")->required();
  command->add_option("-o,--output", o->output, "Output folder")->required();
  command->callback([&runner, o] {
    runner = [o](CommandContext& context) {
      context.mapFields({{"run folders", "merge"}});  // the command's own name, as before
      context.emit(merge(*o, context));
    };
  });
}

}  // namespace icrkit::app
