#include "icr_options.hpp"

#include "argument_parsing.hpp"

#include <cmath>
#include <string>

namespace icrkit::app {

std::vector<int> parseContactIndices(const std::string& text) {
  std::vector<int> contacts;
  const std::vector<std::string> parts = split(text, ',');
  for (std::size_t i = 0; i < parts.size(); ++i) {
    double value = 0.0;
    if (!parseNumber(parts[i], value) || value != std::floor(value) || std::abs(value) > 2e9)
      throw InputError("--contacts", "item " + std::to_string(i + 1),
                       "expected a vertex index, got '" + parts[i] + "'");
    contacts.push_back(static_cast<int>(value));
  }
  return contacts;
}

std::vector<Eigen::Vector3d> parseContactPoints(const std::string& text) {
  std::vector<Eigen::Vector3d> points;
  const std::vector<std::string> items = split(text, ';');
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::vector<std::string> coordinates = split(items[i], ',');
    Eigen::Vector3d p;
    bool ok = coordinates.size() == 3;
    for (std::size_t k = 0; ok && k < 3; ++k) ok = parseNumber(coordinates[k], p[static_cast<Eigen::Index>(k)]);
    if (!ok)
      throw InputError("--contact-points", "point " + std::to_string(i + 1),
                       "expected x,y,z in metres, got '" + items[i] + "'");
    points.push_back(p);
  }
  return points;
}

void addIcrOptions(CLI::App& command, IcrOptions& options) {
  options.mesh.addTo(command);
  auto* contacts = command.add_option("--contacts", options.contacts, "Prototype grasp: vertex indices i,j,k,...");
  auto* points = command.add_option("--contact-points", options.contact_points,
                                    "Prototype grasp as points \"x,y,z;x,y,z;...\" (metres), each snapped to the "
                                    "nearest vertex of a face");
  contacts->excludes(points);
  options.contact_model.addTo(command);
  auto* alpha =
      command
          .add_option("--alpha", options.alpha,
                      "TWS: an origin-centred ball of radius alpha * epsilon of the prototype, alpha in (0, 1]")
          ->check(CLI::Validator(
              [](std::string& value) -> std::string {
                double a = 0.0;
                if (!CLI::detail::lexical_cast(value, a) || !(a > 0.0 && a <= 1.0))
                  return "alpha must be in (0, 1], got " + value;
                return {};
              },
              "(0,1]"))
          ->capture_default_str();
  auto* radius = command
                     .add_option("--tws-radius", options.tws_radius,
                                 "TWS: an origin-centred ball of this absolute radius (instead of --alpha)")
                     ->check(CLI::PositiveNumber);
  alpha->excludes(radius);
  command
      .add_option_function<std::string>(
          "--mode",
          [&options](const std::string& name) {
            options.mode = name == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
          },
          "Region growth: bfs (over mesh neighbours from each contact) or full (test every vertex); default bfs")
      ->check(CLI::IsMember({"bfs", "full"}));
  options.conservative.addTo(command);
  command.add_option("--patch-radius", options.patch_radius,
                     "Multi-point (patch) contacts of the reference ICR library: each contact is the connected piece "
                     "of the mesh within this distance (metres) of its vertex, every point at full strength "
                     "(docs/icr.md: epsilon and regions then grow with the mesh density)");
  command.add_flag("--patch-all-points", options.patch_all_points,
                   "Keep every point of a patch (default: its centre and border points, as the reference library)");
  command.add_option("-o,--output", options.output, "Output .ply (the summary goes to the same name with .json)")
      ->required();
}

icr::IcrParameters icrParameters(const IcrOptions& options) {
  icr::IcrParameters params;
  params.contact_model = options.contact_model.model();
  params.alpha = options.alpha;
  params.tws_radius = options.tws_radius;
  params.mode = options.mode;
  params.conservative = options.conservative.growth();
  return params;
}

std::optional<icr::PatchParameters> patchParameters(const IcrOptions& options, const icr::IcrParameters& params) {
  if (!options.patch_radius) {
    if (options.patch_all_points) throw InputError("--patch-all-points", "", "only with --patch-radius");
    return std::nullopt;
  }
  icr::PatchParameters patch;
  patch.radius_m = *options.patch_radius;
  patch.filter_border = !options.patch_all_points;
  patch.validate();
  if (params.conservative)
    throw InputError("--patch-radius", "", "patch contacts cannot be combined with --conservative yet");
  return patch;
}

}  // namespace icrkit::app
