// `icrkit sensitivity (--cad FILE | --object NAME) -o DIR`: the paper's
// Section III-A as a study (eval/sensitivity_study.hpp). The meshes of each
// noise level are made here, from the libraries `icrkit reconstruct` uses:
// raw = ball pivoting with estimated normals, filtered = smoothing, the
// preselection rule, ball pivoting.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "experiment_options.hpp"
#include "preselection_options.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/eval/sensitivity_study.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/reconstruction/meshing/raw_and_filtered_meshes.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/report/experiment_outputs.hpp>
#include <icrkit/report/sensitivity_plot.hpp>
#include <icrkit/sim/cad_objects.hpp>

#include <cmath>
#include <filesystem>
#include <memory>

namespace icrkit::app {
namespace {

namespace fs = std::filesystem;

struct SensitivityOptions {
  std::string cad, object, name, output;
  double spacing = 0.0;
  std::string noise = "0,0.25,0.5,1";
  std::string rules = "default,paper-mean,none";
  bool mesh_kept_points_only = false;
  double window_normal_angle = M_PI;
  ExperimentOptions experiment;
};

std::vector<double> parseLevels(const std::string& text) {
  std::vector<double> levels;
  for (const std::string& part : split(text, ',')) {
    double value = 0;
    if (!parseNumber(part, value) || !std::isfinite(value) || value < 0)
      throw InputError("--noise", "", "expected noise levels >= 0 (multiples of the spacing) separated by commas, got '" +
                                          text + "'");
    levels.push_back(value);
  }
  if (levels.empty()) throw InputError("--noise", "", "expected at least one noise level");
  return levels;
}

std::vector<std::string> parseRules(const std::string& text) {
  std::vector<std::string> rules;
  for (const std::string& part : split(text, ','))
    rules.push_back(ndt::preselectionRuleName(ndt::parsePreselectionRule(part)));
  if (rules.empty()) throw InputError("--preselection", "", "expected at least one rule");
  return rules;
}

// The raw and filtered meshes of one noisy sample, with one copy of the
// filtered mesh per rule (the smoothing is the same; only the flags differ).
eval::SensitivityMeshes buildMeshes(const PointCloud& noisy, const std::vector<std::string>& rules,
                                    bool kept_points_only, double window_normal_angle) {
  PointCloud cloud = noisy;
  cloud.normals.clear();  // the raw mesh gets estimated normals, as a scan would
  ndt::estimateNormals(cloud);
  reconstruction::RawAndFilteredParameters params;
  params.meshing = reconstruction::ReconstructionParameters{}.meshing;
  params.smoothing.max_normal_angle = window_normal_angle;
  eval::SensitivityMeshes out;
  if (!kept_points_only) {
    reconstruction::RawAndFilteredMeshes meshes = reconstruction::meshRawAndFiltered(cloud, params);
    out.raw = std::move(meshes.raw);
    for (const std::string& rule : rules) {
      ndt::PreselectionParameters p;
      p.rule = ndt::parsePreselectionRule(rule);
      TriangleMesh filtered = meshes.filtered;
      ndt::applyPreselection(filtered.vertices.attributes, filtered.vertexCount(), p, "filtered mesh");
      out.filtered.push_back({rule, std::move(filtered), p.rule != ndt::PreselectionRule::None});
    }
    return out;
  }
  // The other reading: each rule's excluded points are left out of its mesh.
  for (std::size_t r = 0; r < rules.size(); ++r) {
    params.smoothing.preselection.rule = ndt::parsePreselectionRule(rules[r]);
    params.mesh_kept_points_only = true;
    reconstruction::RawAndFilteredMeshes meshes = reconstruction::meshRawAndFiltered(cloud, params);
    if (r == 0) out.raw = std::move(meshes.raw);
    out.filtered.push_back({rules[r], std::move(meshes.filtered),
                            params.smoothing.preselection.rule != ndt::PreselectionRule::None});
  }
  return out;
}

nlohmann::json sensitivity(const SensitivityOptions& o, CommandContext& context) {
  eval::SensitivityParameters params;
  params.experiment = o.experiment.config();
  const eval::Shard shard = o.experiment.parsedShard();
  params.noise_levels = parseLevels(o.noise);
  params.rules = parseRules(o.rules);
  if (!(std::isfinite(o.spacing) && o.spacing >= 0)) throw InputError("--spacing", "", "expected metres > 0 (0: automatic)");
  params.spacing_m = o.spacing;
  params.seed = o.experiment.seed;
  if (o.cad.empty() == o.object.empty()) throw InputError("--cad/--object", "", "give exactly one of --cad FILE and --object NAME");
  std::error_code error;
  if (fs::exists(o.output, error) && !fs::is_directory(o.output, error))
    throw InputError(o.output, "", "exists and is not a directory");

  TriangleMesh cad;
  std::string object = o.name;
  if (!o.object.empty()) {
    cad = sim::makeCadObject(sim::parseCadObject(o.object));
    if (object.empty()) object = o.object;
  } else {
    cad = io::readTriangleMesh(o.cad);
    if (cad.faces.empty()) throw InputError(o.cad, "", "has no faces; the study samples a triangle mesh");
    if (!cad.vertices.hasNormals()) {
      computeVertexNormals(cad);
      context.note("icrkit: " + o.cad + ": vertex normals computed from the faces");
    }
    if (object.empty()) object = fs::path(o.cad).stem().string();
  }

  const std::vector<std::string> rules = params.rules;
  const bool kept_only = o.mesh_kept_points_only;
  const double window_angle = checkedWindowNormalAngle(o.window_normal_angle);
  const eval::SensitivityResult result = eval::runSensitivityStudy(
      cad, object, params,
      [&](const PointCloud& noisy, double, double) { return buildMeshes(noisy, rules, kept_only, window_angle); }, shard,
      context.progress());

  nlohmann::json levels = nlohmann::json::array();
  for (const eval::SensitivityLevelInfo& l : result.levels) {
    nlohmann::json excluded;
    for (std::size_t r = 0; r < rules.size() && r < l.excluded_vertices.size(); ++r)
      excluded[rules[r]] = l.excluded_vertices[r];
    levels.push_back({{"noise_level", l.noise_level},
                      {"sigma_m", l.sigma_m},
                      {"built", l.built},
                      {"sample_points", l.sample_points},
                      {"raw_faces", l.raw_faces},
                      {"filtered_faces", l.filtered_faces},
                      {"excluded_vertices", excluded},
                      {"time_ms", {{"meshes", l.build_ms}, {"evaluate", l.evaluate_ms}}}});
  }
  // run.json must be the same for every shard (merge checks it): levels'
  // per-shard details stay in the command's summary.
  nlohmann::json datasets = nlohmann::json::array();
  std::vector<std::string> order;
  for (const double level : params.noise_levels)
    for (const std::string& rule : rules) {
      order.push_back(eval::sensitivityDatasetName(object, level, rule));
      datasets.push_back({{"name", order.back()}});
    }
  nlohmann::json run{{"command", "sensitivity"},
                     {"config", nlohmann::json::parse(eval::experimentConfigJson(params.experiment))},
                     {"shard", {{"index", shard.index}, {"count", shard.count}}},
                     {"sensitivity",
                      {{"object", object},
                       {"cad", o.cad.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.cad)},
                       {"spacing_m", result.spacing_m},
                       {"noise_levels", params.noise_levels},
                       {"rules", rules},
                       {"seed", params.seed},
                       {"mesh_kept_points_only", kept_only}}},
                     {"datasets", datasets}};
  // Only when asked for: runs without it keep their run.json.
  if (window_angle < M_PI) run["sensitivity"]["window_normal_angle_rad"] = window_angle;
  report::ExperimentOutputs outputs;
  outputs.dataset_order = order;
  outputs.finger_counts = params.experiment.finger_counts;
  outputs.run_json = run.dump();
  report::WrittenOutputs written = report::writeExperimentOutputs(o.output, result.records, outputs);
  const eval::SensitivityTable table =
      eval::computeSensitivityTable(result.records, object, result.spacing_m, params.noise_levels, rules);
  for (const std::string& f : report::writeSensitivityOutputs(o.output, table)) written.files.push_back(f);
  return {{"output", o.output},
          {"object", object},
          {"spacing_m", result.spacing_m},
          {"grasps", result.records.size()},
          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"levels", levels},
          {"sensitivity", nlohmann::json::parse(eval::sensitivityJson(table))["rows"]},
          {"files", written.files},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addSensitivityCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "sensitivity",
      "The paper's noise study (Section III-A): sample a CAD mesh (Poisson disk), add Gaussian noise along the "
      "normals at each level, build the raw mesh (estimated normals) and the filtered mesh (smoothing + each "
      "preselection rule), run the experiment of `icrkit evaluate` on each and write DIR/sensitivity.{md,json,svg,"
      "png} beside the usual Table I files and grasps.jsonl (docs/results.md)");
  auto o = std::make_shared<SensitivityOptions>();
  command->add_option("--cad", o->cad, "CAD mesh file (normals computed from the faces when it has none)");
  command->add_option("--object", o->object, "One of the simulator's CAD objects instead (icrkit datasets list)");
  command->add_option("--name", o->name, "Object name in the records (default: the file stem or object name)");
  command->add_option("--spacing", o->spacing, "Poisson-disk spacing of the sample, metres (0: bounding-box diagonal / 150)")
      ->capture_default_str();
  command->add_option("--noise", o->noise, "Noise levels: sigma along the normal in multiples of the spacing")
      ->capture_default_str();
  command->add_option("--preselection", o->rules, "Preselection rules of the filtered meshes, comma-separated (default, paper-mean, none)")
      ->capture_default_str();
  command->add_flag("--mesh-kept-points-only", o->mesh_kept_points_only,
                    "Mesh each rule's smoothed cloud without its excluded points (the other reading of the paper)");
  addWindowNormalAngleOption(*command, o->window_normal_angle);
  o->experiment.addTo(*command, false);
  command->add_option("-o,--output", o->output, "Output folder")->required();
  command->callback(
      [&runner, o] { runner = [o](CommandContext& context) { context.mapFields({{"SensitivityParameters::noise_levels", "--noise"}, {"SensitivityParameters::rules", "--preselection"}, {"SensitivityParameters::spacing_m", "--spacing"}, {"Shard", "--shard"}, {"object name", "--object"}});
    context.emit(sensitivity(*o, context)); }; });
}

}  // namespace icrkit::app
