#pragma once
// Options shared by `icrkit evaluate` and `icrkit paper`: the experiment's
// parameters (Section IV of the paper) and the shard, reported identically
// in both commands' run.json.

#include "command_context.hpp"

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace icrkit::app {

struct ExperimentOptions {
  std::string fingers = "4,5";
  std::size_t grasps = 200;
  std::uint64_t seed = 1;
  double mu = 0.8;
  int edges = 8;
  double alpha = 0.8;
  std::string mode = "bfs";
  std::string metric = "geodesic";
  double max_line_distance = 0.01;
  double neighbourhood_radius = 0.0;
  std::string shard = "0/1";
  bool no_preselection = false;  ///< the older spelling of --preselection none
  /// "file" (evaluate's default: the filtered mesh's own `excluded` flags),
  /// or a rule (default, paper-mean, none) recomputed from its cardinality
  /// and flatness attributes.
  std::string preselection = "file";
  std::string align = "none";
  /// --conservative [K,K,...]: "" for a bare flag (K = 1), unset without it.
  std::optional<std::string> conservative;
  /// --patch-radius M: the patch-contact study beside the plain one; unset without it.
  std::optional<double> patch_radius;
  int renders = 1;
  /// The planned grasps beside the random ones (eval/planned_grasps.hpp):
  /// `icrkit plan --top plan_top --candidates plan_candidates` on the raw
  /// and filtered meshes, executed on the CAD mesh. 0: none.
  std::size_t plan_top = 10;
  std::size_t plan_candidates = 1000;

  /// `with_preselection` false: the command has its own --preselection.
  void addTo(CLI::App& command, bool with_preselection = true);
  /// Validated: InputError naming the option, or the library's field
  /// (ExperimentConfig::alpha, ...), which mapFieldsTo maps to the option.
  eval::ExperimentConfig config() const;
  /// Maps the experiment's fields to these options in the command's errors.
  static void mapFieldsTo(CommandContext& context);
  eval::Shard parsedShard() const;
  /// The rule's name as run.json records it ("file", "default", ...).
  std::string preselectionName() const;
  /// Recomputes `filtered`'s `excluded` flags when a rule was chosen;
  /// returns what it did (null for "file" and "none"). InputError naming
  /// `path` when the mesh lacks the smoothing's attributes.
  nlohmann::json applyPreselection(TriangleMesh& filtered, const std::string& path) const;
};

/// run.json's "plan": the planned-grasp study's parameters (null when off).
nlohmann::json plannedStudyJson(const ExperimentOptions& options);

/// The planned-grasp study of one dataset (one line of planned.jsonl), or
/// empty with --plan-top 0. Notes what it found.
std::string runPlannedStudy(const ExperimentOptions& options, const eval::DatasetExperiment& experiment,
                            CommandContext& context);

/// Writes DIR/planned.jsonl and planned.md (atomically) from the study
/// lines; nothing without lines. Returns the files written.
std::vector<std::string> writePlannedStudies(const std::string& dir, const std::vector<std::string>& lines);

/// The surface accuracy of the raw and filtered meshes against the CAD mesh
/// (one line of surface.jsonl, eval/surface_accuracy.hpp).
std::string runSurfaceStudy(const eval::DatasetExperiment& experiment);

/// Writes DIR/surface.jsonl and surface.md (atomically) from the lines;
/// nothing without lines. Returns the files written.
std::vector<std::string> writeSurfaceStudies(const std::string& dir, const std::vector<std::string>& lines);

/// A mesh for the experiment: faces required; vertex normals from the
/// file, or with `compute` derived from the faces (noted), else an
/// InputError naming the file and --compute-normals.
TriangleMesh readMeshWithNormals(const std::string& path, bool compute, CommandContext& context);

/// A warning when most grasps of `records` could not be moved onto a
/// reconstructed mesh at all (meshes in different frames or units); empty
/// when all is well.
std::string frameWarning(const std::vector<eval::GraspRecord>& records, const std::string& dataset);

/// With --align icp: moves `mesh` onto the CAD surface (point-to-plane ICP)
/// and returns what was done, recorded under `name`; with --align none:
/// nothing (null). A failed alignment is an InputError naming `path`.
nlohmann::json alignIfAsked(const ExperimentOptions& options, TriangleMesh& mesh, const TriangleMesh& cad,
                            const std::string& name, const std::string& path);

}  // namespace icrkit::app
