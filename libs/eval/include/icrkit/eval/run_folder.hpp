#pragma once
/// \file
/// The run folder: what `icrkit evaluate`, `paper` and `sensitivity` write,
/// `icrkit merge` joins and `icrkit report` reads, and where each file is.
///
///     DIR/grasps.jsonl                  the grasp records (experiment_records.hpp)
///     DIR/run.json                      the run's parameters; "config" is the ExperimentConfig
///     DIR/table1.*, eligibility.json, fig8_*, conservative.*   computed from the records
///     DIR/renders/*.png                 Fig. 6 pictures of evaluated grasps
///     DIR/datasets/NAME/object.ply      paper: the dataset's CAD mesh (and its recording)
///     DIR/reconstructions/NAME/{raw,filtered}.ply   paper: its reconstruction
///     (`paper --reuse` keeps both when they are complete: hasRecording, hasReconstruction)
///
/// `evaluate` records the paths of the meshes it was given in run.json's
/// "datasets" instead.

#include <icrkit/eval/experiment.hpp>

#include <optional>
#include <string>

namespace icrkit::eval {

/// The paths of one run folder's files.
struct RunFolder {
  std::string dir;

  std::string records() const;  ///< DIR/grasps.jsonl
  std::string runJson() const;  ///< DIR/run.json
  std::string renders() const;  ///< DIR/renders
  std::string datasetDir(const std::string& dataset) const;         ///< DIR/datasets/NAME
  std::string cadMesh(const std::string& dataset) const;            ///< DIR/datasets/NAME/object.ply
  std::string reconstructionDir(const std::string& dataset) const;  ///< DIR/reconstructions/NAME
  std::string rawMesh(const std::string& dataset) const;            ///< .../raw.ply
  std::string filteredMesh(const std::string& dataset) const;       ///< .../filtered.ply
  /// What `--reuse` may keep from an earlier run: a finished recording
  /// (datasets/NAME/manifest.json, written last by the simulator) and a
  /// finished reconstruction (both meshes).
  bool hasRecording(const std::string& dataset) const;
  bool hasReconstruction(const std::string& dataset) const;
  /// DIR/renders/DATASET_<F>fingers_grasp<I>_<label>.png: the Fig. 6
  /// picture of one grasp against the `label` ("filtered", "raw") mesh.
  std::string render(const GraspRecord& record, const std::string& label) const;
};

/// The name every render of `record` starts with: "DATASET_<F>fingers_grasp<I>_".
std::string renderStem(const GraspRecord& record);

/// run.json's "config": `config` as compact JSON (sorted keys). "patch" only
/// when the patch study runs, so that other runs keep their form.
std::string experimentConfigJson(const ExperimentConfig& config);
/// The inverse, from the text of that object ("null" or any non-object:
/// the defaults, which are the paper's); absent keys keep the defaults.
/// InputError (source "run.json", location the key) for a malformed "patch".
ExperimentConfig experimentConfigFromJson(const std::string& config_json);

/// The CAD, raw and filtered meshes of one dataset of a run.
struct RunMeshFiles {
  std::string cad, raw, filtered;
};
/// Where `dataset`'s meshes are, from run.json's text: the paths `evaluate`
/// recorded (relative ones are tried from the current folder, then from the
/// run folder), else the run folder's own (`paper`). Unset when run.json does
/// not list the dataset or is not valid JSON.
std::optional<RunMeshFiles> runMeshFiles(const std::string& run_json, const RunFolder& folder,
                                         const std::string& dataset);

}  // namespace icrkit::eval
