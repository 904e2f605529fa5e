#include "sensitivity_options.hpp"

#include "argument_parsing.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/ndt/preselection.hpp>
#include <icrkit/reconstruction/meshing/meshes_per_rule.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

namespace icrkit::app {

namespace {

std::vector<double> parseLevels(const std::string& text) {
  std::vector<double> levels;
  for (const std::string& part : split(text, ',')) {
    double value = 0;
    if (!parseNumber(part, value))
      throw InputError("--noise", "",
                       "expected noise levels >= 0 (multiples of the spacing) separated by commas, got '" + text + "'");
    levels.push_back(value);
  }
  return levels;
}

std::vector<std::string> parseRules(const std::string& text) {
  std::vector<std::string> rules;
  for (const std::string& part : split(text, ','))
    rules.push_back(ndt::preselectionRuleName(ndt::parsePreselectionRule(part, "--preselection")));
  return rules;
}

}  // namespace

// The raw and filtered meshes of one noisy sample, with one copy of the
// filtered mesh per rule (the smoothing is the same; only the flags differ).
eval::SensitivityMeshes buildMeshes(const PointCloud& noisy, const std::vector<std::string>& rules,
                                    bool kept_points_only, double window_normal_angle) {
  reconstruction::RawAndFilteredParameters params;
  params.meshing = reconstruction::ReconstructionParameters{}.meshing;
  params.smoothing.max_normal_angle = window_normal_angle;
  params.mesh_kept_points_only = kept_points_only;
  std::vector<ndt::PreselectionRule> parsed;
  for (const std::string& rule : rules) parsed.push_back(ndt::parsePreselectionRule(rule, "--preselection"));
  reconstruction::MeshesPerRule meshes = reconstruction::meshRawAndFilteredPerRule(noisy, parsed, params);
  eval::SensitivityMeshes out;
  out.raw = std::move(meshes.raw);
  for (std::size_t r = 0; r < rules.size(); ++r)
    out.filtered.push_back({rules[r], std::move(meshes.filtered[r]), parsed[r] != ndt::PreselectionRule::None});
  return out;
}

eval::SensitivityParameters sensitivityParameters(const SensitivityOptions& o) {
  eval::SensitivityParameters params;
  params.experiment = o.experiment.config();
  params.noise_levels = parseLevels(o.noise);
  params.rules = parseRules(o.rules);
  if (o.spacing != 0.0) params.spacing_m = o.spacing;
  params.seed = o.experiment.seed;
  return params;
}

void addSensitivityOptions(CLI::App& command, SensitivityOptions& o) {
  command.add_option("--cad", o.cad, "CAD mesh file (normals computed from the faces when it has none)");
  command.add_option("--object", o.object, "One of the simulator's CAD objects instead (icrkit datasets list)");
  command.add_option("--name", o.name, "Object name in the records (default: the file stem or object name)");
  command
      .add_option("--spacing", o.spacing, "Poisson-disk spacing of the sample, metres (0: bounding-box diagonal / 150)")
      ->capture_default_str();
  command.add_option("--noise", o.noise, "Noise levels: sigma along the normal in multiples of the spacing")
      ->capture_default_str();
  command
      .add_option("--preselection", o.rules,
                  "Preselection rules of the filtered meshes, comma-separated (default, paper-mean, none)")
      ->capture_default_str();
  command.add_flag("--mesh-kept-points-only", o.mesh_kept_points_only,
                   "Mesh each rule's smoothed cloud without its excluded points (the other reading of the paper)");
  addWindowNormalAngleOption(command, o.window_normal_angle);
  o.experiment.addTo(command, false);
  command.add_option("-o,--output", o.output, "Output folder")->required();
}

}  // namespace icrkit::app
