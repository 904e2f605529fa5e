#include <icrkit/eval/experiment.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/mesh_topology.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/eval/kept_vertex_snapping.hpp>
#include <icrkit/eval/region_quality.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/graspable_object.hpp>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <set>
#include <string>
#include <utility>

namespace icrkit::eval {
namespace {

void requireNormals(const TriangleMesh* mesh, const std::string& what) {
  if (!mesh) throw InputError(what, "", "no mesh given");
  if (mesh->faces.empty()) throw InputError(what, "", "the mesh has no faces");
  if (mesh->vertices.normals.size() != mesh->vertexCount())
    throw InputError(what, "", "the mesh needs one normal per vertex");
  // A vertex no face uses is never a contact, a region vertex or a mapping
  // target, so whatever normal it carries (zero, garbage) does not matter.
  const std::vector<std::uint8_t> referenced = referencedVertices(*mesh);
  for (std::size_t v = 0; v < mesh->vertexCount(); ++v) {
    if (!referenced[v]) continue;
    const double length = mesh->vertices.normals[v].norm();
    if (!(std::abs(length - 1.0) < 1e-3))
      throw InputError(what, "vertex " + std::to_string(v),
                       "expected a unit vertex normal, got one of length " + std::to_string(length));
  }
}

std::string fingerName(std::size_t finger) { return "contact " + std::to_string(finger); }

}  // namespace

std::pair<std::size_t, std::size_t> Shard::range(std::size_t total) const {
  // Rounded boundaries: sizes differ by at most one item.
  const auto boundary = [&](std::size_t i) { return (total * i) / count; };
  return {boundary(index), boundary(index + 1)};
}

void Shard::validate() const {
  if (count < 1 || index >= count)
    throw InputError("Shard", "", "expected i/N with N >= 1 and 0 <= i < N, got " + std::to_string(index) + "/" +
                                        std::to_string(count));
}

void ExperimentConfig::validate() const {
  if (finger_counts.empty())
    throw InputError("ExperimentConfig::finger_counts", "", "expected at least one finger count");
  for (const std::size_t f : finger_counts)
    if (f < 2 || f > 20)
      throw InputError("ExperimentConfig::finger_counts", "", "expected 2..20 fingers, got " + std::to_string(f));
  if (std::set<std::size_t>(finger_counts.begin(), finger_counts.end()).size() != finger_counts.size())
    throw InputError("ExperimentConfig::finger_counts", "", "a finger count is repeated");
  if (grasps_per_set < 1) throw InputError("ExperimentConfig::grasps_per_set", "", "expected at least 1");
  if (!(alpha > 0.0 && alpha <= 1.0))
    throw InputError("ExperimentConfig::alpha", "", "expected 0 < alpha <= 1, got " + std::to_string(alpha));
  for (const double k : conservative_sigmas)
    if (!(k >= 0) || !std::isfinite(k))
      throw InputError("ExperimentConfig::conservative_sigmas", "", "expected K >= 0, got " + std::to_string(k));
  mapping.validate();
  if (patch) patch->validate();
  contactModel().validate();
}

icr::IcrParameters ExperimentConfig::icrParameters(double tws_radius) const {
  icr::IcrParameters params;
  params.contact_model = contactModel();
  params.tws_radius = tws_radius;
  params.mode = growth;
  return params;
}

std::vector<std::uint8_t> ExperimentConfig::filteredExclusion(const TriangleMesh& filtered) const {
  return preselection ? icr::exclusionMaskOf(filtered) : std::vector<std::uint8_t>{};
}

icr::WrenchFrame commonWrenchFrame(const TriangleMesh& cad) {
  return icr::makeWrenchFrame(referencedPositions(cad), icr::TorqueReference::Centroid);
}

icr::ContactModel ExperimentConfig::contactModel() const {
  icr::ContactModel model;
  model.type = icr::ContactType::Frictional;
  model.friction = friction;
  model.cone_edges = cone_edges;
  return model;
}

namespace {

// The CAD vertex the region's recommended contact maps onto (eq. (3), as
// its region's vertices do: `mapped` follows the region's vertex order);
// -1 for an empty region or a contact that maps nowhere.
int recommendedImage(const icr::ContactRegion& region, const std::vector<int>& mapped) {
  const int vertex = region.recommended.vertex;
  const auto at = std::lower_bound(region.vertices.begin(), region.vertices.end(), vertex);
  if (vertex < 0 || at == region.vertices.end() || *at != vertex) return -1;
  const auto k = static_cast<std::size_t>(at - region.vertices.begin());
  return k < mapped.size() ? mapped[k] : -1;
}

// The task of every grasp in the experiment: force closure, and the TWS
// ball (radius alpha x the CAD grasp's epsilon) inside the GWS.
bool holdsTask(const icr::GraspWrenchSpace& gws, double tws_radius) {
  return gws.force_closure && gws.epsilon >= tws_radius;
}

// The CAD grasp of the regions' recommended contacts; empty when one maps
// nowhere or two map onto one CAD vertex (no grasp a robot could make).
std::vector<int> aimedCadContacts(const std::vector<icr::ContactRegion>& regions,
                                  const std::vector<std::vector<int>>& mapped) {
  std::vector<int> aimed;
  for (std::size_t n = 0; n < regions.size(); ++n) aimed.push_back(recommendedImage(regions[n], mapped[n]));
  const std::set<int> distinct(aimed.begin(), aimed.end());
  if (distinct.count(-1) > 0 || distinct.size() != aimed.size()) return {};
  return aimed;
}

}  // namespace

struct DatasetExperiment::Impl {
  DatasetMeshes meshes;
  ExperimentConfig config;
  icr::ContactModel model;
  icr::WrenchFrame frame;
  icr::GraspableObject cad_object;
  icr::GraspableObject raw_object;
  icr::GraspableObject filtered_object;
  CadToScanMapping to_raw;
  CadToScanMapping to_filtered;
  // The snapping radius is the mapping's neighbourhood radius
  // (MappingParameters::neighbourhood_radius as the filtered mapping resolved
  // it: default twice the filtered mesh's median edge length). Eq. (2)
  // already treats the vertices within it of the line's crossing as equally
  // good images of one CAD contact, so a move within it stays a transfer of
  // the same contact. The other reach, max_line_distance (10 mm), bounds how
  // far a reconstruction may lie from the CAD surface; a move that far would
  // be a different contact.
  KeptVertexSnapping filtered_snapping;
  IntersectionEstimator estimator;
  VertexFaces raw_faces, filtered_faces;
  RegionQualityEvaluator quality;
  // The filtered mesh's boundary vertices: the rim of the seen surface
  // (the tree keeps a reference to the points, declared first).
  std::vector<Eigen::Vector3d> filtered_rim_points;
  std::unique_ptr<KdTree> filtered_rim;
  struct TestSet {
    std::size_t fingers;
    std::vector<icr::SampledGrasp> grasps;
  };
  std::vector<TestSet> test_sets;
  // With ExperimentConfig::patch: every vertex's patch, built when first
  // asked for and shared by all grasps and threads.
  std::unique_ptr<icr::ContactPatches> cad_patches, raw_patches, filtered_patches;

  Impl(const DatasetMeshes& m, const ExperimentConfig& c, const icr::WrenchFrame& f)
      : meshes(m),
        config(c),
        model(c.contactModel()),
        frame(f),
        cad_object(*m.cad, f),
        raw_object(*m.raw, f),  // raw meshes are never preselected
        filtered_object(*m.filtered, f, c.filteredExclusion(*m.filtered)),
        to_raw(*m.raw, c.mapping),
        to_filtered(*m.filtered, c.mapping),
        filtered_snapping(filtered_object, to_filtered.target().neighbourhoodRadius()),
        estimator(*m.cad, c.mapping),
        raw_faces(vertexFaces(*m.raw)),
        filtered_faces(vertexFaces(*m.filtered)),
        quality(*m.cad, RegionQualityParameters{c.metric, c.paths}) {
    const std::vector<std::uint8_t> rim = boundaryVertices(*m.filtered);
    for (std::size_t v = 0; v < rim.size(); ++v)
      if (rim[v]) filtered_rim_points.push_back(m.filtered->vertices.positions[v]);
    if (!filtered_rim_points.empty()) filtered_rim = std::make_unique<KdTree>(filtered_rim_points);
    if (c.patch) {
      cad_patches = std::make_unique<icr::ContactPatches>(cad_object, *c.patch);
      raw_patches = std::make_unique<icr::ContactPatches>(raw_object, *c.patch);
      filtered_patches = std::make_unique<icr::ContactPatches>(filtered_object, *c.patch);
    }
  }

  /// GraspRecord::seen_rim_distance_m of the mapped grasps.
  double seenRimDistance(const MeshOutcome& raw, const MeshOutcome& filtered) const {
    // A contact whose normal line reaches neither mesh lies beyond what the
    // views saw: on the rim or past it.
    if (raw.contacts.empty() || filtered.contacts.empty()) return 0.0;
    double nearest = std::numeric_limits<double>::infinity();
    if (!filtered_rim) return nearest;
    const auto visit = [&](const std::vector<int>& contacts, const TriangleMesh& mesh) {
      for (int c : contacts)  // mapped contacts are vertices (an unmapped grasp has none)
        nearest = std::min(
            nearest, filtered_rim->nearest(mesh.vertices.positions[static_cast<std::size_t>(c)], 1).front().distance);
    };
    visit(raw.contacts, *meshes.raw);
    visit(filtered.contacts, *meshes.filtered);
    return nearest;
  }

  /// Force closure, epsilon and whether the TWS fits, for mapped contacts.
  struct TaskCheck {
    bool fulfilled = false;
    double epsilon = 0.0;
    std::string reason;  ///< empty when fulfilled
  };
  TaskCheck checkTask(const std::vector<int>& contacts, double tws_radius, const icr::GraspableObject& object) const;
  MeshOutcome transfer(const std::vector<int>& cad_contacts, double tws_radius, const CadToScanMapping& mapping,
                       const icr::GraspableObject& object) const;
  SnappedOutcome snapToKeptVertices(const std::vector<int>& contacts, double tws_radius) const;
  RegionComparison compare(const std::vector<int>& cad_region, const CadRegionSummary& cad_summary,
                           const TriangleMesh& scan, const VertexFaces& scan_faces, const icr::ContactRegion& scan_region,
                           DistanceWorkspace& workspace, std::vector<int>* mapped_out = nullptr) const;
  /// One growth setting's raw and filtered regions, each compared with the
  /// CAD region of its finger (`summaries`: those regions' summaries).
  struct SettingComparison {
    std::vector<RegionComparison> raw, filtered;
    std::vector<std::vector<int>> raw_mapped, filtered_mapped;  ///< each region's vertices' CAD images
  };
  std::vector<CadRegionSummary> summarize(const icr::IcrResult& cad, DistanceWorkspace& workspace) const;
  SettingComparison compareSetting(const icr::IcrResult& cad, const std::vector<CadRegionSummary>& summaries,
                                   const icr::IcrResult& raw, const icr::IcrResult& filtered,
                                   DistanceWorkspace& workspace) const;
  /// Picks one vertex per region (as CAD vertices: `mapped` follows each
  /// region's vertex order), checks them on the CAD mesh; and the grasp of
  /// the regions' recommended contacts.
  PickCheck checkPicks(const std::vector<icr::ContactRegion>& regions, const std::vector<std::vector<int>>& mapped,
                       double tws_radius, std::uint64_t seed) const;
  /// The patch-contact study of an evaluated grasp (ExperimentConfig::patch).
  PatchRecord evaluatePatch(const GraspRecord& record, DistanceWorkspace& workspace) const;
  GraspRecord evaluate(std::size_t set, std::size_t index, DistanceWorkspace& workspace) const;
};

DatasetExperiment::Impl::TaskCheck DatasetExperiment::Impl::checkTask(const std::vector<int>& contacts,
                                                                     double tws_radius,
                                                                     const icr::GraspableObject& object) const {
  TaskCheck check;
  const icr::GraspWrenchSpace gws = icr::graspWrenchSpace(object, contacts, model);
  check.epsilon = gws.force_closure ? gws.epsilon : 0.0;
  check.fulfilled = holdsTask(gws, tws_radius);
  if (!check.fulfilled)
    check.reason = gws.force_closure ? "the GWS does not hold the TWS (epsilon below alpha x the CAD epsilon)"
                                     : "not force closure: " + gws.reason;
  return check;
}

MeshOutcome DatasetExperiment::Impl::transfer(const std::vector<int>& cad_contacts, double tws_radius,
                                              const CadToScanMapping& mapping,
                                              const icr::GraspableObject& object) const {
  MeshOutcome outcome;
  const TriangleMesh& cad = *meshes.cad;
  for (std::size_t k = 0; k < cad_contacts.size(); ++k) {
    const auto v = static_cast<std::size_t>(cad_contacts[k]);
    const VertexImage image = mapping.map(cad.vertices.positions[v], cad.vertices.normals[v]);
    if (image.vertex < 0) {
      outcome.contacts.clear();
      outcome.reason = fingerName(k) + ": the reconstructed mesh is not within reach of the CAD normal line";
      return outcome;
    }
    outcome.contacts.push_back(image.vertex);
  }
  for (std::size_t k = 0; k < outcome.contacts.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (outcome.contacts[k] == outcome.contacts[j]) {
        outcome.reason = fingerName(j) + " and " + fingerName(k) + " map to the same vertex";
        return outcome;
      }
  for (std::size_t k = 0; k < outcome.contacts.size(); ++k)
    if (object.excluded(static_cast<std::size_t>(outcome.contacts[k]))) {
      outcome.preselection_passed = false;
      outcome.reason = fingerName(k) + " lands on a vertex excluded by the preselection";
      break;
    }
  const TaskCheck task = checkTask(outcome.contacts, tws_radius, object);
  outcome.epsilon = task.epsilon;
  outcome.task_fulfilled = task.fulfilled;
  if (outcome.reason.empty()) outcome.reason = task.reason;
  return outcome;
}

SnappedOutcome DatasetExperiment::Impl::snapToKeptVertices(const std::vector<int>& contacts,
                                                           double tws_radius) const {
  SnappedOutcome snapped;
  SnappedContacts moved = filtered_snapping.snap(contacts);
  snapped.contacts = std::move(moved.contacts);
  snapped.move_distances_m = std::move(moved.move_distances_m);
  snapped.reason = std::move(moved.reason);
  if (!snapped.reason.empty()) return snapped;
  // The same task check as the strict G^F's, on the same object.
  const TaskCheck task = checkTask(snapped.contacts, tws_radius, filtered_object);
  snapped.epsilon = task.epsilon;
  snapped.task_fulfilled = task.fulfilled;
  snapped.reason = task.reason;
  return snapped;
}

RegionComparison DatasetExperiment::Impl::compare(const std::vector<int>& cad_region,
                                                  const CadRegionSummary& cad_summary, const TriangleMesh& scan,
                                                  const VertexFaces& scan_faces,
                                                  const icr::ContactRegion& scan_region,
                                                  DistanceWorkspace& workspace, std::vector<int>* mapped_out) const {
  const RegionIntersection intersection = estimator.estimate(cad_region, scan, scan_faces, scan_region.vertices);
  if (mapped_out) *mapped_out = intersection.mapped_vertices;
  RegionComparison c;
  c.vertices = scan_region.vertices.size();
  const int image = recommendedImage(scan_region, intersection.mapped_vertices);
  c.recommended_inside = image >= 0 && std::binary_search(cad_region.begin(), cad_region.end(), image);
  c.area_m2 = intersection.scan_region_area_m2;
  c.intersection_area_m2 = intersection.intersection_area_m2;
  c.false_positive_area_m2 = intersection.false_positive_area_m2;
  if (intersection.cad_region_area_m2 > 0.0) {
    c.intersection_percent = 100.0 * intersection.intersection_area_m2 / intersection.cad_region_area_m2;
    c.false_positive_percent = 100.0 * intersection.false_positive_area_m2 / intersection.cad_region_area_m2;
  }
  std::vector<int> mapped;
  mapped.reserve(intersection.mapped_vertices.size());
  for (const int v : intersection.mapped_vertices)
    if (v >= 0) mapped.push_back(v);
  const RegionQuality q = quality.evaluate(cad_summary, mapped, workspace);
  c.d1_m = q.d1_m;
  c.d2_m = q.d2_m;
  c.quality = q.quality;
  return c;
}

std::vector<CadRegionSummary> DatasetExperiment::Impl::summarize(const icr::IcrResult& cad,
                                                                DistanceWorkspace& workspace) const {
  std::vector<CadRegionSummary> summaries;
  for (const icr::ContactRegion& region : cad.regions) summaries.push_back(quality.summarize(region.vertices, workspace));
  return summaries;
}

DatasetExperiment::Impl::SettingComparison DatasetExperiment::Impl::compareSetting(
    const icr::IcrResult& cad, const std::vector<CadRegionSummary>& summaries, const icr::IcrResult& raw,
    const icr::IcrResult& filtered, DistanceWorkspace& workspace) const {
  const std::size_t fingers = cad.regions.size();
  SettingComparison c;
  c.raw_mapped.resize(fingers);
  c.filtered_mapped.resize(fingers);
  for (std::size_t n = 0; n < fingers; ++n) {
    const std::vector<int>& cad_region = cad.regions[n].vertices;
    c.raw.push_back(compare(cad_region, summaries[n], *meshes.raw, raw_faces, raw.regions[n], workspace, &c.raw_mapped[n]));
    c.filtered.push_back(compare(cad_region, summaries[n], *meshes.filtered, filtered_faces, filtered.regions[n],
                                 workspace, &c.filtered_mapped[n]));
  }
  return c;
}

PickCheck DatasetExperiment::Impl::checkPicks(const std::vector<icr::ContactRegion>& regions,
                                              const std::vector<std::vector<int>>& mapped, double tws_radius,
                                              std::uint64_t seed) const {
  PickCheck check;
  for (const icr::ContactRegion& r : regions)
    if (r.vertices.empty()) return check;
  std::mt19937_64 random(seed);
  for (std::size_t t = 0; t < config.picks_per_grasp; ++t) {
    ++check.tried;
    std::vector<int> cad_contacts;
    for (std::size_t n = 0; n < regions.size(); ++n) {
      const std::size_t k = std::uniform_int_distribution<std::size_t>(0, regions[n].vertices.size() - 1)(random);
      cad_contacts.push_back(k < mapped[n].size() ? mapped[n][k] : -1);
    }
    const std::set<int> distinct(cad_contacts.begin(), cad_contacts.end());
    if (distinct.count(-1) > 0 || distinct.size() < cad_contacts.size()) continue;
    ++check.mapped;
    if (checkTask(cad_contacts, tws_radius, cad_object).fulfilled) ++check.held;
  }
  const std::vector<int> aimed = aimedCadContacts(regions, mapped);
  check.aimed_held = !aimed.empty() && checkTask(aimed, tws_radius, cad_object).fulfilled;
  return check;
}

PatchRecord DatasetExperiment::Impl::evaluatePatch(const GraspRecord& record, DistanceWorkspace& workspace) const {
  PatchRecord study;
  // The TWS radius is set once the CAD patch epsilon is known; the hull
  // options are the ones the regions are grown with.
  icr::IcrParameters params = config.icrParameters(0.0);
  study.radius_m = config.patch->radius_m;
  study.filter_border = config.patch->filter_border;
  // The hull is nearly all of a patch ICR's cost (seconds on dense meshes):
  // each prototype's is built once, checked against the task, then grown from.
  struct Prototype {
    icr::GraspWrenchSpace gws;
    std::vector<int> owners;  // contact index of every wrench
  };
  const auto build = [&](const icr::ContactPatches& patches, const std::vector<int>& contacts) {
    Prototype p;
    p.gws = icr::patchGraspWrenchSpace(patches, contacts, model, params.hull, &p.owners);
    return p;
  };
  const Prototype cad = build(*cad_patches, record.cad_contacts);
  // Every patch holds its centre, so the patch GWS holds the plain one and
  // the CAD grasp stays force closure; guarded all the same.
  if (!cad.gws.force_closure) {
    study.raw.reason = study.filtered.reason = "the CAD grasp's patch GWS is not force closure: " + cad.gws.reason;
    return study;
  }
  study.cad_epsilon = cad.gws.epsilon;
  study.tws_radius = config.alpha * cad.gws.epsilon;
  const auto checkMesh = [&](const Prototype& p, PatchMeshOutcome& mesh) {
    mesh.epsilon = p.gws.force_closure ? p.gws.epsilon : 0.0;
    mesh.task_fulfilled = holdsTask(p.gws, study.tws_radius);
    if (!mesh.task_fulfilled)
      mesh.reason = p.gws.force_closure ? "the patch GWS does not hold the TWS (epsilon below alpha x the CAD patch epsilon)"
                                        : "the patch grasp is not force closure: " + p.gws.reason;
  };
  const Prototype raw = build(*raw_patches, record.raw.contacts);
  const Prototype filtered = build(*filtered_patches, record.filtered.contacts);
  checkMesh(raw, study.raw);
  checkMesh(filtered, study.filtered);
  if (!study.raw.task_fulfilled || !study.filtered.task_fulfilled) return study;

  params.tws_radius = study.tws_radius;
  const icr::IcrResult cad_regions =
      icr::computePatchContactRegions(cad_object, *cad_patches, record.cad_contacts, cad.gws, cad.owners, params);
  const icr::IcrResult raw_regions =
      icr::computePatchContactRegions(raw_object, *raw_patches, record.raw.contacts, raw.gws, raw.owners, params);
  const icr::IcrResult filtered_regions = icr::computePatchContactRegions(
      filtered_object, *filtered_patches, record.filtered.contacts, filtered.gws, filtered.owners, params);
  study.evaluated = true;
  for (const icr::ContactRegion& region : cad_regions.regions) study.cad_region_areas_m2.push_back(region.area_m2);
  SettingComparison compared =
      compareSetting(cad_regions, summarize(cad_regions, workspace), raw_regions, filtered_regions, workspace);
  study.raw.regions = std::move(compared.raw);
  study.filtered.regions = std::move(compared.filtered);
  const auto aimedHeld = [&](const icr::IcrResult& regions, const std::vector<std::vector<int>>& mapped) {
    const std::vector<int> aimed = aimedCadContacts(regions.regions, mapped);
    if (aimed.empty()) return false;
    return holdsTask(icr::patchGraspWrenchSpace(*cad_patches, aimed, model, params.hull), study.tws_radius);
  };
  study.raw.aimed_held = aimedHeld(raw_regions, compared.raw_mapped);
  study.filtered.aimed_held = aimedHeld(filtered_regions, compared.filtered_mapped);
  return study;
}

GraspRecord DatasetExperiment::Impl::evaluate(std::size_t set, std::size_t index,
                                              DistanceWorkspace& workspace) const {
  const TestSet& test_set = test_sets[set];
  const icr::SampledGrasp& grasp = test_set.grasps[index];
  GraspRecord record;
  record.dataset = meshes.name;
  record.fingers = test_set.fingers;
  record.index = index;
  record.cad_contacts = grasp.contacts;
  record.cad_epsilon = grasp.epsilon;
  record.tws_radius = config.alpha * grasp.epsilon;
  record.raw = transfer(grasp.contacts, record.tws_radius, to_raw, raw_object);
  record.filtered = transfer(grasp.contacts, record.tws_radius, to_filtered, filtered_object);
  record.seen_rim_distance_m = seenRimDistance(record.raw, record.filtered);
  // Only beside the strict outcome: whatever it finds, the grasp is
  // evaluated below only when the strict G^F is eligible.
  if (config.snap_excluded_contacts && !record.filtered.preselection_passed)
    record.filtered.snapped = snapToKeptVertices(record.filtered.contacts, record.tws_radius);
  if (!record.raw.eligible() || !record.filtered.eligible()) return record;

  const icr::IcrParameters params = config.icrParameters(record.tws_radius);
  const icr::IcrResult cad = icr::computeIndependentContactRegions(cad_object, grasp.contacts, params);
  const icr::IcrResult raw = icr::computeIndependentContactRegions(raw_object, record.raw.contacts, params);
  const icr::IcrResult filtered = icr::computeIndependentContactRegions(filtered_object, record.filtered.contacts, params);
  record.evaluated = true;
  for (const icr::ContactRegion& region : cad.regions) record.cad_region_areas_m2.push_back(region.area_m2);
  // The CAD regions are summarised once: every growth setting is compared with them.
  const std::vector<CadRegionSummary> summaries = summarize(cad, workspace);
  SettingComparison plain = compareSetting(cad, summaries, raw, filtered, workspace);
  record.raw.regions = std::move(plain.raw);
  record.filtered.regions = std::move(plain.filtered);
  // One seed per grasp and growth setting: the picks do not depend on which
  // thread or shard evaluates the grasp.
  const auto pickSeed = [&](std::size_t setting, std::size_t mesh) {
    return ((config.seed * 1000003 + record.fingers) * 1000003 + index) * 1000003 + setting * 2 + mesh;
  };
  if (config.picks_per_grasp > 0) {
    record.raw.picks = checkPicks(raw.regions, plain.raw_mapped, record.tws_radius, pickSeed(0, 0));
    record.filtered.picks = checkPicks(filtered.regions, plain.filtered_mapped, record.tws_radius, pickSeed(0, 1));
  }
  for (const double k : config.conservative_sigmas) {
    icr::IcrParameters conservative = params;
    conservative.conservative = icr::ConservativeGrowth{};
    conservative.conservative->sigmas = k;
    const icr::IcrResult raw_k = icr::computeIndependentContactRegions(raw_object, record.raw.contacts, conservative);
    const icr::IcrResult filtered_k =
        icr::computeIndependentContactRegions(filtered_object, record.filtered.contacts, conservative);
    SettingComparison compared = compareSetting(cad, summaries, raw_k, filtered_k, workspace);
    ConservativeOutcome raw_outcome{k, std::move(compared.raw), {}}, filtered_outcome{k, std::move(compared.filtered), {}};
    if (config.picks_per_grasp > 0) {
      const std::size_t setting = 1 + record.raw.conservative.size();
      raw_outcome.picks = checkPicks(raw_k.regions, compared.raw_mapped, record.tws_radius, pickSeed(setting, 0));
      filtered_outcome.picks =
          checkPicks(filtered_k.regions, compared.filtered_mapped, record.tws_radius, pickSeed(setting, 1));
    }
    record.raw.conservative.push_back(std::move(raw_outcome));
    record.filtered.conservative.push_back(std::move(filtered_outcome));
  }
  if (config.patch) record.patch = evaluatePatch(record, workspace);
  return record;
}

namespace {

icr::WrenchFrame cadFrame(const DatasetMeshes& meshes, const ExperimentConfig& config) {
  config.validate();
  requireNormals(meshes.cad, "CAD mesh");
  requireNormals(meshes.raw, "raw mesh");
  requireNormals(meshes.filtered, "filtered mesh");
  return commonWrenchFrame(*meshes.cad);
}

}  // namespace

DatasetExperiment::DatasetExperiment(const DatasetMeshes& meshes, const ExperimentConfig& config)
    : impl_(std::make_unique<Impl>(meshes, config, cadFrame(meshes, config))) {
  for (const std::size_t fingers : config.finger_counts) {
    icr::GraspSamplingParameters sampling;
    sampling.fingers = fingers;
    sampling.count = config.grasps_per_set;
    sampling.seed = config.seed * 1000 + fingers;
    sampling.max_attempts = config.max_sampling_attempts;
    impl_->test_sets.push_back({fingers, icr::sampleForceClosureGrasps(impl_->cad_object, impl_->model, sampling)});
  }
}

DatasetExperiment::~DatasetExperiment() = default;

std::size_t DatasetExperiment::itemCount() const {
  std::size_t total = 0;
  for (const auto& set : impl_->test_sets) total += set.grasps.size();
  return total;
}

double DatasetExperiment::cadLambda() const { return impl_->frame.lambda; }

const DatasetMeshes& DatasetExperiment::meshes() const { return impl_->meshes; }

std::size_t DatasetExperiment::sampledGrasps(std::size_t fingers) const {
  for (const auto& set : impl_->test_sets)
    if (set.fingers == fingers) return set.grasps.size();
  return 0;
}

PlannedGraspStudy DatasetExperiment::plannedGrasps(planning::PlanningParameters planning,
                                                  const PlannedExecutionParameters& execution) const {
  if (planning.finger_counts.empty())
    throw InputError("PlanningParameters::finger_counts", "", "expected at least one finger count");
  PlannedGraspStudy study;
  study.dataset = impl_->meshes.name;
  study.fingers = planning.finger_counts.front();
  std::vector<double> epsilons;
  for (const auto& set : impl_->test_sets)
    if (set.fingers == study.fingers)
      for (const auto& g : set.grasps) epsilons.push_back(g.epsilon);
  if (epsilons.empty()) {
    icr::GraspSamplingParameters sampling;
    sampling.fingers = study.fingers;
    sampling.count = impl_->config.grasps_per_set;
    sampling.seed = impl_->config.seed * 1000 + study.fingers;
    sampling.max_attempts = impl_->config.max_sampling_attempts;
    for (const auto& g : icr::sampleForceClosureGrasps(impl_->cad_object, impl_->model, sampling))
      epsilons.push_back(g.epsilon);
  }
  study.cad_grasps = epsilons.size();
  if (epsilons.empty()) throw InputError(study.dataset, "", "no force-closure grasp on the CAD mesh to set the task");
  std::sort(epsilons.begin(), epsilons.end());
  const std::size_t n = epsilons.size();
  const double median = n % 2 ? epsilons[n / 2] : 0.5 * (epsilons[n / 2 - 1] + epsilons[n / 2]);
  study.tws_radius = 0.5 * median;
  planning.regions.contact_model = impl_->model;
  planning.regions.tws_radius = study.tws_radius;
  planning.regions.tws_wrenches.reset();

  const ScanToCadMapping to_cad(*impl_->meshes.cad, impl_->config.mapping);
  const auto run = [&](const icr::GraspableObject& scan, const planning::PlanningParameters& p, const char* mesh,
                       std::size_t keep_first) {
    PlannedMeshStudy s;
    s.mesh = mesh;
    const auto start = std::chrono::steady_clock::now();
    planning::PlanResult plan;
    try {
      plan = planning::planGrasps(scan, p);
    } catch (const InputError& error) {
      s.error = error.detail();
      return s;
    }
    if (keep_first > 0) keepFirstDrawn(plan, keep_first);
    s.plan_ms = millisecondsSince(start);
    PlannedMeshStudy executed = executePlanOnCad(plan, scan, to_cad, impl_->cad_object, impl_->model, execution);
    executed.mesh = s.mesh;
    executed.plan_ms = s.plan_ms;
    return executed;
  };
  const planning::PlanningParameters baseline = randomBaselineParameters(planning, planning.top);
  study.raw = run(impl_->raw_object, planning, "raw", 0);
  study.filtered = run(impl_->filtered_object, planning, "filtered", 0);
  study.raw_random = run(impl_->raw_object, baseline, "raw_random", planning.top);
  study.filtered_random = run(impl_->filtered_object, baseline, "filtered_random", planning.top);
  return study;
}

std::vector<GraspRecord> DatasetExperiment::run(std::size_t begin, std::size_t end,
                                                const ProgressCallback& progress) const {
  end = std::min(end, itemCount());
  if (begin >= end) return {};
  std::vector<std::pair<std::size_t, std::size_t>> items;  // (set, index)
  std::size_t position = 0;
  for (std::size_t s = 0; s < impl_->test_sets.size(); ++s)
    for (std::size_t i = 0; i < impl_->test_sets[s].grasps.size(); ++i, ++position)
      if (position >= begin && position < end) items.emplace_back(s, i);

  std::vector<GraspRecord> records(items.size());
  tbb::enumerable_thread_specific<DistanceWorkspace> workspaces;
  std::atomic<std::size_t> done{0};
  std::mutex progress_mutex;
  tbb::parallel_for(std::size_t{0}, items.size(), [&](std::size_t k) {
    records[k] = impl_->evaluate(items[k].first, items[k].second, workspaces.local());
    const std::size_t finished = ++done;
    if (progress) {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress("grasps", finished, items.size());
    }
  });
  std::sort(records.begin(), records.end());
  return records;
}

}  // namespace icrkit::eval
