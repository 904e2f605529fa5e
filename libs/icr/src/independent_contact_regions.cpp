#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>
#include <icrkit/icr/search_zones.hpp>

#include "prototype_checks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <string>

namespace icrkit::icr {
namespace {

using detail::Clock;

// The conservative test's pieces, shared by every vertex of one grasp.
struct ConservativeTest {
  const ContactModel& model;
  const UncertaintyBounds& bounds;
};

// The wrenches of each vertex (and, under conservative growth, the margin
// they must keep), computed the first time a finger tests it and kept for
// the other fingers.
class LazyVertexWrenches {
public:
  LazyVertexWrenches(const GraspableObject& object, const ContactWrenches& generator,
                     const ConservativeTest* conservative)
      : object_(object), generator_(generator), conservative_(conservative), slot_(object.vertexCount(), -1) {}

  const WrenchSet& of(int vertex) { return cache_[slotOf(vertex)]; }
  double required(int vertex) { return required_[slotOf(vertex)]; }
  std::size_t computed() const { return cache_.size(); }

private:
  std::size_t slotOf(int vertex) {
    const std::size_t v = static_cast<std::size_t>(vertex);
    int& slot = slot_[v];
    if (slot < 0) {
      slot = static_cast<int>(cache_.size());
      const double required =
          conservative_ ? wrenchUncertainty(conservative_->model, object_.frame(), object_.position(v),
                                            conservative_->bounds.angle(v), conservative_->bounds.offset(v))
                        : 0.0;
      cache_.push_back(generator_.compute(object_.position(v), object_.normal(v)));
      required_.push_back(required);
    }
    return static_cast<std::size_t>(slot);
  }

  const GraspableObject& object_;
  const ContactWrenches& generator_;
  const ConservativeTest* conservative_;
  std::vector<int> slot_;
  std::deque<WrenchSet> cache_;  // a deque: references stay valid as it grows
  std::vector<double> required_;
};

// `contact_always`: the prototype contact is in its region by definition
// (plain growth), or only when it qualifies (conservative growth).
std::vector<int> growBreadthFirst(const GraspableObject& object, int contact, std::size_t finger,
                                  LazyVertexWrenches& wrenches, ZoneTester& tester, bool contact_always) {
  const VertexAdjacency& adjacency = object.adjacency();
  std::vector<std::uint8_t> visited(object.vertexCount(), 0);
  std::vector<int> region;
  // Each queued vertex qualified; its evidence (which wrench held each zone,
  // with what slack) lets its neighbours skip most facet tests.
  const std::size_t zones = tester.zoneCount(finger);
  std::vector<Eigen::Index> evidence_wrench;
  std::vector<double> evidence_slack;
  long slots = 0;
  auto newEvidence = [&] {
    evidence_wrench.resize(evidence_wrench.size() + zones);
    evidence_slack.resize(evidence_slack.size() + zones);
    return slots++;
  };
  auto dropLastEvidence = [&] {
    evidence_wrench.resize(evidence_wrench.size() - zones);
    evidence_slack.resize(evidence_slack.size() - zones);
    --slots;
  };
  std::deque<std::pair<int, long>> queue;  // vertex, its evidence slot (-1: none)
  {
    // The contact is in its region by definition; it usually also passes
    // the test (its own wrenches are hull vertices), which gives evidence.
    const long slot = newEvidence();
    const bool passes = tester.qualifies(finger, wrenches.of(contact), nullptr,
                                         evidence_wrench.data() + slot * static_cast<long>(zones),
                                         evidence_slack.data() + slot * static_cast<long>(zones),
                                         wrenches.required(contact));
    if (!passes) dropLastEvidence();
    if (passes || contact_always) region.push_back(contact);
    // A contact that fails still seeds the search: its neighbours may keep the guarantee.
    queue.emplace_back(contact, passes ? slot : -1);
  }
  visited[static_cast<std::size_t>(contact)] = 1;
  while (!queue.empty()) {
    const auto [v, v_slot] = queue.front();
    queue.pop_front();
    for (const int* it = adjacency.begin(static_cast<std::size_t>(v)); it != adjacency.end(static_cast<std::size_t>(v)); ++it) {
      const int u = *it;
      if (visited[static_cast<std::size_t>(u)]) continue;
      visited[static_cast<std::size_t>(u)] = 1;
      // Neighbours share a face, so they are referenced: only the mask can bar them.
      if (object.excluded(static_cast<std::size_t>(u))) continue;
      const WrenchSet& u_wrenches = wrenches.of(u);
      const long slot = newEvidence();  // before taking pointers: the pools may grow
      ZoneTester::Evidence neighbour;
      if (v_slot >= 0) {
        neighbour.wrenches = &wrenches.of(v);
        neighbour.wrench = evidence_wrench.data() + v_slot * static_cast<long>(zones);
        neighbour.slack = evidence_slack.data() + v_slot * static_cast<long>(zones);
      }
      if (!tester.qualifies(finger, u_wrenches, v_slot >= 0 ? &neighbour : nullptr,
                            evidence_wrench.data() + slot * static_cast<long>(zones),
                            evidence_slack.data() + slot * static_cast<long>(zones), wrenches.required(u))) {
        dropLastEvidence();  // the newest slot: nobody refers to it
        continue;
      }
      region.push_back(u);
      queue.emplace_back(u, slot);
    }
  }
  std::sort(region.begin(), region.end());
  return region;
}

std::vector<int> testEveryVertex(const GraspableObject& object, int contact, std::size_t finger,
                                 LazyVertexWrenches& wrenches, ZoneTester& tester, bool contact_always) {
  std::vector<int> region;
  for (std::size_t v = 0; v < object.vertexCount(); ++v) {
    const int vertex = static_cast<int>(v);
    if (vertex == contact && contact_always) {
      region.push_back(contact);
      continue;
    }
    if (!object.eligible(v)) continue;
    if (tester.qualifies(finger, wrenches.of(vertex), wrenches.required(vertex))) region.push_back(vertex);
  }
  return region;
}

}  // namespace

GraspWrenchSpace graspWrenchSpace(const GraspableObject& object, const std::vector<int>& contacts,
                                  const ContactModel& model, const HullParameters& hull) {
  const ContactWrenches generator(model, object.frame());
  const Eigen::Index per_contact = static_cast<Eigen::Index>(generator.perContact());
  WrenchSet wrenches(6, per_contact * static_cast<Eigen::Index>(contacts.size()));
  for (std::size_t i = 0; i < contacts.size(); ++i)
    generator.compute(object.position(static_cast<std::size_t>(contacts[i])),
                      object.normal(static_cast<std::size_t>(contacts[i])), wrenches,
                      per_contact * static_cast<Eigen::Index>(i));
  return computeGraspWrenchSpace(wrenches, hull);
}

IcrResult computeIndependentContactRegions(const GraspableObject& object, const std::vector<int>& contacts,
                                           const IcrParameters& params) {
  const auto start = Clock::now();
  detail::checkPrototype(object, contacts, params);
  const GraspWrenchSpace gws = graspWrenchSpace(object, contacts, params.contact_model, params.hull);
  const double hull_ms = millisecondsSince(start);
  IcrResult result = computeIndependentContactRegions(object, contacts, gws, params);
  result.timings.hull_ms = hull_ms;
  result.timings.total_ms = millisecondsSince(start);
  return result;
}

IcrResult computeIndependentContactRegions(const GraspableObject& object, const std::vector<int>& contacts,
                                           const GraspWrenchSpace& gws, const IcrParameters& params) {
  const auto start = Clock::now();
  detail::checkPrototype(object, contacts, params);

  IcrResult result;
  result.lambda_m = object.frame().lambda;
  const ContactWrenches generator(params.contact_model, object.frame());
  if (gws.force_closure && !gws.hull_vertices.empty() &&
      static_cast<std::size_t>(gws.hull_vertices.back()) >= contacts.size() * generator.perContact())
    throw InputError("grasp", "", "the given GWS was built from more wrenches than these contacts have");

  auto phase = Clock::now();
  if (!gws.force_closure) throw InputError("grasp", "", "the prototype grasp is not force closure: " + gws.reason);
  result.epsilon = gws.epsilon;
  result.gws_facets = gws.facetCount();

  phase = Clock::now();
  const TaskWrenchSpace tws = detail::taskWrenchSpaceFor(params, gws);
  result.tws_radius = tws.radius();
  const SearchZones zones = computeSearchZones(gws, tws, contacts.size(), generator.perContact());
  result.timings.zones_ms = millisecondsSince(phase);

  phase = Clock::now();
  std::optional<UncertaintyBounds> bounds;
  std::optional<ConservativeTest> conservative;
  if (params.conservative) {
    bounds.emplace(object.mesh(), *params.conservative);
    conservative.emplace(ConservativeTest{params.contact_model, *bounds});
  }
  const bool contact_always = !params.conservative;
  LazyVertexWrenches wrenches(object, generator, conservative ? &*conservative : nullptr);
  ZoneTester tester(zones);
  for (std::size_t finger = 0; finger < contacts.size(); ++finger) {
    ContactRegion region;
    region.finger = finger;
    region.contact = contacts[finger];
    region.vertices = params.mode == GrowthMode::BreadthFirst
                          ? growBreadthFirst(object, contacts[finger], finger, wrenches, tester, contact_always)
                          : testEveryVertex(object, contacts[finger], finger, wrenches, tester, contact_always);
    region.area_m2 = regionArea(object.mesh(), region.vertices);
    region.recommended = recommendedContact(object, region.vertices);
    result.regions.push_back(std::move(region));
  }
  result.vertices_tested = wrenches.computed();
  result.timings.growth_ms = millisecondsSince(phase);
  result.timings.total_ms = millisecondsSince(start);
  return result;
}

double regionArea(const TriangleMesh& mesh, const std::vector<int>& region) {
  std::vector<std::uint8_t> member(mesh.vertexCount(), 0);
  for (int v : region) member[static_cast<std::size_t>(v)] = 1;
  const auto& p = mesh.vertices.positions;
  double area = 0.0;
  for (const Triangle& f : mesh.faces)
    if (member[f[0]] && member[f[1]] && member[f[2]]) area += 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
  return area;
}

}  // namespace icrkit::icr
