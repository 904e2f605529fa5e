#pragma once
// The flags of `icrkit icr` and the prototype grasp they give.

#include "conservative_options.hpp"
#include "contact_model_options.hpp"

#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/icr/patch_contacts.hpp>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace icrkit::app {

struct IcrOptions {
  GraspMeshOptions mesh;
  ContactModelOptions contact_model;
  std::string contacts;
  std::string contact_points;
  double alpha = 0.5;
  std::optional<double> tws_radius;
  icr::GrowthMode mode = icr::GrowthMode::BreadthFirst;
  ConservativeOptions conservative;
  std::optional<double> patch_radius;
  bool patch_all_points = false;
  std::string output;
};

/// Adds every flag of the command (the mesh and -o included) to `command`.
void addIcrOptions(CLI::App& command, IcrOptions& options);

/// --contacts "i,j,k": vertex indices; InputError naming the item otherwise.
std::vector<int> parseContactIndices(const std::string& text);

/// --contact-points "x,y,z;x,y,z": points in metres.
std::vector<Eigen::Vector3d> parseContactPoints(const std::string& text);

/// The regions' parameters the flags ask for.
icr::IcrParameters icrParameters(const IcrOptions& options);

/// The patch contacts --patch-radius asks for (checked: the library names
/// PatchParameters::radius_m), nothing without it; `params` are the regions'
/// (patches do not combine with conservative growth).
std::optional<icr::PatchParameters> patchParameters(const IcrOptions& options, const icr::IcrParameters& params);

}  // namespace icrkit::app
