// Independent Contact Regions without any file: build a sphere in memory,
// give it vertex normals, sample a force-closure grasp and grow its regions.
// Exits non-zero when a result is not what an ICR must be.

#include <icrkit/core/mesh_primitives.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/icr/grasp_sampling.hpp>
#include <icrkit/icr/graspable_object.hpp>
#include <icrkit/icr/independent_contact_regions.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

namespace {

// A geodesic sphere (near-uniform vertices, unlike a UV sphere whose poles
// would crowd the grasp sampling), built in memory by icrkit::core.
icrkit::TriangleMesh icosphere(double radius, int levels) { return icrkit::makeIcosphere(levels, radius); }

int check(bool ok, const char* what) {
  if (!ok) std::fprintf(stderr, "icr_in_memory: FAILED: %s\n", what);
  return ok ? 0 : 1;
}

}  // namespace

int main() {
  icrkit::TriangleMesh mesh = icosphere(0.05, 3);
  icrkit::computeVertexNormals(mesh);
  std::printf("mesh: %zu vertices, %zu faces\n", mesh.vertexCount(), mesh.faceCount());

  // One frame for sampling and regions: epsilon depends on it.
  const icrkit::icr::GraspableObject object = icrkit::icr::GraspableObject::withDefaultFrame(mesh);
  icrkit::icr::ContactModel model;  // frictional, mu = 0.8, 8 cone edges
  icrkit::icr::GraspSamplingParameters sampling;
  sampling.fingers = 4;
  sampling.count = 1;
  sampling.seed = 1;
  icrkit::icr::GraspSamplingStatistics statistics;
  const auto grasps = icrkit::icr::sampleForceClosureGrasps(object, model, sampling, &statistics);
  if (check(grasps.size() == 1, "no force-closure grasp was found")) return 1;
  const icrkit::icr::SampledGrasp& grasp = grasps.front();
  std::printf("grasp: contacts %d %d %d %d, epsilon %.6g, after %zu attempts\n", grasp.contacts[0], grasp.contacts[1],
              grasp.contacts[2], grasp.contacts[3], grasp.epsilon, statistics.attempts);

  icrkit::icr::IcrParameters params;
  params.contact_model = model;
  params.alpha = 0.5;
  const icrkit::icr::IcrResult result = icrkit::icr::computeIndependentContactRegions(object, grasp.contacts, params);
  std::printf("epsilon %.6g, TWS radius %.6g, %zu GWS facets\n", result.epsilon, result.tws_radius, result.gws_facets);

  int failures = 0;
  failures += check(std::abs(result.epsilon - grasp.epsilon) <= 1e-12 * std::max(1.0, grasp.epsilon),
                    "the regions' epsilon differs from the sampled grasp's");
  failures += check(std::abs(result.tws_radius - 0.5 * result.epsilon) <= 1e-12, "TWS radius is not alpha * epsilon");
  failures += check(result.regions.size() == 4, "expected one region per finger");
  for (const icrkit::icr::ContactRegion& region : result.regions) {
    std::printf("finger %zu: contact %d, %zu vertices, %.6g m2\n", region.finger, region.contact,
                region.vertices.size(), region.area_m2);
    failures += check(std::binary_search(region.vertices.begin(), region.vertices.end(), region.contact),
                      "a region lacks its own contact");
    failures += check(std::is_sorted(region.vertices.begin(), region.vertices.end()), "a region is not sorted");
    failures += check(region.vertices.size() > 1, "a region did not grow beyond its contact");
  }
  return failures == 0 ? 0 : 1;
}
