#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/icr/patch_contacts.hpp>
#include <icrkit/icr/search_zones.hpp>

#include "prototype_checks.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <sstream>
#include <string>
#include <unordered_set>

namespace icrkit::icr {
namespace {

using detail::Clock;

// Per grasp: the wrenches of each patch point, computed the first time a
// patch holding the point is tested, with a dense slot per computed point.
class PointWrenches {
public:
  PointWrenches(const GraspableObject& object, const ContactWrenches& generator)
      : object_(object), generator_(generator), per_point_(generator.perContact()), slot_(object.vertexCount(), -1) {}

  int slot(int point) {
    int& slot = slot_[static_cast<std::size_t>(point)];
    if (slot < 0) {
      slot = static_cast<int>(computed_++);
      pool_.resize(pool_.size() + 6 * per_point_);
      Eigen::Map<WrenchSet> out(pool_.data() + 6 * per_point_ * static_cast<std::size_t>(slot), 6,
                                static_cast<Eigen::Index>(per_point_));
      out = generator_.compute(object_.position(static_cast<std::size_t>(point)),
                               object_.normal(static_cast<std::size_t>(point)));
    }
    return slot;
  }
  // Column-major 6 x perPoint(); valid until the next new slot.
  const double* of(int slot) const { return pool_.data() + 6 * per_point_ * static_cast<std::size_t>(slot); }
  std::size_t perPoint() const { return per_point_; }
  std::size_t computed() const { return computed_; }

private:
  const GraspableObject& object_;
  const ContactWrenches& generator_;
  std::size_t per_point_;
  std::vector<int> slot_;
  std::vector<double> pool_;
  std::size_t computed_ = 0;
};

// Zone tests of patch candidates. A candidate holds a zone when one of its
// patch points does, and neighbouring candidates share most of their points,
// so each (finger, zone, point) answer is computed once per grasp and kept.
// ZoneTester sees a candidate as one flat wrench set and cannot share that
// work: with it (on each candidate's gathered patch wrenches) growth took
// about 3-4x as long on the 2.5k-vertex references, most of it
// re-proving zones held by the same points; a patch GWS has hundreds of
// facets per zone, and proving that a wrench holds a zone evaluates all of
// them. The test itself is ZoneTester's, with the same arithmetic: a wrench
// holds a zone when n . w - threshold >= 0 for each of the zone's facets.
// (Tried and dropped: skipping facets by a proven holder's margins, or by
// their clearance at the zone's hull vertex, as ZoneTester's neighbour
// evidence does: on these hulls the margins are too small to skip more than
// a third of the facets, and sorting them cost more than it saved.)
class PatchZoneTester {
public:
  PatchZoneTester(const SearchZones& zones, PointWrenches& wrenches) : wrenches_(wrenches) {
    for (FingerFacetRows& rows : fingerFacetRows(zones)) {
      Finger local;
      local.zone_order.resize(rows.zone_rows.size());
      for (std::size_t z = 0; z < local.zone_order.size(); ++z) local.zone_order[z] = z;
      local.rows = std::move(rows);
      fingers_.push_back(std::move(local));
    }
  }

  /// True when every zone of `finger` holds a wrench of some point of `patch`.
  bool qualifies(std::size_t finger, const std::vector<int>& patch) {
    Finger& local = fingers_[finger];
    const std::size_t zones = local.rows.zone_rows.size();
    slots_.clear();
    for (int point : patch) slots_.push_back(wrenches_.slot(point));
    local.known.resize(wrenches_.computed() * zones, kUnknown);
    // Zones are tried hardest first: the one that rejected the last
    // candidate moves to the front. Only the order changes, not the answer.
    for (std::size_t k = 0; k < zones; ++k) {
      const std::size_t zone = local.zone_order[k];
      // A point already proven to hold the zone first: proving another one
      // costs a pass over all of the zone's facets.
      bool held = std::any_of(slots_.begin(), slots_.end(), [&](int slot) {
        return local.known[static_cast<std::size_t>(slot) * zones + zone] == kHeld;
      });
      for (std::size_t i = 0; i < slots_.size() && !held; ++i) {
        std::uint8_t& known = local.known[static_cast<std::size_t>(slots_[i]) * zones + zone];
        if (known == kUnknown) {
          known = pointHolds(local, zone, slots_[i]) ? kHeld : kNotHeld;
          held = known == kHeld;
        }
      }
      if (!held) {
        if (k > 0) std::swap(local.zone_order[k], local.zone_order[0]);
        return false;
      }
    }
    return true;
  }

private:
  static constexpr std::uint8_t kUnknown = 0, kHeld = 1, kNotHeld = 2;
  struct Finger {
    FingerFacetRows rows;
    std::vector<std::size_t> zone_order;
    std::vector<std::uint8_t> known;  // per (point slot, zone): kUnknown, kHeld or kNotHeld
  };

  // Whether one of the point's wrenches holds the zone.
  bool pointHolds(Finger& local, std::size_t zone, int slot) {
    const double* point = wrenches_.of(slot);
    for (std::size_t column = 0; column < wrenches_.perPoint(); ++column)
      if (local.rows.holds(zone, point + 6 * column)) return true;
    return false;
  }

  PointWrenches& wrenches_;
  std::vector<Finger> fingers_;
  std::vector<int> slots_;
};

std::vector<int> growBreadthFirst(const GraspableObject& object, const ContactPatches& patches, int contact,
                                  std::size_t finger, PatchZoneTester& tester) {
  const VertexAdjacency& adjacency = object.adjacency();
  std::vector<std::uint8_t> visited(object.vertexCount(), 0);
  std::vector<int> region{contact};
  std::deque<int> queue{contact};
  visited[static_cast<std::size_t>(contact)] = 1;
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    for (const int* it = adjacency.begin(static_cast<std::size_t>(v)); it != adjacency.end(static_cast<std::size_t>(v)); ++it) {
      const int u = *it;
      if (visited[static_cast<std::size_t>(u)]) continue;
      visited[static_cast<std::size_t>(u)] = 1;
      // Neighbours share a face, so they are referenced: only the mask can bar them.
      if (object.excluded(static_cast<std::size_t>(u))) continue;
      if (!tester.qualifies(finger, patches.of(u))) continue;
      region.push_back(u);
      queue.push_back(u);
    }
  }
  std::sort(region.begin(), region.end());
  return region;
}

std::vector<int> testEveryVertex(const GraspableObject& object, const ContactPatches& patches, int contact,
                                 std::size_t finger, PatchZoneTester& tester) {
  std::vector<int> region;
  for (std::size_t v = 0; v < object.vertexCount(); ++v) {
    if (static_cast<int>(v) == contact) {
      region.push_back(contact);
      continue;
    }
    if (!object.eligible(v)) continue;
    if (tester.qualifies(finger, patches.of(static_cast<int>(v)))) region.push_back(static_cast<int>(v));
  }
  return region;
}

// Before any hull: the checks of every ICR entry point, plus the patch model's own.
void checkPatchPrototype(const GraspableObject& object, const ContactPatches& patches, const std::vector<int>& contacts,
                         const IcrParameters& params) {
  if (&patches.object().mesh() != &object.mesh())
    throw InputError("contact patches", "", "the patches were built on another mesh than the object's");
  detail::checkPrototype(object, contacts, params);
  // Its bound would have to cover every patch point's uncertainty: not derived yet.
  if (params.conservative)
    throw InputError("contact patches", "", "conservative growth is not available with patch contacts");
}

}  // namespace

void PatchParameters::validate() const {
  if (!std::isfinite(radius_m) || radius_m <= 0) {
    std::ostringstream detail;
    detail << "the patch radius must be a finite distance > 0 in metres, got " << radius_m;
    throw InputError("PatchParameters::radius_m", "", detail.str());
  }
}

std::vector<int> contactPatch(const GraspableObject& object, int centre, const PatchParameters& params) {
  const VertexAdjacency& adjacency = object.adjacency();
  const Eigen::Vector3d& c = object.position(static_cast<std::size_t>(centre));
  // The distance itself, not its square, against r: a vertex at exactly r
  // (inclusive) must not flip on the rounding of r * r.
  auto inside = [&](int v) { return (object.position(static_cast<std::size_t>(v)) - c).norm() <= params.radius_m; };

  std::vector<int> piece{centre};
  std::unordered_set<int> seen{centre};  // the piece and the outside vertices already looked at
  for (std::size_t head = 0; head < piece.size(); ++head) {
    const std::size_t v = static_cast<std::size_t>(piece[head]);
    for (const int* it = adjacency.begin(v); it != adjacency.end(v); ++it)
      if (seen.insert(*it).second && inside(*it)) piece.push_back(*it);
  }
  if (!params.filter_border) {
    std::sort(piece.begin(), piece.end());
    return piece;
  }
  std::vector<int> kept{centre};
  for (std::size_t k = 1; k < piece.size(); ++k) {
    const std::size_t v = static_cast<std::size_t>(piece[k]);
    // A neighbour within r would have been entered, so "not in the piece"
    // and "farther than r" are the same test.
    if (std::any_of(adjacency.begin(v), adjacency.end(v), [&](int u) { return !inside(u); }))
      kept.push_back(piece[k]);
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

ContactPatches::ContactPatches(const GraspableObject& object, const PatchParameters& params)
    : object_(&object),
      params_(params),
      once_(new std::once_flag[object.vertexCount()]),
      patches_(object.vertexCount()) {
  params_.validate();
}

const std::vector<int>& ContactPatches::of(int centre) const {
  if (centre < 0 || static_cast<std::size_t>(centre) >= patches_.size())
    throw InputError("contact patches", "vertex " + std::to_string(centre),
                     "expected a vertex index 0.." + std::to_string(static_cast<long>(patches_.size()) - 1));
  const std::size_t v = static_cast<std::size_t>(centre);
  // Each slot is written once, inside its own call_once, which orders the
  // write before every reader's return.
  std::call_once(once_[v], [&] {
    patches_[v] = build(centre);
    built_.fetch_add(1, std::memory_order_relaxed);
  });
  return patches_[v];
}

void ContactPatches::buildAll() const {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, patches_.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t v = range.begin(); v != range.end(); ++v) of(static_cast<int>(v));
                    });
}

std::vector<int> ContactPatches::build(int centre) const { return contactPatch(*object_, centre, params_); }

GraspWrenchSpace patchGraspWrenchSpace(const ContactPatches& patches, const std::vector<int>& contacts,
                                       const ContactModel& model, const HullParameters& hull,
                                       std::vector<int>* finger_of_wrench) {
  const GraspableObject& object = patches.object();
  const ContactWrenches generator(model, object.frame());
  const Eigen::Index per_point = static_cast<Eigen::Index>(generator.perContact());
  Eigen::Index total = 0;
  for (int c : contacts) total += per_point * static_cast<Eigen::Index>(patches.of(c).size());
  WrenchSet wrenches(6, total);
  if (finger_of_wrench) finger_of_wrench->assign(static_cast<std::size_t>(total), 0);
  Eigen::Index column = 0;
  for (std::size_t i = 0; i < contacts.size(); ++i)
    for (int point : patches.of(contacts[i])) {
      generator.compute(object.position(static_cast<std::size_t>(point)), object.normal(static_cast<std::size_t>(point)),
                        wrenches, column);
      if (finger_of_wrench) std::fill_n(finger_of_wrench->begin() + column, per_point, static_cast<int>(i));
      column += per_point;
    }
  return computeGraspWrenchSpace(wrenches, hull);
}

IcrResult computePatchContactRegions(const GraspableObject& object, const ContactPatches& patches,
                                     const std::vector<int>& contacts, const IcrParameters& params) {
  const auto start = Clock::now();
  checkPatchPrototype(object, patches, contacts, params);
  std::vector<int> finger_of_wrench;
  const GraspWrenchSpace gws =
      patchGraspWrenchSpace(patches, contacts, params.contact_model, params.hull, &finger_of_wrench);
  const double hull_ms = millisecondsSince(start);
  IcrResult result = computePatchContactRegions(object, patches, contacts, gws, finger_of_wrench, params);
  result.timings.hull_ms = hull_ms;
  result.timings.total_ms = millisecondsSince(start);
  return result;
}

IcrResult computePatchContactRegions(const GraspableObject& object, const ContactPatches& patches,
                                     const std::vector<int>& contacts, const GraspWrenchSpace& gws,
                                     const std::vector<int>& finger_of_wrench, const IcrParameters& params) {
  const auto start = Clock::now();
  checkPatchPrototype(object, patches, contacts, params);
  const ContactWrenches generator(params.contact_model, object.frame());
  // What patchGraspWrenchSpace makes of these contacts: one block of owners
  // per contact, of its patch's size times the wrenches per point. A hull
  // of other contacts or another contact model would give wrong regions.
  std::size_t expected = 0;
  for (int c : contacts) expected += patches.of(c).size() * generator.perContact();
  const bool owners_valid =
      finger_of_wrench.size() == expected &&
      std::all_of(finger_of_wrench.begin(), finger_of_wrench.end(),
                  [&](int f) { return f >= 0 && static_cast<std::size_t>(f) < contacts.size(); }) &&
      // hull_vertices is sorted: its last id is the largest wrench index.
      (gws.hull_vertices.empty() || static_cast<std::size_t>(gws.hull_vertices.back()) < expected);
  if (!owners_valid)
    throw InputError("contact patches", "",
                     "the prebuilt prototype GWS does not belong to these contacts' patches (expected " +
                         std::to_string(expected) + " wrench owners, got " + std::to_string(finger_of_wrench.size()) +
                         ")");

  IcrResult result;
  result.lambda_m = object.frame().lambda;
  if (!gws.force_closure) throw InputError("grasp", "", "the prototype grasp is not force closure: " + gws.reason);
  result.epsilon = gws.epsilon;
  result.gws_facets = gws.facetCount();

  auto phase = Clock::now();
  const TaskWrenchSpace tws = detail::taskWrenchSpaceFor(params, gws);
  result.tws_radius = tws.radius();
  const SearchZones zones = computeSearchZones(gws, tws, contacts.size(), finger_of_wrench);
  result.timings.zones_ms = millisecondsSince(phase);

  phase = Clock::now();
  PointWrenches wrenches(object, generator);
  PatchZoneTester tester(zones, wrenches);
  for (std::size_t finger = 0; finger < contacts.size(); ++finger) {
    ContactRegion region;
    region.finger = finger;
    region.contact = contacts[finger];
    region.vertices = params.mode == GrowthMode::BreadthFirst
                          ? growBreadthFirst(object, patches, contacts[finger], finger, tester)
                          : testEveryVertex(object, patches, contacts[finger], finger, tester);
    region.area_m2 = regionArea(object.mesh(), region.vertices);
    region.recommended = recommendedContact(object, region.vertices);
    result.regions.push_back(std::move(region));
  }
  result.vertices_tested = wrenches.computed();
  result.timings.growth_ms = millisecondsSince(phase);
  result.timings.total_ms = millisecondsSince(start);
  return result;
}

}  // namespace icrkit::icr
