#include "paper_options.hpp"

#include "argument_parsing.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <filesystem>
#include <system_error>

namespace icrkit::app {

namespace fs = std::filesystem;

void addPaperOptions(CLI::App& command, PaperOptions& o) {
  command.add_option("--datasets", o.datasets, "Comma-separated dataset names (default: all nine)");
  command.add_option("--views", o.views, "Views per dataset (0: each dataset's own)")->capture_default_str();
  command.add_flag("--reuse", o.reuse, "Keep datasets and reconstructions already in DIR from an earlier run");
  command
      .add_option("--smoothing", o.smoothing,
                  "Smoothing of the filtered meshes: feature (one-sided windows, 30 deg, the default of icrkit "
                  "reconstruct) or paper (Algorithm 1's window, for Table I as published)")
      ->check(CLI::IsMember({"feature", "paper"}))
      ->capture_default_str();
  command.add_flag("--mesh-kept-points-only", o.mesh_kept_points_only,
                   "Reconstruct the filtered meshes without their excluded points (with --reuse: only for "
                   "datasets reconstructed in this run)");
  o.experiment.addTo(command);
  command.add_option("-o,--output", o.output, "Output folder")->required();
}

std::vector<sim::DatasetSpec> chosenDatasets(const PaperOptions& o) {
  std::vector<sim::DatasetSpec> specs = sim::paperDatasets(split(o.datasets, ','));  // none named: all nine
  if (o.views < 0) throw InputError("--views", "", "expected 0 (the dataset's own) or a positive count");
  if (o.views > 0)
    for (sim::DatasetSpec& s : specs) s.acquisition.views = o.views;
  return specs;
}

eval::StudyMeshes datasetMeshes(const PaperOptions& o, const sim::DatasetSpec& spec, const std::string& prefix,
                                const ProgressCallback& progress, CommandContext& context, nlohmann::json& info,
                                nlohmann::json& times) {
  const eval::RunFolder folder{o.output};
  const std::string name = sim::datasetName(spec);
  double start = context.elapsedMs();
  if (!(o.reuse && folder.hasRecording(name))) {
    context.note(prefix + "simulating");
    sim::simulateDataset(spec, folder.datasetDir(name), progress);
  }
  times["simulate"] = context.elapsedMs() - start;
  start = context.elapsedMs();
  eval::StudyMeshes meshes{{}, {}, {}, {folder.cadMesh(name), folder.rawMesh(name), folder.filteredMesh(name)}};
  const bool reused = o.reuse && folder.hasReconstruction(name);
  if (reused) {
    meshes.raw = io::readTriangleMesh(meshes.files.raw);
    meshes.filtered = io::readTriangleMesh(meshes.files.filtered);
  } else {
    context.note(prefix + "reconstructing");
    reconstruction::ReconstructionParameters params;
    params.mesh_kept_points_only = o.mesh_kept_points_only;
    if (o.smoothing == "paper") params.smoothing.max_normal_angle = M_PI;
    const std::string rule = o.experiment.preselectionName();
    if (rule != "file") params.smoothing.preselection.rule = ndt::parsePreselectionRule(rule, "--preselection");
    reconstruction::ReconstructionResult result = reconstruction::reconstructRawlog(
        (fs::path(folder.datasetDir(name)) / "scans.rawlog").string(), params, progress);
    std::error_code error;
    fs::create_directories(folder.reconstructionDir(name), error);
    if (error) throw InputError(folder.reconstructionDir(name), "", "cannot create the directory: " + error.message());
    io::writeTriangleMesh(meshes.files.raw, result.raw_mesh);
    io::writeTriangleMesh(meshes.files.filtered, result.filtered_mesh);
    meshes.raw = std::move(result.raw_mesh);
    meshes.filtered = std::move(result.filtered_mesh);
  }
  times["reconstruct"] = context.elapsedMs() - start;
  // A reused reconstruction is decided again by the rule asked for (from
  // the smoothing's attributes), so one set of meshes serves every rule.
  info["preselection"] =
      reused ? o.experiment.applyPreselection(meshes.filtered, meshes.files.filtered) : nlohmann::json();
  meshes.cad = io::readTriangleMesh(meshes.files.cad);
  info["alignment"] = nlohmann::json::array();
  for (auto [mesh, label] :
       {std::pair<TriangleMesh*, const char*>{&meshes.raw, "raw.ply"}, {&meshes.filtered, "filtered.ply"}}) {
    const nlohmann::json a = alignIfAsked(o.experiment, *mesh, meshes.cad, label,
                                          (fs::path(folder.reconstructionDir(name)) / label).string());
    if (!a.is_null()) info["alignment"].push_back(a);
  }
  return meshes;
}

}  // namespace icrkit::app
