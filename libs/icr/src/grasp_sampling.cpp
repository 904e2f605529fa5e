#include <icrkit/icr/grasp_sampling.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace icrkit::icr {
namespace {

// ---------------------------------------------------------------------------
// The pre-check. The origin is interior to the hull of the wrenches iff they
// positively span R^6, iff no direction d != 0 has d . w_i >= 0 for every i.
// Such a d is looked for in two ways:
//  - the origin outside the hull: Wolfe's nearest-point algorithm ("Finding
//    the nearest point in a polytope", 1976) walks a corral of at most 7
//    affinely independent wrenches towards the hull point x nearest the
//    origin, and d = x;
//  - the origin on the boundary (common: two contacts squeezing each other
//    already put the origin in the hull of their wrenches, on a face unless
//    the other fingers close it): Wolfe ends at x = 0 with a corral S whose
//    hull holds the origin in its relative interior. Any certificate d must
//    then be orthogonal to span(S), and the wrenches positively span R^6 iff
//    their projections onto span(S)^perp positively span that subspace, so
//    the search repeats there, in at most 6 ever smaller subspaces.
// Every d found is checked against the original wrenches before "false" is
// answered: rounding inside the iterations can cost rejections but never
// create a wrong one.

enum class OriginPlace { Outside, Inside, Unknown };

constexpr int kMaxCorral = 7;        // affinely independent points in R^6
constexpr int kMaxMajorCycles = 200;  // far above what the 36-wrench sets need
// Relative to the largest wrench norm: a separating margin this small is
// below anything the hull could resolve, and a nearest point this close is
// "touching".
constexpr double kRelativeTolerance = 1e-12;
// A barycentric weight below this leaves the origin on the corral's face.
constexpr double kNegligibleWeight = 1e-9;

using CorralPoints = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxCorral - 1>;

struct Corral {
  std::array<Eigen::Index, kMaxCorral> index{};
  std::array<double, kMaxCorral> weight{};
  int size = 0;

  bool contains(Eigen::Index j) const {
    return std::find(index.begin(), index.begin() + size, j) != index.begin() + size;
  }
  Wrench point(const WrenchSet& w) const {
    Wrench x = Wrench::Zero();
    for (int i = 0; i < size; ++i) x += weight[i] * w.col(index[i]);
    return x;
  }
};

// Barycentric coordinates of the point of aff(corral) nearest the origin,
// as a least-squares problem in the differences to the first point (better
// conditioned than the bordered Gram system). False when the corral has
// become affinely dependent through rounding.
bool affineMinimizer(const WrenchSet& w, const Corral& corral, std::array<double, kMaxCorral>& alpha) {
  if (corral.size == 1) {
    alpha[0] = 1.0;
    return true;
  }
  const Wrench base = w.col(corral.index[0]);
  CorralPoints differences(6, corral.size - 1);
  for (int i = 1; i < corral.size; ++i) differences.col(i - 1) = w.col(corral.index[i]) - base;
  const Eigen::ColPivHouseholderQR<CorralPoints> qr(differences);
  if (qr.rank() < corral.size - 1) return false;
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCorral - 1, 1> beta = qr.solve(-base);
  if (!beta.allFinite()) return false;
  alpha[0] = 1.0 - beta.sum();
  for (int i = 1; i < corral.size; ++i) alpha[i] = beta[i - 1];
  return true;
}

// Wolfe's iteration on the columns of w; `corral` and `x` are where it stopped.
OriginPlace locateOrigin(const WrenchSet& w, double scale, Corral& corral, Wrench& x) {
  const double tolerance = kRelativeTolerance * scale;
  corral = Corral{};
  Eigen::Index start = 0;
  w.colwise().squaredNorm().minCoeff(&start);
  corral.index[0] = start;
  corral.weight[0] = 1.0;
  corral.size = 1;
  x = w.col(start);
  Eigen::Matrix<double, 1, Eigen::Dynamic> dots(w.cols());
  std::array<double, kMaxCorral> alpha{};

  for (int major = 0; major < kMaxMajorCycles; ++major) {
    const double norm = x.norm();
    if (norm <= tolerance) return OriginPlace::Inside;
    dots.noalias() = x.transpose() * w;
    Eigen::Index entering = 0;
    const double least = dots.minCoeff(&entering);
    if (least > tolerance * norm) return OriginPlace::Outside;  // every wrench strictly beyond x's hyperplane
    // x is (numerically) the nearest point but the origin is within rounding
    // of the hull: nothing can be proved either way.
    if (norm * norm - least <= tolerance * scale || corral.contains(entering) || corral.size == kMaxCorral)
      return OriginPlace::Unknown;

    corral.index[corral.size] = entering;
    corral.weight[corral.size] = 0.0;
    ++corral.size;
    // Minor cycles: each one drops at least one point, so they end.
    for (;;) {
      if (!affineMinimizer(w, corral, alpha)) return OriginPlace::Unknown;
      bool interior = true;
      for (int i = 0; i < corral.size; ++i) interior = interior && alpha[i] > 0.0;
      if (interior) {
        std::copy(alpha.begin(), alpha.begin() + corral.size, corral.weight.begin());
        break;
      }
      // Move from the current weights towards alpha until a weight hits zero;
      // that point (and any other rounded to zero) leaves the corral.
      double theta = 1.0;
      int leaving = -1;
      for (int i = 0; i < corral.size; ++i) {
        if (alpha[i] > 0.0) continue;
        const double ratio = corral.weight[i] > 0.0 ? corral.weight[i] / (corral.weight[i] - alpha[i]) : 0.0;
        if (leaving < 0 || ratio < theta) {
          theta = ratio;
          leaving = i;
        }
      }
      int kept = 0;
      double total = 0.0;
      for (int i = 0; i < corral.size; ++i) {
        const double weight = (1.0 - theta) * corral.weight[i] + theta * alpha[i];
        if (i == leaving || !(weight > 0.0)) continue;
        corral.index[kept] = corral.index[i];
        corral.weight[kept] = weight;
        total += weight;
        ++kept;
      }
      if (kept == 0 || kept == corral.size || !(total > 0.0)) return OriginPlace::Unknown;
      corral.size = kept;
      for (int i = 0; i < kept; ++i) corral.weight[i] /= total;
    }
    x = corral.point(w);
  }
  return OriginPlace::Unknown;
}

// d certifies "not force closure" when every wrench lies on its closed side:
// then no ball around the origin fits in the hull. An origin closer to the
// boundary than 1e-12 times the largest wrench norm counts as on it, far
// below the hull's own force-closure threshold (1e-10 for unit forces).
bool separates(const WrenchSet& w, const Wrench& d, double scale) {
  const double length = d.norm();
  if (!(length > 0.0)) return false;
  return (d.transpose() * w).minCoeff() >= -kRelativeTolerance * scale * length;
}

using Basis = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;

// The wrenches' projections onto the subspace with orthonormal `basis`,
// without those that vanish there (they cannot help to span it).
WrenchSet projectOnto(const WrenchSet& w, const Basis& basis, double scale) {
  const WrenchSet projected = basis * (basis.transpose() * w);
  const Eigen::Array<double, 1, Eigen::Dynamic> norms = projected.colwise().norm();
  WrenchSet kept(6, (norms > kRelativeTolerance * scale).count());
  Eigen::Index column = 0;
  for (Eigen::Index i = 0; i < projected.cols(); ++i)
    if (norms[i] > kRelativeTolerance * scale) kept.col(column++) = projected.col(i);
  return kept;
}

// ---------------------------------------------------------------------------
// Sampling. Attempt a draws its contacts from a generator seeded by (seed, a)
// alone, so attempts can be evaluated in any order on any number of threads
// and the accepted grasps are those of the first attempts in attempt order:
// the same for a seed whatever the thread count.

// SplitMix64 finaliser: a bijection on 64-bit words that scrambles every bit.
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// SplitMix64 stream: tiny state, so starting one per attempt is free
// (unlike re-seeding a Mersenne twister).
class AttemptRandom {
public:
  AttemptRandom(std::uint64_t seed, std::uint64_t attempt) : state_(mix64(mix64(seed) ^ attempt)) {}

  // Uniform in [0, n), without modulo bias; spelled out (rather than
  // std::uniform_int_distribution) so results agree across standard libraries.
  std::size_t below(std::size_t n) {
    const std::uint64_t range = n;
    const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                                std::numeric_limits<std::uint64_t>::max() % range;
    std::uint64_t r = next();
    while (r >= limit) r = next();
    return static_cast<std::size_t>(r % range);
  }

private:
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ULL;
    return mix64(state_);
  }
  std::uint64_t state_;
};

// Wrenches of the contacts drawn for one attempt.
void graspWrenches(const GraspableObject& object, const ContactWrenches& contact_wrenches, const int* contacts,
                   std::size_t fingers, WrenchSet& out) {
  for (std::size_t f = 0; f < fingers; ++f) {
    const auto vertex = static_cast<std::size_t>(contacts[f]);
    contact_wrenches.compute(object.position(vertex), object.normal(vertex), out,
                             static_cast<Eigen::Index>(f * contact_wrenches.perContact()));
  }
}

}  // namespace

bool mayBeForceClosure(const WrenchSet& wrenches) {
  // Positively spanning R^6 takes at least 7 vectors; the hull code also
  // declares such sets degenerate.
  if (wrenches.cols() < 7) return false;
  if (!wrenches.allFinite()) return true;  // not ours to judge: the hull reports it
  const double scale = wrenches.colwise().norm().maxCoeff();
  if (!(scale > 0.0)) return false;

  Basis basis = Basis::Identity(6, 6);
  WrenchSet points = projectOnto(wrenches, basis, scale);
  Corral corral;
  Wrench x;
  while (basis.cols() > 0) {
    if (points.cols() == 0) return !separates(wrenches, basis.col(0), scale);  // all wrenches orthogonal to it
    const OriginPlace place = locateOrigin(points, scale, corral, x);
    if (place != OriginPlace::Inside) return !separates(wrenches, x, scale);
    // The origin is in the relative interior of the corral's hull: recurse
    // into the part of the current subspace orthogonal to the corral. A
    // point with a vanishing weight only means the origin is (nearly) on a
    // face of the corral's simplex, i.e. maybe on the hull's boundary, so it
    // is left out of the span.
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxCorral> local(basis.cols(), corral.size);
    Eigen::Index essential = 0;
    for (int i = 0; i < corral.size; ++i)
      if (corral.weight[i] > kNegligibleWeight)
        local.col(essential++) = basis.transpose() * points.col(corral.index[i]);
    if (essential == 0) return true;  // no progress possible (weights sum to 1: cannot happen)
    local.conservativeResize(Eigen::NoChange, essential);
    const Eigen::JacobiSVD<decltype(local)> svd(local, Eigen::ComputeFullU);
    const Eigen::Index rank = (svd.singularValues().array() > kRelativeTolerance * scale).count();
    if (rank == basis.cols()) return true;  // a full-dimensional simplex around the origin
    if (rank == 0) return true;             // no progress possible
    const Basis rest = basis * svd.matrixU().rightCols(basis.cols() - rank);
    basis = rest;
    points = projectOnto(wrenches, basis, scale);
  }
  return true;
}

std::vector<SampledGrasp> sampleForceClosureGrasps(const GraspableObject& object, const ContactModel& model,
                                                   const GraspSamplingParameters& params,
                                                   GraspSamplingStatistics* statistics) {
  const auto started = std::chrono::steady_clock::now();
  model.validate();
  if (params.fingers < 2)
    throw InputError("grasp sampling", "fingers", "need at least 2 fingers, got " + std::to_string(params.fingers));
  std::vector<int> eligible;
  eligible.reserve(object.vertexCount());
  for (std::size_t v = 0; v < object.vertexCount(); ++v)
    if (object.eligible(v)) eligible.push_back(static_cast<int>(v));
  if (eligible.size() < params.fingers)
    throw InputError("grasp sampling", "",
                     std::to_string(params.fingers) + " fingers need as many distinct contacts, but only " +
                         std::to_string(eligible.size()) + " vertices are used by a face and not excluded");

  const ContactWrenches contact_wrenches(model, object.frame());
  const std::size_t fingers = params.fingers;
  const auto columns = static_cast<Eigen::Index>(fingers * contact_wrenches.perContact());
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));

  std::vector<SampledGrasp> grasps;
  GraspSamplingStatistics stats;
  std::vector<int> drawn;                // `fingers` contacts per attempt of the batch
  std::vector<std::uint8_t> passed;      // per attempt: survived the pre-check
  std::vector<std::size_t> survivors;    // attempts (batch offsets) that did, ascending
  std::vector<double> epsilon;           // per survivor, once its hull is built
  std::vector<std::uint8_t> closure;     // per survivor

  // Attempts are evaluated in batches, survivors' hulls in chunks sized to
  // what is still wanted; both sizes only decide how much work may be
  // wasted past the last grasp needed, never which grasps come back.
  std::size_t next_attempt = 0;
  std::size_t batch = std::clamp<std::size_t>(2 * params.count, 64, 8192);
  double hull_acceptance = 1.0;  // fraction of built hulls that gave a grasp so far
  while (grasps.size() < params.count && next_attempt < params.max_attempts) {
    const std::size_t first = next_attempt;
    const std::size_t size = std::min(batch, params.max_attempts - first);
    drawn.assign(size * fingers, -1);
    passed.assign(size, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, size), [&](const tbb::blocked_range<std::size_t>& range) {
      WrenchSet wrenches(6, columns);
      for (std::size_t s = range.begin(); s != range.end(); ++s) {
        AttemptRandom random(params.seed, first + s);
        int* contacts = drawn.data() + s * fingers;
        for (std::size_t f = 0; f < fingers; ++f) {
          int vertex;
          do {
            vertex = eligible[random.below(eligible.size())];
          } while (std::find(contacts, contacts + f, vertex) != contacts + f);
          contacts[f] = vertex;
        }
        graspWrenches(object, contact_wrenches, contacts, fingers, wrenches);
        passed[s] = mayBeForceClosure(wrenches);
      }
    });
    survivors.clear();
    for (std::size_t s = 0; s < size; ++s)
      if (passed[s]) survivors.push_back(s);
    epsilon.assign(survivors.size(), 0.0);
    closure.assign(survivors.size(), 0);

    std::size_t consumed = size;  // attempts of this batch that count
    for (std::size_t done = 0; done < survivors.size() && grasps.size() < params.count;) {
      const double wanted = static_cast<double>(params.count - grasps.size()) / std::max(hull_acceptance, 0.01);
      const std::size_t chunk =
          std::min(survivors.size() - done, std::max(threads, static_cast<std::size_t>(std::ceil(wanted))));
      tbb::parallel_for(tbb::blocked_range<std::size_t>(done, done + chunk, 1),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          WrenchSet wrenches(6, columns);
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                            graspWrenches(object, contact_wrenches, drawn.data() + survivors[i] * fingers, fingers,
                                          wrenches);
                            const GraspWrenchSpace gws = computeGraspWrenchSpace(wrenches, params.hull);
                            epsilon[i] = gws.epsilon;
                            closure[i] = gws.force_closure && gws.epsilon >= params.min_epsilon;
                          }
                        });
      for (std::size_t i = done; i < done + chunk; ++i) {
        ++stats.hulls_built;
        if (!closure[i]) continue;
        const auto begin = drawn.begin() + static_cast<std::ptrdiff_t>(survivors[i] * fingers);
        grasps.push_back({std::vector<int>(begin, begin + static_cast<std::ptrdiff_t>(fingers)), epsilon[i]});
        if (grasps.size() == params.count) {
          consumed = survivors[i] + 1;
          break;
        }
      }
      done += chunk;
      hull_acceptance = static_cast<double>(grasps.size()) / static_cast<double>(stats.hulls_built);
    }
    stats.attempts += consumed;
    stats.rejected_by_precheck += consumed - static_cast<std::size_t>(std::count(passed.begin(), passed.begin() +
                                                                              static_cast<std::ptrdiff_t>(consumed),
                                                                          std::uint8_t{1}));
    next_attempt += size;
    batch = std::min<std::size_t>(batch * 2, 65536);
  }

  stats.time_ms = millisecondsSince(started);
  if (statistics) *statistics = stats;
  return grasps;
}

}  // namespace icrkit::icr
