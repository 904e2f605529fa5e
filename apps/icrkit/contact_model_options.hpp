#pragma once
// Options shared by the grasp commands (`icr`, `grasps`): the contact model
// and how the mesh is prepared (normals, exclusion mask, torque reference),
// so that both commands accept and report them identically.

#include "command_context.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/contact_model.hpp>
#include <icrkit/icr/wrench.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace icrkit::app {

struct ContactModelOptions {
  icr::ContactType type = icr::ContactType::Frictional;
  double mu = 0.8;
  double mu_t = 0.5;
  int edges = 8;

  /// --model, --mu, --mu-t, --edges.
  void addTo(CLI::App& command);
  /// The model, validated (InputError on a parameter out of range).
  icr::ContactModel model() const;
};

struct GraspMeshOptions {
  std::string path;
  bool compute_normals = false;
  std::string exclude_path;  ///< empty: the mesh's own `excluded` attribute, if any
  icr::TorqueReference torque_reference = icr::TorqueReference::Origin;

  /// The MESH positional and --compute-normals, --exclude, --torque-reference.
  void addTo(CLI::App& command);
};

struct GraspMesh {
  TriangleMesh mesh;
  std::vector<std::uint8_t> excluded;  ///< empty or one flag per vertex
  std::string exclusion_source;        ///< "none", "attribute" or the mask file
  bool normals_computed = false;
};

/// Reads the mesh and its exclusion mask. A mesh without vertex normals is an
/// InputError naming the file unless --compute-normals was given: normals
/// derived from faces are a guess the user should opt into.
GraspMesh loadGraspMesh(const GraspMeshOptions& options, CommandContext& context);

/// The same error prefixed with the mesh path, so that a library message
/// ("grasp: contact 2 is vertex ...") names the file it is about.
InputError namingMesh(const std::string& path, const InputError& error);

/// Number of non-zero flags.
std::size_t countExcluded(const std::vector<std::uint8_t>& mask);

/// What a summary says of the mesh a grasp command read: torque_reference,
/// normals ("computed" or "file"), exclusion, excluded_vertices, vertices,
/// unreferenced_vertices (`unreferenced`: vertices no face uses).
nlohmann::json graspMeshJson(const GraspMesh& input, const GraspMeshOptions& options, std::size_t unreferenced);

/// A CLI11 check for integers >= `minimum`.
CLI::Validator atLeast(long long minimum);

}  // namespace icrkit::app
