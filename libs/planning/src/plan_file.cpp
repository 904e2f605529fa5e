#include <icrkit/planning/plan_file.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace icrkit::planning {
namespace {

nlohmann::json vector3(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

class PlanReader {
public:
  PlanReader(std::string source, std::size_t vertex_count) : source_(std::move(source)), vertex_count_(vertex_count) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const { throw InputError(source_, where, what); }

  const nlohmann::json& member(const nlohmann::json& object, const char* key, const std::string& where) const {
    if (!object.is_object()) fail(where, "expected a JSON object");
    const auto it = object.find(key);
    if (it == object.end()) fail(where, std::string("missing \"") + key + "\"");
    return *it;
  }
  double number(const nlohmann::json& object, const char* key, const std::string& where) const {
    const nlohmann::json& v = member(object, key, where);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      fail(where + "." + key, "expected a finite number");
    return v.get<double>();
  }
  std::size_t count(const nlohmann::json& object, const char* key, const std::string& where) const {
    const nlohmann::json& v = member(object, key, where);
    if (!v.is_number_unsigned()) fail(where + "." + key, "expected a non-negative integer");
    return v.get<std::size_t>();
  }
  int vertex(const nlohmann::json& v, const std::string& where) const {
    if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 2000000000LL)
      fail(where, "expected a vertex id (integer >= 0)");
    const long long id = v.get<long long>();
    if (vertex_count_ > 0 && static_cast<std::size_t>(id) >= vertex_count_)
      fail(where, "vertex " + std::to_string(id) + " is out of range: the mesh has " + std::to_string(vertex_count_) +
                      " vertices");
    return static_cast<int>(id);
  }
  Eigen::Vector3d point(const nlohmann::json& object, const char* key, const std::string& where) const {
    const nlohmann::json& v = member(object, key, where);
    if (!v.is_array() || v.size() != 3) fail(where + "." + key, "expected [x, y, z]");
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) {
      if (!v[static_cast<std::size_t>(i)].is_number() || !std::isfinite(v[static_cast<std::size_t>(i)].get<double>()))
        fail(where + "." + key + "[" + std::to_string(i) + "]", "expected a finite number");
      p[i] = v[static_cast<std::size_t>(i)].get<double>();
    }
    return p;
  }

private:
  std::string source_;
  std::size_t vertex_count_;
};

}  // namespace

std::string planJson(const std::string& mesh_path, const icr::GraspableObject& object, const icr::ContactModel& model,
                     const PlanResult& result, const std::string& extra) {
  nlohmann::json grasps = nlohmann::json::array();
  for (const PlannedGrasp& g : result.grasps) {
    nlohmann::json regions = nlohmann::json::array();
    for (std::size_t n = 0; n < g.regions.regions.size(); ++n) {
      const icr::ContactRegion& r = g.regions.regions[n];
      nlohmann::json recommended{{"vertex", r.recommended.vertex}, {"depth_m", r.recommended.depth_m}};
      if (r.recommended.vertex >= 0) {
        const auto v = static_cast<std::size_t>(r.recommended.vertex);
        recommended["position"] = vector3(object.position(v));
        recommended["normal"] = vector3(object.normal(v));
      }
      regions.push_back({{"finger", r.finger},
                         {"contact", r.contact},
                         {"vertices", r.vertices},
                         {"area_m2", r.area_m2},
                         {"landing_probability", g.score.finger_probability[n]},
                         {"recommended", recommended}});
    }
    grasps.push_back({{"rank", g.rank},
                      {"fingers", g.fingers},
                      {"candidate", g.candidate},
                      {"contacts", g.contacts},
                      {"epsilon", g.epsilon},
                      {"tws_radius", g.tws_radius},
                      {"growth_tws_radius", g.growth_tws_radius},
                      {"score", g.score.probability},
                      {"min_depth_m", g.score.min_depth_m},
                      {"regions", regions}});
  }
  nlohmann::json plan{{"mesh", mesh_path},
                      {"model", nlohmann::json::parse(icr::contactModelJson(model))},
                      {"torque_reference_m", vector3(object.frame().reference_point)},
                      {"lambda_m", object.frame().lambda},
                      {"grasps", grasps}};
  // The executor's spelling of the friction model, whatever the type.
  plan["model"]["mu_t"] = model.torsional_friction;
  plan["model"]["mu"] = model.friction;
  plan["model"]["edges"] = model.cone_edges;
  // The regions' contact model: a finger is a patch of this radius around
  // the aim (docs/planning.md), or a point.
  plan["patch"] = result.patch ? nlohmann::json{{"radius_m", result.patch->radius_m},
                                                {"filter_border", result.patch->filter_border}}
                               : nlohmann::json(nullptr);
  if (!extra.empty()) plan.update(nlohmann::json::parse(extra));
  return plan.dump();
}

StoredPlan parsePlanJson(const std::string& text, const std::string& source, std::size_t vertex_count) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(source, "byte " + std::to_string(e.byte), "not valid JSON");
  } catch (const nlohmann::json::exception& e) {  // a number out of range (1e999)
    throw InputError(source, "", std::string("not valid JSON: ") + e.what());
  }
  const PlanReader read(source, vertex_count);
  StoredPlan plan;
  const nlohmann::json& mesh = read.member(doc, "mesh", "plan");
  if (!mesh.is_string()) read.fail("mesh", "expected the mesh path as a string");
  plan.mesh = mesh.get<std::string>();
  const nlohmann::json& model = read.member(doc, "model", "plan");
  const nlohmann::json& type = read.member(model, "type", "model");
  if (!type.is_string()) read.fail("model.type", "expected frictional, frictionless or soft");
  try {
    plan.model.type = icr::parseContactType(type.get<std::string>());
  } catch (const InputError& e) {
    read.fail("model.type", e.detail());
  }
  if (plan.model.type != icr::ContactType::Frictionless) {
    plan.model.friction = read.number(model, "mu", "model");
    plan.model.cone_edges = static_cast<int>(read.count(model, "edges", "model"));
  }
  if (plan.model.type == icr::ContactType::SoftFinger) plan.model.torsional_friction = read.number(model, "mu_t", "model");
  try {
    plan.model.validate();
  } catch (const InputError& e) {
    read.fail("model", e.detail());
  }
  plan.frame.reference_point = read.point(doc, "torque_reference_m", "plan");
  plan.frame.lambda = read.number(doc, "lambda_m", "plan");
  if (!(plan.frame.lambda > 0.0)) read.fail("lambda_m", "expected a length > 0");
  const nlohmann::json& grasps = read.member(doc, "grasps", "plan");
  if (!grasps.is_array()) read.fail("grasps", "expected an array");
  for (std::size_t g = 0; g < grasps.size(); ++g) {
    const std::string where = "grasps[" + std::to_string(g) + "]";
    StoredPlanGrasp grasp;
    grasp.rank = read.count(grasps[g], "rank", where);
    grasp.tws_radius = read.number(grasps[g], "tws_radius", where);
    grasp.score = read.number(grasps[g], "score", where);
    const nlohmann::json& regions = read.member(grasps[g], "regions", where);
    if (!regions.is_array() || regions.size() < 2) read.fail(where + ".regions", "expected an array of at least 2 regions");
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const std::string at = where + ".regions[" + std::to_string(r) + "]";
      StoredPlanRegion region;
      region.finger = read.count(regions[r], "finger", at);
      region.area_m2 = read.number(regions[r], "area_m2", at);
      const nlohmann::json& vertices = read.member(regions[r], "vertices", at);
      if (!vertices.is_array()) read.fail(at + ".vertices", "expected an array of vertex ids");
      for (std::size_t k = 0; k < vertices.size(); ++k)
        region.vertices.push_back(read.vertex(vertices[k], at + ".vertices[" + std::to_string(k) + "]"));
      const nlohmann::json& recommended = read.member(regions[r], "recommended", at);
      region.recommended = read.vertex(read.member(recommended, "vertex", at + ".recommended"), at + ".recommended.vertex");
      region.position = read.point(recommended, "position", at + ".recommended");
      region.normal = read.point(recommended, "normal", at + ".recommended");
      grasp.regions.push_back(std::move(region));
    }
    plan.grasps.push_back(std::move(grasp));
  }
  return plan;
}

StoredPlan readPlanFile(const std::string& path, std::size_t vertex_count) {
  return parsePlanJson(io::readFileBytes(path), path, vertex_count);
}

}  // namespace icrkit::planning
