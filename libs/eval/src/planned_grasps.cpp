#include <icrkit/eval/planned_grasps.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/icr/grasp_wrench_space.hpp>
#include <icrkit/planning/placement_score.hpp>

#include <nlohmann/json.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <sstream>
#include <iomanip>

namespace icrkit::eval {
namespace {

// One random stream per planned grasp and trial kind, whatever the thread
// count or the order grasps are executed in.
std::uint64_t streamSeed(std::uint64_t seed, std::size_t rank, std::uint64_t kind) {
  std::uint64_t z = seed * 0x9e3779b97f4a7c15ULL + rank * 0xbf58476d1ce4e5b9ULL + kind * 0x94d049bb133111ebULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The CAD vertices the fingers land on, or empty when one maps nowhere or
// two land on one vertex (a failure: no grasp a robot could make).
std::vector<int> landOnCad(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                           const ScanToCadMapping& to_cad) {
  std::vector<int> contacts;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const VertexImage image = to_cad.map(points[k], normals[k]);
    if (image.vertex < 0) return {};
    contacts.push_back(image.vertex);
  }
  const std::set<int> distinct(contacts.begin(), contacts.end());
  if (distinct.size() != contacts.size()) return {};
  return contacts;
}

double epsilonOnCad(const std::vector<int>& contacts, const icr::GraspableObject& cad, const icr::ContactModel& model) {
  if (contacts.empty()) return 0.0;
  const icr::GraspWrenchSpace gws = icr::graspWrenchSpace(cad, contacts, model);
  return gws.force_closure ? gws.epsilon : 0.0;
}

bool holdsOnCad(const std::vector<int>& contacts, double tws_radius, const icr::GraspableObject& cad,
                const icr::ContactModel& model) {
  if (contacts.empty()) return false;
  const double epsilon = epsilonOnCad(contacts, cad, model);
  return epsilon > 0.0 && epsilon >= tws_radius;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  double m = values[mid];
  if (values.size() % 2 == 0) m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + static_cast<long>(mid)));
  return m;
}

double fraction(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

}  // namespace

void PlannedExecutionParameters::validate() const {
  if (!(std::isfinite(placement_error_m) && placement_error_m >= 0.0))
    throw InputError("PlannedExecutionParameters::placement_error_m", "",
                     "expected a finite length >= 0 (metres), got " + std::to_string(placement_error_m));
}

double PlannedMeshStudy::aimedHeldFraction() const {
  std::size_t held = 0;
  for (const auto& g : grasps) held += g.aimed_held ? 1 : 0;
  return fraction(held, grasps.size());
}

double PlannedMeshStudy::picksHeldFraction() const {
  std::size_t held = 0, total = 0;
  for (const auto& g : grasps) held += g.picks_held, total += g.picks;
  return fraction(held, total);
}

double PlannedMeshStudy::placementsHeldFraction() const {
  std::size_t held = 0, total = 0;
  for (const auto& g : grasps) held += g.placements_held, total += g.placements;
  return fraction(held, total);
}

double PlannedMeshStudy::medianRegionAreaM2() const {
  std::vector<double> areas;
  for (const auto& g : grasps) areas.insert(areas.end(), g.region_areas_m2.begin(), g.region_areas_m2.end());
  return median(std::move(areas));
}

PlannedMeshStudy executePlanOnCad(const planning::PlanResult& plan, const icr::GraspableObject& scan,
                                  const ScanToCadMapping& to_cad, const icr::GraspableObject& cad,
                                  const icr::ContactModel& model, const PlannedExecutionParameters& params) {
  params.validate();
  PlannedMeshStudy study;
  study.grasps.resize(plan.grasps.size());
  const auto& positions = scan.mesh().vertices.positions;
  const auto& normals = scan.mesh().vertices.normals;
  tbb::parallel_for(std::size_t{0}, plan.grasps.size(), [&](std::size_t g) {
    const planning::PlannedGrasp& planned = plan.grasps[g];
    PlannedGraspExecution& out = study.grasps[g];
    out.rank = planned.rank;
    out.score = planned.score.probability;
    out.epsilon = planned.epsilon;
    const auto& regions = planned.regions.regions;
    const std::size_t fingers = regions.size();
    std::vector<Eigen::Vector3d> aim(fingers), aim_normal(fingers), t1(fingers), t2(fingers);
    bool complete = true;
    for (std::size_t n = 0; n < fingers; ++n) {
      out.region_areas_m2.push_back(regions[n].area_m2);
      const int v = regions[n].recommended.vertex;
      if (v < 0 || regions[n].vertices.empty()) {
        complete = false;
        continue;
      }
      aim[n] = positions[static_cast<std::size_t>(v)];
      aim_normal[n] = normals[static_cast<std::size_t>(v)].normalized();
      planning::tangentBasis(aim_normal[n], t1[n], t2[n]);
    }
    if (!complete) return;  // the planner never returns an empty region; nothing to execute
    const std::vector<int> aimed = landOnCad(aim, aim_normal, to_cad);
    out.aimed_epsilon = epsilonOnCad(aimed, cad, model);
    out.aimed_held = !aimed.empty() && out.aimed_epsilon > 0.0 && out.aimed_epsilon >= planned.tws_radius;

    std::mt19937_64 pick_random(streamSeed(params.seed, planned.rank, 1));
    std::vector<Eigen::Vector3d> points(fingers), point_normals(fingers);
    for (std::size_t t = 0; t < params.picks_per_grasp; ++t) {
      for (std::size_t n = 0; n < fingers; ++n) {
        const auto& vertices = regions[n].vertices;
        const std::size_t k = std::uniform_int_distribution<std::size_t>(0, vertices.size() - 1)(pick_random);
        const auto v = static_cast<std::size_t>(vertices[k]);
        points[n] = positions[v];
        point_normals[n] = normals[v];
      }
      const std::vector<int> landed = landOnCad(points, point_normals, to_cad);
      ++out.picks;
      if (landed.empty()) ++out.unmapped;
      else if (holdsOnCad(landed, planned.tws_radius, cad, model)) ++out.picks_held;
    }

    std::mt19937_64 place_random(streamSeed(params.seed, planned.rank, 2));
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (std::size_t t = 0; t < params.placement_samples; ++t) {
      for (std::size_t n = 0; n < fingers; ++n) {
        const double a = gauss(place_random) * params.placement_error_m;
        const double b = gauss(place_random) * params.placement_error_m;
        points[n] = aim[n] + a * t1[n] + b * t2[n];
      }
      // The finger approaches along the aimed contact's normal; eq. (3)
      // takes it to the true surface that faces it.
      const std::vector<int> landed = landOnCad(points, aim_normal, to_cad);
      ++out.placements;
      if (landed.empty()) ++out.unmapped;
      else if (holdsOnCad(landed, planned.tws_radius, cad, model)) ++out.placements_held;
    }
  });
  return study;
}

namespace {

nlohmann::json meshStudyJson(const PlannedMeshStudy& s) {
  nlohmann::json grasps = nlohmann::json::array();
  for (const auto& g : s.grasps)
    grasps.push_back({{"rank", g.rank},
                      {"score", g.score},
                      {"epsilon", g.epsilon},
                      {"region_areas_m2", g.region_areas_m2},
                      {"aimed_held", g.aimed_held},
                      {"aimed_epsilon", g.aimed_epsilon},
                      {"picks", g.picks},
                      {"picks_held", g.picks_held},
                      {"placements", g.placements},
                      {"placements_held", g.placements_held},
                      {"unmapped", g.unmapped}});
  // No timings: the file is part of the results, which merged shards
  // reproduce byte for byte.
  nlohmann::json j{{"mesh", s.mesh},
                   {"grasps", grasps},
                   {"aimed_held_fraction", s.aimedHeldFraction()},
                   {"picks_held_fraction", s.picksHeldFraction()},
                   {"placements_held_fraction", s.placementsHeldFraction()},
                   {"median_region_area_m2", s.medianRegionAreaM2()}};
  if (!s.error.empty()) j["error"] = s.error;
  return j;
}

std::string percent(double f) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << 100.0 * f;
  return out.str();
}

}  // namespace

planning::PlanningParameters randomBaselineParameters(const planning::PlanningParameters& planned, std::size_t count) {
  planning::PlanningParameters p = planned;
  p.trust.rim_distance_m = 0.0;
  p.trust.footprint_radius_m = 0.0;
  p.trust.max_normal_spread_rad = M_PI;
  p.trust.max_normal_sigma_rad.reset();
  p.trust.min_relative_support.reset();
  p.trust.min_relative_flatness.reset();
  p.task_margin = 0.0;
  p.regions.conservative.reset();
  // Every drawn candidate gets a hull and every one meeting the task is
  // kept: the first `count` draws that meet it, not the best of many.
  p.candidates = 4 * count;
  p.hulls = p.candidates;
  p.top = p.candidates;
  p.seed = planned.seed + 7919;
  return p;
}

void keepFirstDrawn(planning::PlanResult& plan, std::size_t count) {
  std::stable_sort(plan.grasps.begin(), plan.grasps.end(),
                   [](const planning::PlannedGrasp& a, const planning::PlannedGrasp& b) { return a.candidate < b.candidate; });
  if (plan.grasps.size() > count) plan.grasps.resize(count);
  for (std::size_t k = 0; k < plan.grasps.size(); ++k) plan.grasps[k].rank = k + 1;
}

std::string plannedGraspStudyJson(const PlannedGraspStudy& study) {
  const nlohmann::json j{{"dataset", study.dataset},
                         {"fingers", study.fingers},
                         {"tws_radius", study.tws_radius},
                         {"cad_grasps", study.cad_grasps},
                         {"raw", meshStudyJson(study.raw)},
                         {"filtered", meshStudyJson(study.filtered)},
                         {"raw_random", meshStudyJson(study.raw_random)},
                         {"filtered_random", meshStudyJson(study.filtered_random)}};
  return j.dump();
}

std::string plannedGraspStudiesMarkdown(const std::vector<std::string>& jsonl_lines) {
  std::ostringstream out;
  out << "| dataset | mesh | TWS radius | grasps | aimed held % | picks held % | placement held % | median region mm² "
         "|\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& line : jsonl_lines) {
    const nlohmann::json j = nlohmann::json::parse(line);
    for (const char* mesh : {"filtered", "filtered_random", "raw", "raw_random"}) {
      if (!j.contains(mesh)) continue;
      const nlohmann::json& m = j.at(mesh);
      out << "| " << j.at("dataset").get<std::string>() << " | " << mesh << " | " << std::setprecision(4)
          << j.at("tws_radius").get<double>() << " | ";
      if (m.contains("error")) {
        out << "0 | – | – | – | – |\n";
        continue;
      }
      out << m.at("grasps").size() << " | " << percent(m.at("aimed_held_fraction").get<double>()) << " | "
          << percent(m.at("picks_held_fraction").get<double>()) << " | "
          << percent(m.at("placements_held_fraction").get<double>()) << " | " << std::fixed << std::setprecision(0)
          << m.at("median_region_area_m2").get<double>() * 1e6 << std::defaultfloat << " |\n";
    }
  }
  return out.str();
}

}  // namespace icrkit::eval
