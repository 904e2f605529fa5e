#pragma once
/// \file
/// The paper's study over several datasets (Section IV: Table I, Fig. 8), as
/// `icrkit paper` runs it. The datasets' work items (finger counts x grasps,
/// ExperimentConfig::nominalItems) lie end to end and a shard is a
/// contiguous block of them, so a shard only needs the datasets its block
/// touches. For each of those the caller's StudyStages::meshes makes or reads
/// the CAD, raw and filtered meshes (the paper command simulates and
/// reconstructs them; simulation and reconstruction stay out of eval, as in
/// sensitivity_study.hpp), the experiment runs on the block's part of the
/// dataset, and StudyStages::after sees its records (for renders). Writing
/// the run folder is the report's (report/experiment_outputs.hpp).

#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/eval/run_folder.hpp>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace icrkit::eval {

/// One dataset's meshes, in the CAD frame, with unit vertex normals.
struct StudyMeshes {
  TriangleMesh cad, raw, filtered;
  /// Where they came from, named in errors (experimentNamingFiles).
  RunMeshFiles files;
};

/// A DatasetExperiment on `meshes`; an InputError about its "CAD mesh",
/// "raw mesh" or "filtered mesh" is raised again naming that file of `files`
/// (when set), so that the user reads which file is at fault.
std::unique_ptr<DatasetExperiment> experimentNamingFiles(const DatasetMeshes& meshes, const ExperimentConfig& config,
                                                         const RunMeshFiles& files);

struct StudyStages {
  /// Required: the meshes of dataset `name`, the `position`-th of the study
  /// (0-based), reporting its work through `progress`.
  std::function<StudyMeshes(const std::string& name, std::size_t position, const ProgressCallback& progress)> meshes;
  /// Optional: called after a dataset's part has run, with its meshes and records.
  std::function<void(const DatasetMeshes& meshes, const std::vector<GraspRecord>& records)> after;
  /// Optional: called with a dataset's experiment by the one shard that
  /// holds the dataset's first grasp (per-dataset work done once over all
  /// shards: the planned-grasp study).
  std::function<void(const DatasetExperiment& experiment)> first_shard;
  /// Optional: a line for the user ("[1/9] cup_kinect_B: evaluating grasps 0..400").
  std::function<void(const std::string& message)> note;
};

/// What a shard did with one dataset.
struct StudyDatasetReport {
  std::string name;
  std::size_t position = 0;  ///< in the study's dataset list
  std::size_t cad_vertices = 0, raw_vertices = 0, filtered_vertices = 0;
  double lambda_m = 0.0;  ///< the common wrench frame's lambda (DatasetExperiment::cadLambda)
  std::vector<std::pair<std::size_t, std::size_t>> grasps_sampled;  ///< (finger count, CAD grasps sampled)
  std::size_t first_record = 0, record_count = 0;                   ///< its records in StudyResult::records
  double meshes_ms = 0.0, evaluate_ms = 0.0, after_ms = 0.0;
};

struct StudyResult {
  std::vector<GraspRecord> records;          ///< the shard's, in dataset order, each dataset's sorted
  std::vector<StudyDatasetReport> datasets;  ///< the datasets the shard touched, in study order
};

/// Runs the shard's part of the study over `datasets` (names, in order).
/// Progress stages are those of the meshes stage and of the experiment
/// ("grasps"), each prefixed "[i/N] NAME: ". Throws what the stages and the
/// experiment throw (InputError naming a mesh file), and InputError("Shard")
/// for an invalid shard.
StudyResult runStudy(const std::vector<std::string>& datasets, const ExperimentConfig& config, const Shard& shard,
                     const StudyStages& stages, const ProgressCallback& progress = {});

/// Records whose grasp found no reconstructed surface near a contact on
/// either mesh: most of a dataset's grasps means its meshes are not in the
/// CAD mesh's frame or units.
std::size_t graspsWithoutSurface(const std::vector<GraspRecord>& records);

}  // namespace icrkit::eval
