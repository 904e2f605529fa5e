#include "contact_model_options.hpp"

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <algorithm>
#include <map>
#include <sstream>

namespace icrkit::app {
namespace {

// The library's names, as CLI11 checks them.
const std::map<std::string, icr::ContactType> kContactTypes{
    {icr::contactTypeName(icr::ContactType::Frictional), icr::ContactType::Frictional},
    {icr::contactTypeName(icr::ContactType::Frictionless), icr::ContactType::Frictionless},
    {icr::contactTypeName(icr::ContactType::SoftFinger), icr::ContactType::SoftFinger}};

const std::map<std::string, icr::TorqueReference> kTorqueReferences{
    {icr::torqueReferenceName(icr::TorqueReference::Origin), icr::TorqueReference::Origin},
    {icr::torqueReferenceName(icr::TorqueReference::Centroid), icr::TorqueReference::Centroid}};

// One 0/1 per line; blank lines (e.g. a final newline) are ignored so that
// files written by common tools load.
std::vector<std::uint8_t> readExclusionMask(const std::string& path, std::size_t vertices) {
  std::istringstream in(io::readFileBytes(path));
  std::vector<std::uint8_t> mask;
  mask.reserve(vertices);
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const std::string value = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    if (value != "0" && value != "1")
      throw InputError(path, "line " + std::to_string(number), "expected 0 or 1, got '" + value + "'");
    mask.push_back(value == "1" ? 1 : 0);
  }
  if (mask.size() != vertices)
    throw InputError(path, "", "holds " + std::to_string(mask.size()) + " flags, expected one per vertex (" +
                                   std::to_string(vertices) + ")");
  return mask;
}

}  // namespace

void ContactModelOptions::addTo(CLI::App& command) {
  command
      .add_option_function<std::string>(
          "--model", [this](const std::string& name) { type = kContactTypes.at(name); },
          "Contact model: frictional, frictionless or soft (soft finger); default frictional")
      ->check(CLI::IsMember(kContactTypes));
  command.add_option("--mu", mu, "Coulomb friction coefficient")->check(CLI::PositiveNumber)->capture_default_str();
  command.add_option("--mu-t", mu_t, "Torsional friction coefficient of the soft finger (N m per N)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  command.add_option("--edges", edges, "Edges of the linearised friction cone")->check(atLeast(3))->capture_default_str();
}

icr::ContactModel ContactModelOptions::model() const {
  icr::ContactModel model;
  model.type = type;
  model.friction = mu;
  model.torsional_friction = mu_t;
  model.cone_edges = edges;
  model.validate();
  return model;
}

void GraspMeshOptions::addTo(CLI::App& command) {
  command.add_option("mesh", path, "Mesh with vertex normals (.ply nx/ny/nz, .obj vn)")->required();
  command.add_flag("--compute-normals", compute_normals,
                   "Derive vertex normals from the faces (orienting them outwards) instead of reading them");
  command.add_option("--exclude", exclude_path,
                     "Text file with one 0/1 per vertex (1 = never a contact); default: the mesh's `excluded` "
                     "vertex attribute when present");
  command
      .add_option_function<std::string>(
          "--torque-reference", [this](const std::string& name) { torque_reference = kTorqueReferences.at(name); },
          "Torque reference: origin (of the mesh frame) or centroid (of the vertices faces use); lambda is the "
          "farthest such vertex from it; default " +
          std::string(icr::torqueReferenceName(torque_reference)))
      ->check(CLI::IsMember(kTorqueReferences));
}

GraspMesh loadGraspMesh(const GraspMeshOptions& options, CommandContext& context) {
  GraspMesh out;
  out.mesh = io::readTriangleMesh(options.path);
  if (options.compute_normals) {
    if (out.mesh.faces.empty())
      throw InputError(options.path, "", "has no faces, so --compute-normals cannot derive vertex normals");
    const OrientationReport report = computeVertexNormals(out.mesh);
    out.normals_computed = true;
    if (report.flipped_faces > 0 || report.conflicting_edges > 0)
      context.note("icrkit: " + options.path + ": " + std::to_string(report.flipped_faces) + " faces flipped, " +
                   std::to_string(report.conflicting_edges) + " edges without a consistent winding");
  } else if (!out.mesh.vertices.hasNormals()) {
    throw InputError(options.path, "",
                     "has no vertex normals (OBJ vn or PLY nx/ny/nz), which ICRs need; pass --compute-normals to "
                     "derive them from the faces");
  }
  if (!options.exclude_path.empty()) {
    out.excluded = readExclusionMask(options.exclude_path, out.mesh.vertexCount());
    out.exclusion_source = options.exclude_path;
  } else {
    out.excluded = icr::exclusionMaskOf(out.mesh);
    out.exclusion_source = out.excluded.empty() ? "none" : "attribute";
  }
  return out;
}

InputError namingMesh(const std::string& path, const InputError& error) {
  if (error.source() == path) return error;
  return InputError(path, "", error.what());
}

std::size_t countExcluded(const std::vector<std::uint8_t>& mask) {
  return static_cast<std::size_t>(std::count_if(mask.begin(), mask.end(), [](std::uint8_t f) { return f != 0; }));
}

nlohmann::json graspMeshJson(const GraspMesh& input, const GraspMeshOptions& options, std::size_t unreferenced) {
  return {{"torque_reference", icr::torqueReferenceName(options.torque_reference)},
          {"normals", input.normals_computed ? "computed" : "file"},
          {"exclusion", input.exclusion_source},
          {"excluded_vertices", countExcluded(input.excluded)},
          {"vertices", input.mesh.vertexCount()},
          {"unreferenced_vertices", unreferenced}};
}

CLI::Validator atLeast(long long minimum) {
  return CLI::Validator(
      [minimum](std::string& value) -> std::string {
        long long parsed = 0;
        if (!CLI::detail::lexical_cast(value, parsed)) return "expected an integer, got " + value;
        if (parsed < minimum) return "must be at least " + std::to_string(minimum) + ", got " + value;
        return {};
      },
      ">=" + std::to_string(minimum));
}

}  // namespace icrkit::app
