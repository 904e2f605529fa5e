// `icrkit smooth IN -o OUT`: the 3D-NDT smoothing layer and preselection
// (ndt::smoothPointCloud) on any point cloud or mesh's vertices. Writes OUT
// with the per-point attributes and the JSON summary next to it.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "preselection_options.hpp"
#include "smoothing_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/reconstruction/fusion/octree_fusion.hpp>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct SmoothOptions {
  std::string input;
  std::string output;
  std::string radius = "4x";
  int passes = 1;
  std::string preselection = "default";
  bool no_preselection = false;  ///< --no-preselection: the same as --preselection none
  std::optional<double> cardinality_threshold;
  std::optional<double> flatness_threshold;
  std::string viewpoint;
  double window_normal_angle = M_PI;
};

ndt::SmoothingParameters parameters(const SmoothOptions& options) {
  ndt::SmoothingParameters params;
  params.radius = parseLength("--radius", options.radius);
  params.passes = options.passes;
  params.preselection.rule = options.no_preselection
                                 ? ndt::PreselectionRule::None
                                 : ndt::parsePreselectionRule(options.preselection, "--preselection");
  params.preselection.cardinality_threshold = options.cardinality_threshold;
  params.preselection.flatness_threshold = options.flatness_threshold;
  if (!options.viewpoint.empty()) params.viewpoint = parsePoint("--viewpoint", options.viewpoint);
  params.max_normal_angle = checkedWindowNormalAngle(options.window_normal_angle);
  // Checked before a large file is read.
  params.validate();
  return params;
}

nlohmann::json smooth(const SmoothOptions& options, CommandContext& context) {
  const ndt::SmoothingParameters params = parameters(options);
  io::formatFromPath(options.input);
  io::formatFromPath(options.output);
  const std::string summary_path = summaryPathFor(options.output);
  // Same-named output and summary would overwrite each other; refuse before any work.
  if (summary_path == options.output)
    throw InputError(options.output, "", "the output needs an extension other than .json (the summary goes there)");

  const double read_start = context.elapsedMs();
  PointCloud cloud = io::readPointCloud(options.input);
  const double read_ms = context.elapsedMs() - read_start;
  // A fused cloud knows each point's sensor: its normals face it.
  ndt::SmoothingParameters run = params;
  if (!run.viewpoint) run.viewpoints = reconstruction::fusionViewpoints(cloud);

  const ndt::SmoothingReport s = renamingInputErrors(
      "point cloud", options.input, [&] { return ndt::smoothPointCloud(cloud, run, context.progress()); });

  const double write_start = context.elapsedMs();
  io::writePointCloud(options.output, cloud);
  const double write_ms = context.elapsedMs() - write_start;

  nlohmann::json viewpoint = nullptr;
  if (params.viewpoint) viewpoint = {params.viewpoint->x(), params.viewpoint->y(), params.viewpoint->z()};
  if (!run.viewpoints.empty()) viewpoint = "per point (viewpoint_x/y/z)";
  const nlohmann::json preselection = preselectionJson(s.preselection, params.preselection.cardinality_threshold.has_value(),
                                                       params.preselection.flatness_threshold.has_value());
  nlohmann::json summary{
      {"input", options.input},
      {"output", options.output},
      {"summary", summary_path},
      {"points", s.points},
      {"radius_m", s.radius_m},
      {"radius_factor", params.radius.relative ? nlohmann::json(params.radius.value) : nlohmann::json(nullptr)},
      // null when --radius was given in metres: the spacing is then not measured
      {"median_spacing_m", s.median_spacing_m > 0 ? nlohmann::json(s.median_spacing_m) : nlohmann::json(nullptr)},
      {"passes", s.passes},
      {"window_normal_angle_rad", params.max_normal_angle},
      {"small_windows", s.small_windows},
      {"mean_cardinality", s.preselection.mean_cardinality},
      {"mean_flatness", s.preselection.mean_flatness},
      {"median_cardinality", s.preselection.median_cardinality},
      {"median_flatness", s.preselection.median_flatness},
      {"preselection", preselection["rule"]},
      {"thresholds", preselection["thresholds"]},
      {"excluded", preselection["excluded"]},
      {"mean_displacement_m", s.mean_displacement_m},
      {"max_displacement_m", s.max_displacement_m},
      {"viewpoint", viewpoint},
      {"time_ms", {{"read", read_ms}, {"smooth", s.time_ms}, {"write", write_ms}, {"total", context.elapsedMs()}}}};
  writeSummaryFile(summary_path, summary);
  return summary;
}

}  // namespace

void addSmoothCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "smooth",
      "3D-NDT smoothing layer and preselection (Krug et al., Alg. 1): each point is projected onto the plane of "
      "the two dominant eigenvectors of its spherical window. Writes OUT (any format; .ply keeps the vertex "
      "properties cardinality, flatness, displacement, excluded and the normals nx, ny, nz) and the JSON summary "
      "next to it (OUT with .json)");
  auto options = std::make_shared<SmoothOptions>();
  command
      ->add_option("input", options->input, "Point cloud or mesh (.ply, .obj, .pcd, .xyz); meshes give their vertices")
      ->required();
  command->add_option("-o,--output", options->output, "Output cloud, written atomically (.ply recommended)")
      ->required();
  command
      ->add_option("--radius", options->radius,
                   "Window radius: metres (0.004) or a multiple of the median nearest-neighbour spacing (4x)")
      ->capture_default_str();
  command->add_option("--passes", options->passes, "Smoothing passes k, each from the previous pass's output")
      ->capture_default_str();
  addPreselectionOption(*command, options->preselection, "marking points as excluded");
  command->add_flag("--no-preselection", options->no_preselection, "Same as --preselection none: no 'excluded' flags");
  command->add_option("--cardinality-threshold", options->cardinality_threshold,
                      "Exclude points whose window holds fewer points (default: the rule's own threshold)");
  command->add_option("--flatness-threshold", options->flatness_threshold,
                      "Exclude points whose flatness sqrt(l2/l3) is lower (default: the rule's own threshold)");
  command->add_option("--viewpoint", options->viewpoint,
                      "Sensor position x,y,z (metres): normals point towards it (default: a fused cloud's normals "
                      "face each point's own sensor, its viewpoint_x/y/z; other clouds' point outwards from the "
                      "centroid, made consistent over neighbours)");
  addWindowNormalAngleOption(*command, options->window_normal_angle);
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      context.mapFields({{"SmoothingParameters::radius", "--radius"},
                         {"SmoothingParameters::passes", "--passes"},
                         {"PreselectionParameters::cardinality_threshold", "--cardinality-threshold"},
                         {"PreselectionParameters::flatness_threshold", "--flatness-threshold"}});
      context.emit(smooth(*options, context));
    };
  });
}

}  // namespace icrkit::app
