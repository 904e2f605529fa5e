#include "plan_options.hpp"

#include "argument_parsing.hpp"

#include <cmath>
#include <string>

namespace icrkit::app {

void addPlanOptions(CLI::App& command, PlanOptions& options) {
  // A reconstruction lives in the world frame: torques about its origin
  // would be about a point a metre away. The object's centroid is the frame.
  options.mesh.torque_reference = icr::TorqueReference::Centroid;
  options.mesh.addTo(command);
  options.contact_model.addTo(command);
  command.add_option("--fingers", options.fingers, "Finger counts to plan for, e.g. 3,4,5")->capture_default_str();
  command.add_option("--top", options.top, "Grasps to return, best first (over all finger counts)")->capture_default_str();
  command.add_option("--candidates", options.candidates, "Random contact sets drawn per finger count")
      ->capture_default_str();
  command.add_option("--hulls", options.hulls,
                     "Hulls built per finger count, for the candidates whose epsilon bound is largest "
                     "(default max(20 x top, 64))");
  auto* alpha = command
                    .add_option("--alpha", options.alpha,
                                "Task: a ball of radius alpha x each candidate's epsilon (the paper's), alpha in (0, 1]")
                    ->capture_default_str();
  auto* radius = command.add_option("--tws-radius", options.tws_radius,
                                    "Task: a ball of this absolute radius (wrench units of `icrkit icr`), the same "
                                    "for every candidate; instead of --alpha")
                     ->check(CLI::PositiveNumber);
  alpha->excludes(radius);
  command.add_option("--mode", options.mode, "Region growth: bfs or full")
      ->check(CLI::IsMember({"bfs", "full"}))
      ->capture_default_str();
  options.conservative.addTo(command);
  command.add_option("--task-margin", options.task_margin,
                     "Regions are grown for the task x (1 + margin), and candidates must reach it: slack for what "
                     "the mesh gets wrong (docs/planning.md)")
      ->capture_default_str();
  command.add_option("--placement-error", options.placement_error,
                     "The robot's fingertip placement error (metres, sigma per tangent axis); the score is the "
                     "probability that every finger lands inside its region")
      ->capture_default_str();
  command.add_option("--placement-samples", options.placement_samples, "Offsets per finger the score is estimated on")
      ->capture_default_str();
  command.add_option("--rim-distance", options.rim_distance,
                     "No finger closer than this (metres, along the mesh) to the rim of the seen surface")
      ->capture_default_str();
  command.add_option("--footprint-radius", options.footprint_radius,
                     "The fingertip's footprint (metres): normals within it must agree ...")
      ->capture_default_str();
  command.add_option("--max-normal-spread", options.max_normal_spread,
                     "... to within this angle (radians) of their mean: the vertex's own and all but ...")
      ->capture_default_str();
  command.add_option("--max-spread-fraction", options.max_spread_fraction,
                     "... this fraction of the others (0: every one)")
      ->capture_default_str();
  command.add_option("--max-normal-sigma", options.max_normal_sigma,
                     "No finger where the mesh's `normal_sigma` exceeds this (radians; ignored without the attribute)")
      ->capture_default_str();
  command.add_option("--min-support", options.min_support,
                     "No finger where a vertex under the footprint has a `cardinality` below this fraction of the "
                     "mesh's median (0: off; ignored without the attribute)")
      ->capture_default_str();
  command.add_option("--min-flatness", options.min_flatness,
                     "No finger where the mesh's `flatness` is below this fraction of its median (0: off; ignored "
                     "without the attribute)")
      ->capture_default_str();
  command.add_option("--min-region-area", options.min_region_area,
                     "Drop candidates with a region smaller than this (m²; default: drop regions without a whole "
                     "triangle)");
  command.add_option("--patch-radius", options.patch_radius,
                     "Fingers as patches of this radius (metres) around the aim, the reference ICR library's "
                     "multi-point contacts: the best 3 x top candidates get patch regions (not with --conservative)");
  command.add_flag("--patch-all-points", options.patch_all_points,
                   "Keep every point of a patch (default: its centre and border points, as the reference library)");
  command.add_option("--seed", options.seed, "Seed of the candidate draws")->capture_default_str();
  command.add_option("--renders", options.renders, "Grasps drawn in the PNG next to the plan (0: no PNG)")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  command.add_option("-o,--output", options.output,
                     "plan.json; the regions of the best grasp go to the same name with .ply, the render with .png")
      ->required();
}

planning::PlanningParameters planningParameters(const PlanOptions& options) {
  planning::PlanningParameters p;
  p.finger_counts.clear();
  for (const std::string& text : split(options.fingers, ',')) {
    double value = 0;
    if (!parseNumber(text, value) || value != std::floor(value) || value < 2 || value > 16)
      throw InputError("--fingers", "", "expected finger counts 2..16 separated by commas, got '" + options.fingers + "'");
    p.finger_counts.push_back(static_cast<std::size_t>(value));
  }
  p.top = options.top;
  p.candidates = options.candidates;
  p.hulls = options.hulls;
  p.seed = options.seed;
  p.regions.contact_model = options.contact_model.model();
  p.regions.alpha = options.alpha;
  p.regions.tws_radius = options.tws_radius;
  p.regions.mode = options.mode == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
  p.regions.conservative = options.conservative.growth();
  p.task_margin = options.task_margin;
  p.placement.placement_error_m = options.placement_error;
  p.placement.samples = options.placement_samples;
  p.trust.rim_distance_m = options.rim_distance;
  p.trust.footprint_radius_m = options.footprint_radius;
  p.trust.max_normal_spread_rad = options.max_normal_spread;
  p.trust.max_normal_sigma_rad = options.max_normal_sigma;
  p.trust.max_spread_fraction = options.max_spread_fraction;
  p.min_region_area_m2 = options.min_region_area;
  if (options.patch_radius) {
    icr::PatchParameters patch;
    patch.radius_m = *options.patch_radius;
    patch.filter_border = !options.patch_all_points;
    p.patch = patch;
  } else if (options.patch_all_points) {
    throw InputError("--patch-all-points", "", "only with --patch-radius");
  }
  if (options.min_support > 0.0) p.trust.min_relative_support = options.min_support;
  else p.trust.min_relative_support.reset();
  if (options.min_flatness > 0.0) p.trust.min_relative_flatness = options.min_flatness;
  else p.trust.min_relative_flatness.reset();
  return p;
}

void mapPlanFields(CommandContext& context) {
  context.mapFields({{"PlanningParameters::finger_counts", "--fingers"},
                     {"PlanningParameters::top", "--top"},
                     {"PlanningParameters::candidates", "--candidates"},
                     {"PlanningParameters::hulls", "--hulls"},
                     {"PlanningParameters::task_margin", "--task-margin"},
                     {"PlanningParameters::patch", "--patch-radius"},
                     {"PatchParameters::radius_m", "--patch-radius"},
                     {"IcrParameters::alpha", "--alpha"},
                     {"IcrParameters::tws_radius", "--tws-radius"},
                     {"PlacementParameters::placement_error_m", "--placement-error"},
                     {"PlacementParameters::samples", "--placement-samples"},
                     {"ContactTrustParameters::rim_distance_m", "--rim-distance"},
                     {"ContactTrustParameters::footprint_radius_m", "--footprint-radius"},
                     {"ContactTrustParameters::max_normal_spread_rad", "--max-normal-spread"},
                     {"ContactTrustParameters::max_normal_sigma_rad", "--max-normal-sigma"},
                     {"ContactTrustParameters::min_relative_support", "--min-support"},
                     {"ContactTrustParameters::max_spread_fraction", "--max-spread-fraction"},
                     {"ContactTrustParameters::min_relative_flatness", "--min-flatness"},
                     {"PlanningParameters::min_region_area_m2", "--min-region-area"}});
}

}  // namespace icrkit::app
