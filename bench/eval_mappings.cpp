// Throughput of the evaluation's normal-line mappings (P_C2S, eq. 2; P_S2C,
// eq. 3) and of Algorithm 2 (IntersectionEstimator::estimate) on a
// 100k-vertex "CAD" sphere and a ~98k-vertex noisy "scan" of it, against the
// exhaustive-search baselines. vertices_per_second is the figure to read;
// docs/performance.md records the numbers. Before timing, the fast and the
// brute-force answers are compared on the brute-force samples and the
// disagreements reported (stdout and the `disagree` counters).

#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/eval/brute_force_mappings.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/eval/normal_line_mappings.hpp>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

namespace {

using icrkit::Triangle;
using icrkit::TriangleMesh;
using icrkit::eval::CadToScanMapping;
using icrkit::eval::IntersectionEstimator;
using icrkit::eval::RegionIntersection;
using icrkit::eval::ScanToCadMapping;
using icrkit::eval::VertexImage;

constexpr double kRadius = 0.05;          // a graspable object, metres
constexpr double kNoiseSigma = 0.0005;    // range noise along the normal
constexpr int kCadFrequency = 100;        // 10 * 100^2 + 2 = 100 002 vertices
constexpr int kScanFrequency = 99;        // 98 012 vertices: a different triangulation
constexpr std::size_t kFastQueries = 20000;
constexpr std::size_t kBruteQueries = 50;     // timed brute-force queries
constexpr std::size_t kCheckQueries = 200;    // brute-force agreement check (superset of the timed ones)
constexpr std::size_t kAlgorithm2BruteVertices = 50;
constexpr double kCapCosine = 0.94;       // cap of 3 % of the sphere: ~3 000 CAD vertices

// Geodesic sphere of frequency n (each icosahedron edge cut into n): 10 n^2 + 2
// vertices. makeIcosphere only reaches 10 * 4^s + 2, i.e. 41k or 164k, so the
// 100k pair needs its own frequency; two frequencies also give two unrelated
// triangulations, as a reconstruction is to its CAD model.
TriangleMesh geodesicSphere(int n, double radius) {
  const TriangleMesh base = icrkit::makeIcosphere(0, 1.0);
  TriangleMesh mesh;
  auto& positions = mesh.vertices.positions;
  positions = base.vertices.positions;
  auto add = [&](const Eigen::Vector3d& p) {
    positions.push_back(p.normalized());
    return static_cast<int>(positions.size() - 1);
  };
  // Interior points of each icosahedron edge, created once and shared by its two faces.
  std::map<std::pair<int, int>, std::vector<int>> edge_points;
  auto edgePoint = [&](int from, int to, int k) {  // k-th of n steps from `from` towards `to`
    const int lo = std::min(from, to), hi = std::max(from, to);
    auto [it, inserted] = edge_points.try_emplace({lo, hi});
    if (inserted)
      for (int s = 1; s < n; ++s)
        it->second.push_back(add(positions[lo] + (positions[hi] - positions[lo]) * (double(s) / n)));
    const int step = from == lo ? k : n - k;
    return it->second[static_cast<std::size_t>(step - 1)];
  };
  for (const Triangle& f : base.faces) {
    const int a = f[0], b = f[1], c = f[2];
    const Eigen::Vector3d pa = positions[a], pb = positions[b], pc = positions[c];
    // Grid (i along a->b, j along a->c, i + j <= n).
    std::vector<std::vector<int>> grid(static_cast<std::size_t>(n + 1));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        int index;
        if (i == 0 && j == 0) index = a;
        else if (i == n) index = b;
        else if (j == n) index = c;
        else if (j == 0) index = edgePoint(a, b, i);
        else if (i == 0) index = edgePoint(a, c, j);
        else if (i + j == n) index = edgePoint(b, c, j);
        else index = add(pa + (pb - pa) * (double(i) / n) + (pc - pa) * (double(j) / n));
        grid[static_cast<std::size_t>(i)].push_back(index);
      }
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]; };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        mesh.faces.emplace_back(at(i, j), at(i + 1, j), at(i, j + 1));
        if (i + j < n - 1) mesh.faces.emplace_back(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  mesh.vertices.normals = positions;  // unit sphere: position = outward normal
  for (auto& p : positions) p *= radius;
  return mesh;
}

// The "scan": another triangulation, turned so no vertex sits on a CAD vertex's
// normal line by construction, each vertex pushed along its normal by range
// noise; normals then re-estimated from the faces, as a reconstruction has.
TriangleMesh noisyScan(std::mt19937& rng) {
  TriangleMesh scan = geodesicSphere(kScanFrequency, kRadius);
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  std::normal_distribution<double> noise(0.0, kNoiseSigma);
  for (std::size_t v = 0; v < scan.vertexCount(); ++v) {
    const Eigen::Vector3d normal = turn * scan.vertices.normals[v];
    scan.vertices.positions[v] = turn * scan.vertices.positions[v] + noise(rng) * normal;
  }
  scan.vertices.normals.clear();
  icrkit::computeVertexNormals(scan);
  return scan;
}

std::vector<int> sample(std::size_t from, std::size_t count, std::mt19937& rng) {
  std::vector<int> all(from);
  std::iota(all.begin(), all.end(), 0);
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(std::min(count, from));
  return all;
}

std::vector<int> cap(const TriangleMesh& mesh, const Eigen::Vector3d& axis) {
  std::vector<int> region;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    if (mesh.vertices.positions[v].normalized().dot(axis) >= kCapCosine) region.push_back(static_cast<int>(v));
  return region;
}

bool sameImage(const VertexImage& a, const VertexImage& b) { return a.vertex == b.vertex && a.fallback == b.fallback; }

// Inclusive line-triangle test in double precision: a line through an edge or
// corner touches every face there, as Algorithm 2 asks. Tolerance in
// barycentric units, so it scales with the triangle.
bool lineTouches(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const Eigen::Vector3d& a,
                 const Eigen::Vector3d& b, const Eigen::Vector3d& c, double& t) {
  constexpr double kSlack = 1e-9;
  const Eigen::Vector3d ab = b - a, ac = c - a, normal = ab.cross(ac);
  const double denom = normal.dot(dir);
  if (std::abs(denom) <= 1e-14 * ab.norm() * ac.norm()) return false;
  t = normal.dot(a - origin) / denom;
  const Eigen::Vector3d p = origin + t * dir - a;
  // Barycentrics from signed sub-areas along the face normal.
  const double u = p.cross(ac).dot(normal) / normal.squaredNorm();
  const double w = ab.cross(p).dot(normal) / normal.squaredNorm();
  return u >= -kSlack && w >= -kSlack && u + w <= 1.0 + kSlack;
}

// Algorithm 2 by exhaustive search for the given scan vertices: each mapped
// by bruteForceScanToCad, its line along the CAD normal tested against every
// CAD region face. Returns per-vertex images and inside flags, and the
// crossed faces (sorted) in `crossed`.
struct BruteAlgorithm2 {
  std::vector<int> images;
  std::vector<std::uint8_t> inside;
  std::vector<int> crossed;
};

BruteAlgorithm2 bruteAlgorithm2(const TriangleMesh& cad, const std::vector<int>& region_faces, const TriangleMesh& scan,
                                const std::vector<int>& scan_vertices, double radius, double reach) {
  BruteAlgorithm2 out;
  std::vector<std::uint8_t> crossed(cad.faceCount(), 0);
  const auto& p = cad.vertices.positions;
  for (const int s : scan_vertices) {
    const auto u = static_cast<std::size_t>(s);
    const VertexImage image =
        icrkit::eval::bruteForceScanToCad(cad, scan.vertices.positions[u], scan.vertices.normals[u], radius, reach);
    out.images.push_back(image.vertex);
    out.inside.push_back(0);
    if (image.vertex < 0) continue;
    const Eigen::Vector3d dir = cad.vertices.normals[static_cast<std::size_t>(image.vertex)].normalized();
    for (const int face : region_faces) {
      const Triangle& f = cad.faces[static_cast<std::size_t>(face)];
      double t = 0.0;
      if (!lineTouches(scan.vertices.positions[u], dir, p[f[0]], p[f[1]], p[f[2]], t) || std::abs(t) > reach) continue;
      crossed[static_cast<std::size_t>(face)] = 1;
      out.inside.back() = 1;
    }
  }
  for (std::size_t i = 0; i < crossed.size(); ++i)
    if (crossed[i]) out.crossed.push_back(static_cast<int>(i));
  return out;
}

struct Fixture {
  TriangleMesh cad, scan;
  std::unique_ptr<CadToScanMapping> c2s;
  std::unique_ptr<ScanToCadMapping> s2c;
  std::unique_ptr<IntersectionEstimator> estimator;
  std::vector<int> cad_queries, scan_queries;  // fast: kFastQueries each; brute: their first kBruteQueries
  std::vector<int> cad_region, scan_region, cad_region_faces, scan_region_brute;
  // Agreement of fast and brute-force answers on kCheckQueries queries.
  std::size_t c2s_disagree = 0, s2c_disagree = 0, algorithm2_disagree = 0;
  std::size_t c2s_fallbacks = 0;  // fast P_C2S on the timed queries that crossed nothing facing
};

void checkMappings(Fixture& f) {
  const double c2s_radius = f.c2s->target().neighbourhoodRadius(), c2s_reach = f.c2s->target().maxLineDistance();
  const double s2c_radius = f.s2c->target().neighbourhoodRadius(), s2c_reach = f.s2c->target().maxLineDistance();
  for (std::size_t i = 0; i < kCheckQueries; ++i) {
    const auto c = static_cast<std::size_t>(f.cad_queries[i]);
    const auto& cp = f.cad.vertices.positions[c];
    const auto& cn = f.cad.vertices.normals[c];
    const VertexImage fast = f.c2s->map(cp, cn);
    const VertexImage brute = icrkit::eval::bruteForceCadToScan(f.scan, cp, cn, c2s_radius, c2s_reach);
    if (!sameImage(fast, brute)) {
      ++f.c2s_disagree;
      std::printf("P_C2S disagreement at CAD vertex %zu: fast %d (line %.3g m%s), brute %d (line %.3g m%s)\n", c,
                  fast.vertex, fast.line_distance_m, fast.fallback ? ", fallback" : "", brute.vertex,
                  brute.line_distance_m, brute.fallback ? ", fallback" : "");
    }
    const auto s = static_cast<std::size_t>(f.scan_queries[i]);
    const auto& sp = f.scan.vertices.positions[s];
    const auto& sn = f.scan.vertices.normals[s];
    const VertexImage fast_s = f.s2c->map(sp, sn);
    const VertexImage brute_s = icrkit::eval::bruteForceScanToCad(f.cad, sp, sn, s2c_radius, s2c_reach);
    if (!sameImage(fast_s, brute_s)) {
      ++f.s2c_disagree;
      std::printf("P_S2C disagreement at scan vertex %zu: fast %d (line %.3g m), brute %d (line %.3g m)\n", s,
                  fast_s.vertex, fast_s.line_distance_m, brute_s.vertex, brute_s.line_distance_m);
    }
  }
}

// estimate() on just the brute-force subset: I_n is the union of the subset's
// crossings, so it must equal the brute-force union face for face.
void checkAlgorithm2(Fixture& f) {
  const auto& target = f.estimator->scanToCad().target();
  const RegionIntersection fast = f.estimator->estimate(f.cad_region, f.scan, f.scan_region_brute);
  const BruteAlgorithm2 brute = bruteAlgorithm2(f.cad, f.cad_region_faces, f.scan, f.scan_region_brute,
                                                target.neighbourhoodRadius(), target.maxLineDistance());
  for (std::size_t i = 0; i < f.scan_region_brute.size(); ++i)
    if (fast.mapped_vertices[i] != brute.images[i] || fast.inside[i] != brute.inside[i]) {
      ++f.algorithm2_disagree;
      std::printf("Algorithm 2 disagreement at scan vertex %d: fast image %d inside %d, brute image %d inside %d\n",
                  f.scan_region_brute[i], fast.mapped_vertices[i], fast.inside[i], brute.images[i], brute.inside[i]);
    }
  if (fast.intersection_faces != brute.crossed) {
    ++f.algorithm2_disagree;
    std::printf("Algorithm 2 disagreement: fast I_n has %zu faces, brute force %zu\n", fast.intersection_faces.size(),
                brute.crossed.size());
  }
}

const Fixture& fixture() {
  static const Fixture instance = [] {
    Fixture f;
    std::mt19937 rng(20250314);
    f.cad = geodesicSphere(kCadFrequency, kRadius);
    f.scan = noisyScan(rng);
    f.c2s = std::make_unique<CadToScanMapping>(f.scan);
    f.s2c = std::make_unique<ScanToCadMapping>(f.cad);
    f.estimator = std::make_unique<IntersectionEstimator>(f.cad);
    f.cad_queries = sample(f.cad.vertexCount(), kFastQueries, rng);
    f.scan_queries = sample(f.scan.vertexCount(), kFastQueries, rng);

    const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, 3.0).normalized();
    f.cad_region = cap(f.cad, axis);
    f.scan_region = cap(f.scan, axis);
    std::vector<std::uint8_t> in(f.cad.vertexCount(), 0);
    for (const int v : f.cad_region) in[static_cast<std::size_t>(v)] = 1;
    const auto mask = icrkit::eval::regionFaceMask(f.cad, in);
    for (std::size_t i = 0; i < mask.size(); ++i)
      if (mask[i]) f.cad_region_faces.push_back(static_cast<int>(i));
    f.scan_region_brute = sample(f.scan_region.size(), kAlgorithm2BruteVertices, rng);
    for (int& i : f.scan_region_brute) i = f.scan_region[static_cast<std::size_t>(i)];

    for (const VertexImage& image : f.c2s->mapVertices(f.cad, f.cad_queries)) f.c2s_fallbacks += image.fallback;
    std::printf("CAD: %zu vertices, %zu faces; scan: %zu vertices, %zu faces\n", f.cad.vertexCount(),
                f.cad.faceCount(), f.scan.vertexCount(), f.scan.faceCount());
    std::printf("P_C2S radius %.3g mm, P_S2C radius %.3g mm; region: %zu CAD vertices (%zu faces), %zu scan vertices\n",
                1e3 * f.c2s->target().neighbourhoodRadius(), 1e3 * f.s2c->target().neighbourhoodRadius(),
                f.cad_region.size(), f.cad_region_faces.size(), f.scan_region.size());
    checkMappings(f);
    checkAlgorithm2(f);
    std::printf("disagreements: P_C2S %zu of %zu queries, P_S2C %zu of %zu, Algorithm 2 %zu (%zu scan vertices, "
                "then I_n as a whole); P_C2S fallbacks %zu of %zu\n",
                f.c2s_disagree, kCheckQueries, f.s2c_disagree, kCheckQueries, f.algorithm2_disagree,
                f.scan_region_brute.size(), f.c2s_fallbacks, kFastQueries);
    return f;
  }();
  return instance;
}

// Argument: TBB threads, 0 = every core.
tbb::global_control threadLimit(const benchmark::State& state) {
  const auto threads = static_cast<std::size_t>(state.range(0));
  return tbb::global_control(tbb::global_control::max_allowed_parallelism,
                             threads > 0 ? threads : static_cast<std::size_t>(tbb::info::default_concurrency()));
}

void reportRate(benchmark::State& state, std::size_t vertices) {
  state.counters["vertices_per_second"] =
      benchmark::Counter(static_cast<double>(vertices), benchmark::Counter::kIsIterationInvariantRate);
}

void cadToScanEmbree(benchmark::State& state) {
  const Fixture& f = fixture();
  const auto limit = threadLimit(state);
  for (auto _ : state) benchmark::DoNotOptimize(f.c2s->mapVertices(f.cad, f.cad_queries));
  reportRate(state, f.cad_queries.size());
  state.counters["fallbacks"] = static_cast<double>(f.c2s_fallbacks);
}

void cadToScanBruteForce(benchmark::State& state) {
  const Fixture& f = fixture();
  const double radius = f.c2s->target().neighbourhoodRadius(), reach = f.c2s->target().maxLineDistance();
  for (auto _ : state)
    for (std::size_t i = 0; i < kBruteQueries; ++i) {
      const auto v = static_cast<std::size_t>(f.cad_queries[i]);
      benchmark::DoNotOptimize(icrkit::eval::bruteForceCadToScan(f.scan, f.cad.vertices.positions[v],
                                                                 f.cad.vertices.normals[v], radius, reach));
    }
  reportRate(state, kBruteQueries);
  state.counters["disagree"] = static_cast<double>(f.c2s_disagree);
  state.counters["checked"] = static_cast<double>(kCheckQueries);
}

void scanToCadEmbree(benchmark::State& state) {
  const Fixture& f = fixture();
  const auto limit = threadLimit(state);
  for (auto _ : state) benchmark::DoNotOptimize(f.s2c->mapVertices(f.scan, f.scan_queries));
  reportRate(state, f.scan_queries.size());
}

void scanToCadBruteForce(benchmark::State& state) {
  const Fixture& f = fixture();
  const double radius = f.s2c->target().neighbourhoodRadius(), reach = f.s2c->target().maxLineDistance();
  for (auto _ : state)
    for (std::size_t i = 0; i < kBruteQueries; ++i) {
      const auto v = static_cast<std::size_t>(f.scan_queries[i]);
      benchmark::DoNotOptimize(icrkit::eval::bruteForceScanToCad(f.cad, f.scan.vertices.positions[v],
                                                                 f.scan.vertices.normals[v], radius, reach));
    }
  reportRate(state, kBruteQueries);
  state.counters["disagree"] = static_cast<double>(f.s2c_disagree);
  state.counters["checked"] = static_cast<double>(kCheckQueries);
}

// Rate in scan-region vertices: the loop of Algorithm 2 runs over C_n^S.
void algorithm2Embree(benchmark::State& state) {
  const Fixture& f = fixture();
  const auto limit = threadLimit(state);
  for (auto _ : state) benchmark::DoNotOptimize(f.estimator->estimate(f.cad_region, f.scan, f.scan_region));
  reportRate(state, f.scan_region.size());
  state.counters["scan_region"] = static_cast<double>(f.scan_region.size());
  state.counters["cad_region"] = static_cast<double>(f.cad_region.size());
}

void algorithm2BruteForce(benchmark::State& state) {
  const Fixture& f = fixture();
  const auto& target = f.estimator->scanToCad().target();
  for (auto _ : state)
    benchmark::DoNotOptimize(bruteAlgorithm2(f.cad, f.cad_region_faces, f.scan, f.scan_region_brute,
                                             target.neighbourhoodRadius(), target.maxLineDistance()));
  reportRate(state, f.scan_region_brute.size());
  state.counters["disagree"] = static_cast<double>(f.algorithm2_disagree);
  state.counters["checked"] = static_cast<double>(f.scan_region_brute.size());
}

// Wall-clock time throughout: the TBB batches run on several threads.
BENCHMARK(cadToScanEmbree)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(cadToScanBruteForce)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(scanToCadEmbree)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(scanToCadBruteForce)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(algorithm2Embree)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(algorithm2BruteForce)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
