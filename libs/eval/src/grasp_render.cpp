#include <icrkit/eval/grasp_render.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/eval/mesh_distances.hpp>
#include <icrkit/eval/region_quality.hpp>

#include <algorithm>

namespace icrkit::eval {
namespace {

const Eigen::Vector3f kContact(0.1f, 0.1f, 0.1f);
const Eigen::Vector3f kCentre(1.0f, 1.0f, 1.0f);

// Contacts dark with a white ring, central points white with a dark ring:
// both stand out on every palette colour and differ from each other.
std::vector<Marker> markers(const TriangleMesh& mesh, const std::vector<int>& contacts,
                            const std::vector<std::vector<int>>& regions, bool central_points, int width) {
  const double radius = std::max(3.0, width / 100.0);
  std::vector<Marker> out;
  if (central_points) {
    const MeshDistanceGraph graph(mesh);
    DistanceWorkspace workspace;
    for (const auto& region : regions) {
      if (region.empty()) continue;
      const int centre = centralPoint(graph, region, DistanceMetric::Geodesic, workspace).vertex;
      if (centre < 0) continue;
      Marker m;
      m.position = mesh.vertices.positions[static_cast<std::size_t>(centre)];
      m.colour = kCentre;
      m.outline_colour = kContact;
      m.radius_px = 0.8 * radius;
      out.push_back(m);
    }
  }
  for (const int c : contacts) {
    if (c < 0 || static_cast<std::size_t>(c) >= mesh.vertexCount()) continue;
    Marker m;
    m.position = mesh.vertices.positions[static_cast<std::size_t>(c)];
    m.colour = kContact;
    m.radius_px = radius;
    out.push_back(m);
  }
  return out;
}

}  // namespace

RgbImage renderGraspComparison(const TriangleMesh& cad, const std::vector<std::vector<int>>& cad_regions,
                               const std::vector<int>& cad_contacts, const TriangleMesh& scan,
                               const std::vector<std::vector<int>>& scan_regions,
                               const std::vector<int>& scan_contacts, const std::string& scan_label,
                               const GraspRenderParameters& params) {
  if (cad_regions.size() != scan_regions.size())
    throw InputError("grasp render", "regions",
                     "the CAD mesh has " + std::to_string(cad_regions.size()) + " regions, the " + scan_label +
                         " mesh " + std::to_string(scan_regions.size()));
  const IntersectionEstimator estimator(cad);
  std::vector<std::vector<int>> faces;
  std::vector<std::vector<std::uint8_t>> inside;
  for (std::size_t n = 0; n < cad_regions.size(); ++n) {
    RegionIntersection r = estimator.estimate(cad_regions[n], scan, scan_regions[n]);
    faces.push_back(std::move(r.intersection_faces));
    inside.push_back(std::move(r.inside));
  }
  RenderStyle style;
  style.width = params.view_width;
  style.height = params.view_height;
  style.samples_per_axis = params.samples_per_axis;
  SurfaceColours cad_colours, scan_colours;
  cad_colours.per_face = cadComparisonColours(cad, cad_regions, faces, style.base_colour);
  scan_colours.per_corner = scanComparisonColours(scan, scan_regions, inside, style.base_colour);

  OrbitParameters orbit;
  orbit.count = params.views;
  orbit.aspect = static_cast<double>(params.view_width) / params.view_height;
  // One set of cameras for both rows: the meshes share a frame, so one place
  // of the object sits at the same pixel in both.
  const std::vector<RenderCamera> cameras = orbitCameras(cad, orbit);
  const MeshRenderer cad_renderer(cad), scan_renderer(scan);
  const auto cad_markers = markers(cad, cad_contacts, cad_regions, params.central_points, params.view_width);
  const auto scan_markers = markers(scan, scan_contacts, scan_regions, params.central_points, params.view_width);
  std::vector<RgbImage> tiles;
  for (const RenderCamera& camera : cameras) {
    RgbImage image = cad_renderer.render(camera, style, cad_colours, cad_markers);
    drawCaption(image, "CAD: " + camera.name);
    tiles.push_back(std::move(image));
  }
  for (const RenderCamera& camera : cameras) {
    RgbImage image = scan_renderer.render(camera, style, scan_colours, scan_markers);
    drawCaption(image, scan_label + ": " + camera.name);
    tiles.push_back(std::move(image));
  }
  const ComparisonPalette palette;
  std::vector<LegendEntry> legend{{palette.intersection, "I_n / inside the CAD region", false},
                                  {palette.missed, "CAD region outside I_n", false},
                                  {palette.false_positive, "false positive", false},
                                  {kContact, "prototype contact", true}};
  if (params.central_points) legend.push_back({kCentre, "central point", true});
  return appendLegend(tileImages(tiles, static_cast<int>(cameras.size())), legend);
}

}  // namespace icrkit::eval
