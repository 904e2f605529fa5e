#include "experiment_options.hpp"

#include "argument_parsing.hpp"
#include "contact_model_options.hpp"
#include "preselection_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/eval/rigid_alignment.hpp>
#include <icrkit/eval/study.hpp>
#include <icrkit/eval/surface_accuracy.hpp>

#include <icrkit/core/atomic_file.hpp>

#include <cmath>
#include <filesystem>

namespace icrkit::app {

void ExperimentOptions::addTo(CLI::App& command, bool with_preselection) {
  command.add_option("--fingers", fingers, "Finger counts of the test sets, comma-separated")->capture_default_str();
  command.add_option("--grasps", grasps, "Random CAD grasps per finger count and dataset")
      ->check(atLeast(1))
      ->capture_default_str();
  command.add_option("--seed", seed, "Seed of the grasp sampling (set for f fingers: seed * 1000 + f)")
      ->capture_default_str();
  command.add_option("--mu", mu, "Friction coefficient of the frictional point contacts")->capture_default_str();
  command.add_option("--edges", edges, "Edges of the linearised friction cones")->capture_default_str();
  command.add_option("--alpha", alpha, "TWS radius = alpha x epsilon of the CAD grasp")->capture_default_str();
  command.add_option("--mode", mode, "Region growth: bfs (from the contact) or full (every vertex)")
      ->capture_default_str();
  command.add_option("--metric", metric,
                     "Distances of Q_n: geodesic (shortest paths over the CAD mesh: edges plus unfolded diagonals) "
                     "or euclidean")
      ->capture_default_str();
  command.add_option("--max-line-distance", max_line_distance,
                     "Normal-line crossings farther than this (metres) are ignored (the object's far side)")
      ->capture_default_str();
  command.add_option("--neighbourhood-radius", neighbourhood_radius,
                     "Candidate vertices around a crossing, metres (0: twice the target's median edge)")
      ->capture_default_str();
  if (with_preselection)
    command
      .add_option("--preselection", preselection,
                  "Preselection of the filtered mesh: file (its own `excluded` flags), default (the robust rule), "
                  "paper-mean (the paper's literal rule) or none (smoothing alone); a rule is recomputed from the "
                  "mesh's cardinality and flatness (docs/smoothing.md)")
      ->check(CLI::IsMember({"file", "default", "robust", "paper-mean", "none"}))
      ->capture_default_str();
  if (with_preselection) command.add_flag("--no-preselection", no_preselection, "Same as --preselection none");
  command.add_option("--align", align,
                     "Rigid alignment of the raw and filtered meshes to the CAD surface first: none (meshes already in "
                     "the CAD frame, as simulated ones are) or icp (point-to-plane ICP; the paper aligned by hand)")
      ->capture_default_str();
  command.add_option("--renders", renders,
                     "Fig. 6 renders (CAD vs filtered, CAD vs raw) of this many evaluated grasps per dataset, in "
                     "DIR/renders/ (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command
      .add_option("--plan-top", plan_top,
                  "Beside the random grasps, plan this many grasps (icrkit plan, 4 fingers, task half the median "
                  "epsilon of the random CAD grasps) on the raw and on the filtered mesh and execute them on the CAD "
                  "mesh: aimed, random picks, 3 mm placement error, and a random baseline (planned.{jsonl,md}; 0: "
                  "none)")
      ->capture_default_str();
  command.add_option("--plan-candidates", plan_candidates, "Candidates the planner draws (--plan-top)")
      ->check(atLeast(1))
      ->capture_default_str();
  command.add_option("--shard", shard, "Run shard i of N (0-based) of the work; combine with `icrkit merge`")
      ->capture_default_str();
  command
      .add_option_function<std::string>(
          "--conservative", [this](const std::string& value) { conservative = value; },
          "Also grow uncertainty-aware regions on the raw and filtered meshes with K (default 1) or each K of a "
          "comma-separated list (a curve), beside the plain ones: conservative.{json,md,svg}. The meshes need "
          "the normal_sigma and position_sigma vertex attributes. Write --conservative=K before a positional")
      ->expected(0, 1);
  command.add_option_function<double>(
      "--patch-radius", [this](const double& value) { patch_radius = value; },
      "Also run every evaluated grasp with the reference ICR library's multi-point (patch) contacts of this "
      "radius (metres) on all three meshes: its own task (alpha x the CAD patch epsilon) and CAD regions, rows "
      "'patch' in conservative.{json,md}. Costs up to 5 patch hulls per grasp (seconds each on dense meshes)");
}

void ExperimentOptions::mapFieldsTo(CommandContext& context) {
  context.mapFields({{"ExperimentConfig::finger_counts", "--fingers"},
                     {"ExperimentConfig::grasps_per_set", "--grasps"},
                     {"ExperimentConfig::alpha", "--alpha"},
                     {"ExperimentConfig::conservative_sigmas", "--conservative"},
                     {"MappingParameters::max_line_distance", "--max-line-distance"},
                     {"MappingParameters::neighbourhood_radius", "--neighbourhood-radius"},
                     {"PatchParameters::radius_m", "--patch-radius"},
                     {"contact model", "--mu/--edges"},
                     {"Shard", "--shard"}});
}

eval::Shard ExperimentOptions::parsedShard() const {
  const auto parts = split(shard, '/');
  double index = 0, count = 0;
  if (parts.size() != 2 || !parseNumber(parts[0], index) || !parseNumber(parts[1], count) || index < 0 ||
      count < 1 || index != std::floor(index) || count != std::floor(count) || index >= count)
    throw InputError("--shard", "", "expected i/N with 0 <= i < N, got '" + shard + "'");
  return {static_cast<std::size_t>(index), static_cast<std::size_t>(count)};
}

eval::ExperimentConfig ExperimentOptions::config() const {
  eval::ExperimentConfig config;
  config.finger_counts.clear();
  for (const std::string& text : split(fingers, ',')) {
    double value = 0;
    if (!parseNumber(text, value) || value != std::floor(value) || value < 2 || value > 20)
      throw InputError("--fingers", "", "expected finger counts 2..20 separated by commas, got '" + fingers + "'");
    config.finger_counts.push_back(static_cast<std::size_t>(value));
  }
  config.grasps_per_set = grasps;
  config.seed = seed;
  config.friction = mu;
  config.cone_edges = edges;
  config.alpha = alpha;
  if (mode == "bfs")
    config.growth = icr::GrowthMode::BreadthFirst;
  else if (mode == "full")
    config.growth = icr::GrowthMode::Full;
  else
    throw InputError("--mode", "", "expected bfs or full, got '" + mode + "'");
  if (metric == "geodesic")
    config.metric = eval::DistanceMetric::Geodesic;
  else if (metric == "euclidean")
    config.metric = eval::DistanceMetric::Euclidean;
  else
    throw InputError("--metric", "", "expected geodesic or euclidean, got '" + metric + "'");
  config.mapping.max_line_distance = max_line_distance;
  if (neighbourhood_radius != 0.0) config.mapping.neighbourhood_radius = neighbourhood_radius;  // 0: automatic
  config.preselection = preselectionName() != "none";
  if (conservative) {
    const std::vector<std::string> items = conservative->empty() ? std::vector<std::string>{"1"} : split(*conservative, ',');
    for (const std::string& text : items) {
      double k = 0;
      if (!parseNumber(text, k))
        throw InputError("--conservative", "", "expected K >= 0 or a comma-separated list of them, got '" + *conservative + "'");
      config.conservative_sigmas.push_back(k);
    }
  }
  if (patch_radius) {
    config.patch = icr::PatchParameters{};
    config.patch->radius_m = *patch_radius;
  }
  if (align != "none" && align != "icp") throw InputError("--align", "", "expected none or icp, got '" + align + "'");
  // The library names a bad field; the commands map it to the flag (mapFieldsTo).
  config.validate();
  return config;
}

std::string ExperimentOptions::preselectionName() const {
  if (no_preselection) return "none";
  if (preselection == "file") return "file";
  return ndt::preselectionRuleName(ndt::parsePreselectionRule(preselection, "--preselection"));
}

nlohmann::json ExperimentOptions::applyPreselection(TriangleMesh& filtered, const std::string& path) const {
  const std::string name = preselectionName();
  if (name == "file" || name == "none") return nullptr;
  ndt::PreselectionParameters params;
  params.rule = ndt::parsePreselectionRule(name, "--preselection");
  return preselectionJson(ndt::applyPreselection(filtered.vertices.attributes, filtered.vertexCount(), params, path));
}

nlohmann::json alignIfAsked(const ExperimentOptions& options, TriangleMesh& mesh, const TriangleMesh& cad,
                            const std::string& name, const std::string& path) {
  if (options.align != "icp") return nullptr;
  eval::AlignmentResult a;
  try {
    a = eval::alignToCad(mesh, cad);
  } catch (const InputError& error) {
    throw InputError(path, "", std::string("--align icp: ") + error.detail());
  }
  eval::transformMesh(mesh, a.transform);
  const Eigen::AngleAxisd rotation(a.transform.linear());
  nlohmann::json matrix = nlohmann::json::array();
  const Eigen::Matrix4d m = a.transform.matrix();
  for (int r = 0; r < 4; ++r) matrix.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return {{"mesh", name},
          {"method", "point-to-plane ICP"},
          {"matrix", matrix},
          {"translation_m", {a.transform.translation().x(), a.transform.translation().y(), a.transform.translation().z()}},
          {"rotation_rad", rotation.angle()},
          {"iterations", a.iterations},
          {"converged", a.converged},
          {"rms_before_m", a.rms_before_m},
          {"rms_after_m", a.rms_after_m}};
}

nlohmann::json plannedStudyJson(const ExperimentOptions& options) {
  if (options.plan_top == 0) return nullptr;
  const eval::PlannedExecutionParameters execution;
  return {{"top", options.plan_top},
          {"candidates", options.plan_candidates},
          {"fingers", 4},
          {"task", "0.5 x median epsilon of the random CAD grasps"},
          {"picks_per_grasp", execution.picks_per_grasp},
          {"placement_samples", execution.placement_samples},
          {"placement_error_m", execution.placement_error_m}};
}

std::string runPlannedStudy(const ExperimentOptions& options, const eval::DatasetExperiment& experiment,
                            CommandContext& context) {
  if (options.plan_top == 0) return {};
  planning::PlanningParameters planning;
  planning.top = options.plan_top;
  planning.candidates = options.plan_candidates;
  planning.seed = options.seed;
  planning.regions.mode = options.mode == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
  eval::PlannedExecutionParameters execution;
  execution.seed = options.seed;
  const eval::PlannedGraspStudy study = experiment.plannedGrasps(planning, execution);
  const auto line = [](const eval::PlannedMeshStudy& s) {
    if (!s.error.empty()) return s.mesh + ": no plan (" + s.error + ")";
    return s.mesh + ": " + std::to_string(s.grasps.size()) + " grasps, aimed " +
           std::to_string(static_cast<int>(std::lround(100 * s.aimedHeldFraction()))) + "%, picks " +
           std::to_string(static_cast<int>(std::lround(100 * s.picksHeldFraction()))) + "%, placement " +
           std::to_string(static_cast<int>(std::lround(100 * s.placementsHeldFraction()))) + "% held on the CAD";
  };
  context.note(study.dataset + ": planned grasps, " + line(study.filtered) + "; " + line(study.raw) +
               "; random baseline " + line(study.filtered_random));
  return eval::plannedGraspStudyJson(study);
}

namespace {

// DIR/STEM.jsonl (the lines) and DIR/STEM.md (`heading` and the table),
// atomically; nothing without lines.
std::vector<std::string> writeDatasetStudies(const std::string& dir, const std::string& stem,
                                             const std::vector<std::string>& lines, const std::string& heading,
                                             const std::string& table) {
  if (lines.empty()) return {};
  const std::string jsonl = (std::filesystem::path(dir) / (stem + ".jsonl")).string();
  const std::string md = (std::filesystem::path(dir) / (stem + ".md")).string();
  writeFileAtomically(jsonl, [&](std::ostream& out) {
    for (const std::string& l : lines) out << l << "\n";
  });
  writeFileAtomically(md, [&](std::ostream& out) { out << heading << "\n\n" << table; });
  return {jsonl, md};
}

}  // namespace

std::vector<std::string> writePlannedStudies(const std::string& dir, const std::vector<std::string>& lines) {
  if (lines.empty()) return {};
  return writeDatasetStudies(dir, "planned", lines, "# Planned grasps executed on the CAD mesh",
                             eval::plannedGraspStudiesMarkdown(lines));
}

std::string runSurfaceStudy(const eval::DatasetExperiment& experiment) {
  const eval::DatasetMeshes& m = experiment.meshes();
  return eval::datasetSurfaceAccuracyJson(m.name, *m.cad, *m.raw, *m.filtered);
}

std::vector<std::string> writeSurfaceStudies(const std::string& dir, const std::vector<std::string>& lines) {
  if (lines.empty()) return {};
  return writeDatasetStudies(dir, "surface", lines,
                             "# Surface accuracy against the CAD mesh\n\nPer vertex: distance to the CAD surface and "
                             "angle between the vertex normal and the CAD face normal there; near edges = within 4 mm "
                             "of a CAD edge whose faces differ by more than 30 deg (docs/evaluation.md).",
                             eval::surfaceAccuracyMarkdown(lines));
}

TriangleMesh readMeshWithNormals(const std::string& path, bool compute, CommandContext& context) {
  TriangleMesh mesh = io::readTriangleMesh(path);
  if (mesh.faces.empty()) throw InputError(path, "", "has no faces; the evaluation needs a triangle mesh");
  if (!mesh.vertices.hasNormals()) {
    if (!compute)
      throw InputError(path, "",
                       "has no vertex normals (PLY nx/ny/nz or OBJ vn); pass --compute-normals to derive them");
    computeVertexNormals(mesh);
    context.note("icrkit: " + path + ": vertex normals computed from the faces");
  }
  return mesh;
}

std::string frameWarning(const std::vector<eval::GraspRecord>& records, const std::string& dataset) {
  const std::size_t unreachable = eval::graspsWithoutSurface(records);
  // Unscanned undersides leave a quarter or so of the grasps without surface;
  // far more means the meshes do not lie on each other.
  if (records.empty() || 2 * unreachable <= records.size()) return {};
  return "icrkit: warning: " + dataset + ": " + std::to_string(unreachable) + " of " + std::to_string(records.size()) +
         " grasps found no reconstructed surface within --max-line-distance of a contact on either mesh; are the "
         "meshes in the CAD mesh's frame and units? (--align icp aligns them)";
}

}  // namespace icrkit::app
