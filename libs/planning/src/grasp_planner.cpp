#include <icrkit/planning/grasp_planner.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/wrench.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

namespace icrkit::planning {
namespace {

using Clock = std::chrono::steady_clock;

// splitmix64: one independent stream per (seed, finger count, candidate),
// so a candidate's contacts never depend on which thread drew it.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Fixed unit directions of wrench space: the coordinate axes both ways and
// quasi-random others. A hull holding the ball of radius epsilon reaches at
// least epsilon along every direction, so the smallest support along these
// bounds epsilon from above without a hull.
Eigen::Matrix<double, Eigen::Dynamic, 6> boundDirections() {
  constexpr int kRandom = 52;
  Eigen::Matrix<double, Eigen::Dynamic, 6> d(12 + kRandom, 6);
  d.setZero();
  for (int i = 0; i < 6; ++i) {
    d(2 * i, i) = 1.0;
    d(2 * i + 1, i) = -1.0;
  }
  std::mt19937_64 random(0xd1ecULL);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  for (int r = 12; r < d.rows(); ++r) {
    for (int c = 0; c < 6; ++c) d(r, c) = gaussian(random);
    d.row(r).normalize();
  }
  return d;
}

struct Candidate {
  std::vector<int> contacts;
  bool precheck = false;
  double bound = 0.0;  // upper bound on epsilon
};

struct Scored {
  PlannedGrasp grasp;
  bool ok = false;
  bool force_closure = false;
  bool small_region = false;  // met the task, but a region is below the minimum area
};

// Every finger has somewhere to go: a region with at least `min_area`
// (unset: with a whole triangle).
bool usableRegions(const icr::IcrResult& result, const std::optional<double>& min_area) {
  return std::none_of(result.regions.begin(), result.regions.end(), [&](const icr::ContactRegion& r) {
    return r.vertices.empty() || (min_area ? r.area_m2 < *min_area : !(r.area_m2 > 0.0));
  });
}

bool better(const PlannedGrasp& a, const PlannedGrasp& b) {
  if (a.score.probability != b.score.probability) return a.score.probability > b.score.probability;
  if (a.score.min_depth_m != b.score.min_depth_m) return a.score.min_depth_m > b.score.min_depth_m;
  if (a.epsilon != b.epsilon) return a.epsilon > b.epsilon;
  if (a.fingers != b.fingers) return a.fingers < b.fingers;
  return a.candidate < b.candidate;
}

}  // namespace

void PlanningParameters::validate() const {
  if (finger_counts.empty()) throw InputError("PlanningParameters::finger_counts", "", "expected at least one finger count");
  for (std::size_t f : finger_counts)
    if (f < 2 || f > 16)
      throw InputError("PlanningParameters::finger_counts", "", "expected finger counts in 2..16, got " + std::to_string(f));
  if (top < 1) throw InputError("PlanningParameters::top", "", "expected at least 1 grasp to return, got 0");
  if (candidates < 1) throw InputError("PlanningParameters::candidates", "", "expected at least 1 candidate");
  if (hulls && *hulls < 1) throw InputError("PlanningParameters::hulls", "", "expected at least 1 hull");
  if (min_region_area_m2 && !(std::isfinite(*min_region_area_m2) && *min_region_area_m2 >= 0.0))
    throw InputError("PlanningParameters::min_region_area_m2", "",
                     "expected a finite area >= 0 (m²), got " + std::to_string(*min_region_area_m2));
  if (!(std::isfinite(task_margin) && task_margin >= 0.0))
    throw InputError("PlanningParameters::task_margin", "", "expected a finite margin >= 0, got " + std::to_string(task_margin));
  if (regions.tws_wrenches)
    throw InputError("IcrParameters::tws_wrenches", "", "the planner takes a ball task (alpha or tws_radius), not a polytope");
  if (regions.tws_radius) {
    if (!(std::isfinite(*regions.tws_radius) && *regions.tws_radius > 0.0))
      throw InputError("IcrParameters::tws_radius", "", "expected a finite radius > 0, got " + std::to_string(*regions.tws_radius));
  } else {
    if (!(regions.alpha > 0.0 && regions.alpha <= 1.0))
      throw InputError("IcrParameters::alpha", "", "expected alpha in (0, 1], got " + std::to_string(regions.alpha));
    if (regions.alpha * (1.0 + task_margin) > 1.0)
      throw InputError("PlanningParameters::task_margin", "",
                       "alpha x (1 + margin) = " + std::to_string(regions.alpha * (1.0 + task_margin)) +
                           " exceeds 1: no grasp can hold its own task with that margin");
  }
  regions.contact_model.validate();
  if (regions.conservative) regions.conservative->validate();
  if (patch) {
    patch->validate();
    if (regions.conservative)
      throw InputError("PlanningParameters::patch", "", "patch contacts cannot be combined with conservative growth yet");
  }
  trust.validate();
  placement.validate();
}

PlanResult planGrasps(const icr::GraspableObject& object, const PlanningParameters& params,
                      const ProgressCallback& progress) {
  const auto start = Clock::now();
  params.validate();
  PlanResult result;
  PlanReport& report = result.report;

  auto phase = Clock::now();
  const ContactTrust trust = assessContactTrust(object.mesh(), object.exclusionMask(), params.trust);
  report.trust = trust.report;
  const icr::GraspableObject trusted(object.mesh(), object.frame(), trust.untrusted);
  std::vector<int> eligible;
  for (std::size_t v = 0; v < trusted.vertexCount(); ++v)
    if (trusted.eligible(v)) eligible.push_back(static_cast<int>(v));
  const std::optional<double> min_area = params.min_region_area_m2;
  const PlacementScorer scorer(trusted, params.placement);
  report.trust_ms = millisecondsSince(phase);

  const icr::ContactWrenches generator(params.regions.contact_model, object.frame());
  const auto per_contact = static_cast<Eigen::Index>(generator.perContact());
  const Eigen::Matrix<double, Eigen::Dynamic, 6> directions = boundDirections();
  const double margin = 1.0 + params.task_margin;
  // The task with its margin, known before any hull for an absolute task.
  const double absolute_need = params.regions.tws_radius ? *params.regions.tws_radius * margin : 0.0;
  const std::size_t total = params.candidates * params.finger_counts.size();
  std::size_t done = 0;

  std::vector<PlannedGrasp> scored;
  double best_epsilon = -std::numeric_limits<double>::infinity();
  std::size_t force_closure_total = 0;
  for (std::size_t fingers : params.finger_counts) {
    FingerCountReport fc;
    fc.fingers = fingers;
    if (eligible.size() < fingers)
      throw InputError("mesh", "",
                       std::to_string(fingers) + " fingers need as many trusted vertices, but only " +
                           std::to_string(eligible.size()) + " of " + std::to_string(report.trust.vertices) +
                           " are trusted (" + std::to_string(report.trust.excluded) + " excluded, " +
                           std::to_string(report.trust.near_rim) + " near the rim, " +
                           std::to_string(report.trust.normal_spread) + " under disagreeing normals, " +
                           std::to_string(report.trust.normal_sigma) + " with a large normal_sigma, " +
                           std::to_string(report.trust.weak_support) + " on thinly supported surface, " +
                           std::to_string(report.trust.low_flatness) + " on rounded features)");
    const auto columns = per_contact * static_cast<Eigen::Index>(fingers);

    // 1. Draw and screen without hulls.
    phase = Clock::now();
    std::vector<Candidate> candidates(params.candidates);
    const std::uint64_t stream = mix(params.seed ^ mix(fingers));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        icr::WrenchSet wrenches(6, columns);
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          Candidate& c = candidates[i];
                          std::uint64_t state = mix(stream + i);
                          while (c.contacts.size() < fingers) {
                            state = mix(state);
                            const int v = eligible[state % eligible.size()];
                            if (std::find(c.contacts.begin(), c.contacts.end(), v) == c.contacts.end())
                              c.contacts.push_back(v);
                          }
                          for (std::size_t f = 0; f < fingers; ++f) {
                            const auto v = static_cast<std::size_t>(c.contacts[f]);
                            generator.compute(trusted.position(v), trusted.normal(v), wrenches,
                                              per_contact * static_cast<Eigen::Index>(f));
                          }
                          c.precheck = icr::mayBeForceClosure(wrenches);
                          if (c.precheck) c.bound = (directions * wrenches).rowwise().maxCoeff().minCoeff();
                        }
                      });
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (!candidates[i].precheck) {
        ++fc.rejected_by_precheck;
      } else if (candidates[i].bound < absolute_need) {
        ++fc.rejected_by_bound;
      } else {
        order.push_back(i);
      }
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return candidates[a].bound > candidates[b].bound; });
    const std::size_t hulls =
        std::min(order.size(), params.hulls ? *params.hulls : std::max<std::size_t>(20 * params.top, 64));
    order.resize(hulls);
    fc.drawn = candidates.size();
    report.screening_ms += millisecondsSince(phase);

    // 2. Hulls, the task, regions and scores of the most promising.
    phase = Clock::now();
    std::vector<Scored> results(order.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        const Candidate& c = candidates[order[k]];
        Scored& s = results[k];
        const icr::GraspWrenchSpace gws =
            icr::graspWrenchSpace(trusted, c.contacts, params.regions.contact_model, params.regions.hull);
        s.grasp.epsilon = gws.epsilon;
        s.force_closure = gws.force_closure;
        if (!gws.force_closure) continue;
        const double task = params.regions.tws_radius ? *params.regions.tws_radius : params.regions.alpha * gws.epsilon;
        const double need = task * margin;
        if (gws.epsilon < need) continue;
        icr::IcrParameters growth = params.regions;
        growth.tws_radius = need;
        s.grasp.regions = icr::computeIndependentContactRegions(trusted, c.contacts, gws, growth);
        // Conservative growth can leave a region empty: nowhere to aim that finger.
        if (!usableRegions(s.grasp.regions, min_area)) {
          s.small_region = true;
          continue;
        }
        s.grasp.fingers = fingers;
        s.grasp.candidate = order[k];
        s.grasp.contacts = c.contacts;
        s.grasp.tws_radius = task;
        s.grasp.growth_tws_radius = need;
        s.grasp.score = scorer.score(s.grasp.regions);
        s.ok = true;
      }
    });
    fc.hulls_built = results.size();
    for (Scored& s : results) {
      if (!s.force_closure) {
        ++fc.not_force_closure;
        continue;
      }
      ++force_closure_total;
      best_epsilon = std::max(best_epsilon, s.grasp.epsilon);
      if (s.small_region) {
        ++fc.small_regions;
        continue;
      }
      if (!s.ok) {
        ++fc.below_task;
        continue;
      }
      ++fc.with_regions;
      scored.push_back(std::move(s.grasp));
    }
    report.regions_ms += millisecondsSince(phase);
    report.finger_counts.push_back(fc);
    done += params.candidates;
    if (progress) progress("candidates", done, total);
  }

  if (force_closure_total == 0 && std::all_of(report.finger_counts.begin(), report.finger_counts.end(),
                                              [](const FingerCountReport& f) { return f.rejected_by_bound == 0; }))
    throw InputError("grasp planning", "",
                     "no force-closure grasp among " + std::to_string(total) + " candidates drawn from " +
                         std::to_string(eligible.size()) + " trusted vertices; try more --candidates");
  if (scored.empty()) {
    std::size_t small_total = 0;
    for (const FingerCountReport& f : report.finger_counts) small_total += f.small_regions;
    const std::string small =
        small_total == 0 ? std::string()
                         : "; " + std::to_string(small_total) + " met it with a region of " +
                               (min_area ? "less than " + std::to_string(*min_area * 1e6) + " mm²" : std::string("no area")) +
                               " (--min-region-area)";
    const std::string need = params.regions.tws_radius ? std::to_string(absolute_need)
                                                       : "alpha x (1 + margin) of its epsilon";
    throw InputError("grasp planning", "",
                     "no candidate meets the task: " + std::to_string(total) + " candidates tried, " +
                         std::to_string(force_closure_total) + " force closure, largest epsilon " +
                         (force_closure_total ? std::to_string(best_epsilon) : std::string("none")) +
                         ", the task with its margin needs " + need + small);
  }
  std::sort(scored.begin(), scored.end(), better);
  if (params.patch) {
    // Patch fingers for the best few only: their regions grown again from
    // the patch hull, for the same task, and scored again.
    phase = Clock::now();
    const icr::ContactPatches patches(trusted, *params.patch);
    if (scored.size() > 3 * params.top) scored.resize(3 * params.top);
    std::vector<std::uint8_t> kept(scored.size(), 0);
    tbb::parallel_for(std::size_t{0}, scored.size(), [&](std::size_t k) {
      PlannedGrasp& g = scored[k];
      icr::IcrParameters growth = params.regions;
      growth.tws_radius = g.growth_tws_radius;
      try {
        icr::IcrResult regions = icr::computePatchContactRegions(trusted, patches, g.contacts, growth);
        if (!usableRegions(regions, min_area)) return;
        g.regions = std::move(regions);
        g.score = scorer.score(g.regions);
        kept[k] = 1;
      } catch (const InputError&) {
        // The patch grasp does not reach the task (patches on a thin
        // feature can cancel): the next candidate takes its place.
      }
    });
    std::vector<PlannedGrasp> patched;
    for (std::size_t k = 0; k < scored.size(); ++k)
      if (kept[k]) patched.push_back(std::move(scored[k]));
    if (patched.empty())
      throw InputError("grasp planning", "",
                       "none of the best " + std::to_string(scored.size()) +
                           " candidates meets the task with patch contacts of radius " +
                           std::to_string(params.patch->radius_m) + " m");
    scored = std::move(patched);
    std::sort(scored.begin(), scored.end(), better);
    result.patch = params.patch;
    report.regions_ms += millisecondsSince(phase);
  }
  if (scored.size() > params.top) scored.resize(params.top);
  for (std::size_t r = 0; r < scored.size(); ++r) scored[r].rank = r + 1;
  result.grasps = std::move(scored);
  report.total_ms = millisecondsSince(start);
  return result;
}

}  // namespace icrkit::planning
