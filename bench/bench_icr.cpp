// Time of one complete ICR computation (wrenches, hull, search zones, region
// growth) on the icr-models meshes, with the per-phase breakdown, and the lazy
// wrench evaluation against computing every vertex's wrenches up front on a
// 100k-vertex mesh. Results and commands: docs/performance.md.

#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

using namespace icrkit;
using namespace icrkit::icr;

namespace {

const std::string kData = ICRKIT_SHARED_DATA_DIR;

struct Workload {
  TriangleMesh mesh;
  std::unique_ptr<GraspableObject> object;
  std::vector<std::vector<int>> grasps;
};

// The reference grasps of one model and finger count (frictional, mu 0.8, L 8).
std::shared_ptr<Workload> referenceWorkload(const std::string& model, int fingers) {
  const std::string alpha = fingers == 4 ? "0.5" : "0.8";
  const std::string file = kData + "/icr-reference/" + model + "__frictional_mu0.8_L8_f" + std::to_string(fingers) +
                           "_a" + alpha + ".json";
  if (!std::filesystem::exists(file)) return nullptr;
  auto w = std::make_shared<Workload>();
  w->mesh = io::readTriangleMesh(kData + "/icr-models/" + model + ".obj");
  w->object = std::make_unique<GraspableObject>(GraspableObject::withDefaultFrame(w->mesh));
  std::ifstream in(file);
  const nlohmann::json reference = nlohmann::json::parse(in);
  for (const auto& g : reference.at("grasps")) w->grasps.push_back(g.at("contacts").get<std::vector<int>>());
  return w;
}

// An ellipsoid of about 100k vertices (UV-free: a subdivided octahedron).
TriangleMesh largeEllipsoid() {
  TriangleMesh m;
  const int n = 158;  // vertices: 4 n^2 + 2, about 100k
  std::map<std::tuple<int, int, int>, int> index;
  auto vertex = [&](int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const Eigen::Vector3d p = Eigen::Vector3d(i, j, k).normalized();
    m.vertices.positions.push_back(p.cwiseProduct(Eigen::Vector3d(0.10, 0.07, 0.05)));
    return index[key] = static_cast<int>(m.vertices.positions.size() - 1);
  };
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1})
        for (int a = 0; a < n; ++a)
          for (int b = 0; a + b < n; ++b) {
            auto v = [&](int i, int j) { return vertex(sx * i, sy * j, sz * (n - i - j)); };
            const bool flip = sx * sy * sz < 0;
            auto add = [&](int p, int q, int r) { flip ? m.faces.emplace_back(p, r, q) : m.faces.emplace_back(p, q, r); };
            add(v(a, b), v(a + 1, b), v(a, b + 1));
            if (a + b + 1 < n) add(v(a + 1, b), v(a + 1, b + 1), v(a, b + 1));
          }
  computeVertexNormals(m);
  return m;
}

// `conservative`: uncertainty-aware growth with fixed bounds (the models have
// no sigma attributes) of 0.5 deg and 0.2 mm, small enough that regions
// still grow, so the extra per-vertex work is measured, not smaller regions.
void runIcr(benchmark::State& state, std::shared_ptr<Workload> w, double alpha, bool conservative = false) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  IcrParameters params;
  params.alpha = alpha;
  if (conservative) {
    params.conservative = ConservativeGrowth{};
    params.conservative->normal_angle = 0.5 * M_PI / 180.0;
    params.conservative->position_offset = 0.0002;
  }
  std::size_t i = 0, region_vertices = 0;
  double hull = 0, zones = 0, growth = 0;
  for (auto _ : state) {
    const IcrResult r = computeIndependentContactRegions(*w->object, w->grasps[i++ % w->grasps.size()], params);
    hull += r.timings.hull_ms;
    zones += r.timings.zones_ms;
    growth += r.timings.growth_ms;
    for (const ContactRegion& region : r.regions) region_vertices += region.vertices.size();
    benchmark::DoNotOptimize(r.regions.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["region_vertices"] = static_cast<double>(region_vertices) / n;
  state.counters["hull_ms"] = hull / n;
  state.counters["zones_ms"] = zones / n;
  state.counters["growth_ms"] = growth / n;
}

struct LargeWorkload {
  TriangleMesh mesh;
  std::unique_ptr<GraspableObject> object;
  std::vector<std::vector<int>> grasps;
};

LargeWorkload& large() {
  static LargeWorkload w = [] {
    LargeWorkload l;
    l.mesh = largeEllipsoid();
    l.object = std::make_unique<GraspableObject>(GraspableObject::withDefaultFrame(l.mesh));
    // Twenty random force-closure grasps (seed 1): typical, not hand-picked, regions.
    GraspSamplingParameters sampling;
    sampling.count = 20;
    for (const SampledGrasp& g : sampleForceClosureGrasps(*l.object, ContactModel(), sampling))
      l.grasps.push_back(g.contacts);
    return l;
  }();
  return w;
}

void runLarge(benchmark::State& state, bool conservative) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  LargeWorkload& w = large();
  IcrParameters params;
  if (conservative) {
    // Per-vertex sigmas as a reconstruction writes them (0.2 deg, 0.1 mm), read
    // from the attributes like on a real mesh; K = 1.
    if (!w.mesh.vertices.attributes.has("normal_sigma")) {
      w.mesh.vertices.attributes.add("normal_sigma", ScalarType::Float32, w.mesh.vertexCount(), 0.2 * M_PI / 180.0);
      w.mesh.vertices.attributes.add("position_sigma", ScalarType::Float32, w.mesh.vertexCount(), 0.0001);
    }
    params.conservative = ConservativeGrowth{};
  }
  std::size_t tested = 0, i = 0, region_vertices = 0;
  for (auto _ : state) {
    const IcrResult r = computeIndependentContactRegions(*w.object, w.grasps[i++ % w.grasps.size()], params);
    tested += r.vertices_tested;
    for (const ContactRegion& region : r.regions) region_vertices += region.vertices.size();
    benchmark::DoNotOptimize(r.regions.data());
  }
  state.counters["vertices"] = static_cast<double>(w.mesh.vertexCount());
  state.counters["vertices_tested"] = static_cast<double>(tested) / static_cast<double>(state.iterations());
  state.counters["region_vertices"] = static_cast<double>(region_vertices) / static_cast<double>(state.iterations());
}

void BM_IcrLargeMeshLazy(benchmark::State& state) { runLarge(state, false); }
void BM_IcrLargeMeshConservative(benchmark::State& state) { runLarge(state, true); }

// The eager alternative: every vertex's wrenches before the hull, then the same ICR.
void BM_IcrLargeMeshEagerWrenches(benchmark::State& state) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  LargeWorkload& w = large();
  IcrParameters params;
  const ContactWrenches generator(params.contact_model, w.object->frame());
  std::size_t i = 0;
  for (auto _ : state) {
    WrenchSet all(6, static_cast<Eigen::Index>(generator.perContact() * w.mesh.vertexCount()));
    for (std::size_t v = 0; v < w.mesh.vertexCount(); ++v)
      generator.compute(w.object->position(v), w.object->normal(v), all,
                        static_cast<Eigen::Index>(v * generator.perContact()));
    benchmark::DoNotOptimize(all.data());
    const IcrResult r = computeIndependentContactRegions(*w.object, w.grasps[i++ % w.grasps.size()], params);
    benchmark::DoNotOptimize(r.regions.data());
  }
}

}  // namespace

BENCHMARK(BM_IcrLargeMeshLazy)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IcrLargeMeshConservative)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IcrLargeMeshEagerWrenches)->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  const char* models[] = {"CokePlasticSmall_5k", "Fish_5k", "RedCup_5k", "ShowerGel_5k", "Sprayflask_5k", "Tortoise_5k"};
  for (int fingers : {4, 5})
    for (const char* model : models) {
      auto w = referenceWorkload(model, fingers);
      if (!w) {
        std::fprintf(stderr, "note: shared ICR data for %s not found, skipped\n", model);
        continue;
      }
      benchmark::RegisterBenchmark(("BM_Icr/" + std::string(model) + "/fingers:" + std::to_string(fingers)).c_str(),
                                   [w, fingers](benchmark::State& s) { runIcr(s, w, fingers == 4 ? 0.5 : 0.8); })
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(
          ("BM_IcrConservative/" + std::string(model) + "/fingers:" + std::to_string(fingers)).c_str(),
          [w, fingers](benchmark::State& s) { runIcr(s, w, fingers == 4 ? 0.5 : 0.8, true); })
          ->Unit(benchmark::kMillisecond);
    }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
