#pragma once
// The flags of `icrkit plan` and the planner's parameters they give.

#include "conservative_options.hpp"
#include "contact_model_options.hpp"

#include <icrkit/planning/grasp_planner.hpp>

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace icrkit::app {

struct PlanOptions {
  GraspMeshOptions mesh;
  ContactModelOptions contact_model;
  std::string fingers = "4";
  std::size_t top = 10;
  std::size_t candidates = 1000;
  std::optional<std::size_t> hulls;
  double alpha = 0.5;
  std::optional<double> tws_radius;
  std::string mode = "bfs";
  ConservativeOptions conservative;
  double task_margin = 0.25;
  double placement_error = 0.003;
  std::size_t placement_samples = 128;
  double rim_distance = 0.004;
  double footprint_radius = 0.003;
  double max_normal_spread = 0.35;
  double max_normal_sigma = 0.25;
  double min_support = 1.0 / 3.0;
  double max_spread_fraction = 0.1;
  double min_flatness = 0.75;
  std::optional<double> min_region_area;
  std::optional<double> patch_radius;
  bool patch_all_points = false;
  std::uint64_t seed = 1;
  int renders = 3;
  std::string output;
};

/// Adds every flag of the command (the mesh and -o included) to `command`.
void addPlanOptions(CLI::App& command, PlanOptions& options);

/// The planner's parameters the flags ask for (InputError naming the flag
/// for a malformed --fingers; the library checks the rest).
planning::PlanningParameters planningParameters(const PlanOptions& options);

/// The library's fields and the flags that set them.
void mapPlanFields(CommandContext& context);

}  // namespace icrkit::app
