#include <icrkit/report/grasp_render.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/eval/geodesic_distances.hpp>
#include <icrkit/eval/grasp_regions.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/eval/region_quality.hpp>
#include <icrkit/eval/run_folder.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <tuple>

namespace icrkit::report {

using eval::centralPoint;
using eval::DistanceMetric;
using eval::DistanceWorkspace;
using eval::IntersectionEstimator;
using eval::MeshDistanceGraph;
using eval::RegionIntersection;
namespace {

const Eigen::Vector3f kContact(0.1f, 0.1f, 0.1f);
const Eigen::Vector3f kCentre(1.0f, 1.0f, 1.0f);

// One view per camera, each captioned "<prefix><camera name>"; `step` after each.
std::vector<RgbImage> captionedViews(const TriangleMesh& mesh, const std::vector<RenderCamera>& cameras,
                                     const RenderStyle& style, const SurfaceColours& colours,
                                     const std::vector<Marker>& markers, const std::string& prefix,
                                     const std::function<void()>& step) {
  const MeshRenderer renderer(mesh);
  std::vector<RgbImage> views;
  for (const RenderCamera& camera : cameras) {
    RgbImage view = renderer.render(camera, style, colours, markers);
    drawCaption(view, prefix + camera.name);
    views.push_back(std::move(view));
    step();
  }
  return views;
}

}  // namespace

std::vector<int> regionCentralPoints(const TriangleMesh& mesh, const std::vector<std::vector<int>>& regions) {
  std::vector<int> centres(regions.size(), -1);
  if (regions.empty()) return centres;
  const MeshDistanceGraph graph(mesh);
  DistanceWorkspace workspace;
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (!regions[r].empty()) centres[r] = centralPoint(graph, regions[r], DistanceMetric::Geodesic, workspace).vertex;
  return centres;
}

std::vector<Marker> graspMarkers(const TriangleMesh& mesh, const std::vector<int>& contacts,
                                 const std::vector<int>& central_points, int view_width) {
  // Dots grow with the image, from 4 px at 400 px wide.
  const double radius = std::max(3.0, view_width / 100.0);
  std::vector<Marker> markers;
  const auto add = [&](int vertex, const Eigen::Vector3f& fill, const Eigen::Vector3f& ring, double r) {
    if (vertex < 0 || static_cast<std::size_t>(vertex) >= mesh.vertexCount()) return;
    Marker m;
    m.position = mesh.vertices.positions[static_cast<std::size_t>(vertex)];
    m.colour = fill;
    m.outline_colour = ring;
    m.radius_px = r;
    markers.push_back(m);
  };
  for (const int c : central_points) add(c, kCentre, kContact, 0.8 * radius);
  // Contacts last: on top when a contact is its region's central point.
  for (const int c : contacts) add(c, kContact, Marker{}.outline_colour, radius);
  return markers;
}

std::vector<LegendEntry> graspMarkerLegend(bool central_points) {
  std::vector<LegendEntry> legend{{kContact, "prototype contact", true}};
  if (central_points) legend.push_back({kCentre, "central point", true});
  return legend;
}

RegionPicture renderRegionViews(const TriangleMesh& mesh, const std::vector<int>& fingers,
                                const std::vector<std::vector<int>>& regions, const std::vector<int>& contacts,
                                const std::vector<RenderCamera>& cameras, const RenderStyle& style, int columns,
                                bool central_points, const ProgressCallback& progress) {
  if (fingers.size() != regions.size())
    throw InputError("regions", "",
                     "expected one finger per region, got " + std::to_string(fingers.size()) + " fingers for " +
                         std::to_string(regions.size()) + " regions");
  RegionPicture picture;
  picture.central_points = central_points ? regionCentralPoints(mesh, regions) : std::vector<int>(regions.size(), -1);
  SurfaceColours colours;
  if (!fingers.empty()) colours.per_vertex = regionColours(mesh, fingers, regions, style.base_colour);
  const std::vector<Marker> markers = graspMarkers(mesh, contacts, picture.central_points, style.width);
  std::size_t done = 0;
  const std::vector<RgbImage> views = captionedViews(mesh, cameras, style, colours, markers, "", [&] {
    if (progress) progress("render", ++done, cameras.size());
  });
  const int count = static_cast<int>(cameras.size());
  picture.columns =
      columns > 0 ? std::min(columns, count) : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  std::vector<LegendEntry> legend;
  std::vector<int> sorted = fingers;
  std::sort(sorted.begin(), sorted.end());
  for (int finger : sorted) legend.push_back({fingerColour(finger), "finger " + std::to_string(finger), false});
  if (!contacts.empty() || !fingers.empty())
    for (const LegendEntry& entry : graspMarkerLegend(central_points && !fingers.empty())) legend.push_back(entry);
  picture.image = appendLegend(tileImages(views, picture.columns), legend);
  return picture;
}

RgbImage renderRegionComparison(const TriangleMesh& cad, const std::vector<std::vector<int>>& cad_regions,
                                const std::vector<int>& cad_contacts, const TriangleMesh& scan,
                                const std::vector<std::vector<int>>& scan_regions,
                                const std::vector<int>& scan_contacts,
                                const std::vector<RegionIntersection>& intersections,
                                const std::vector<RenderCamera>& cameras, const RenderStyle& style,
                                const ComparisonLayout& layout, const ProgressCallback& progress) {
  if (cad_regions.size() != scan_regions.size() || intersections.size() != cad_regions.size())
    throw InputError("comparison render", "regions",
                     "the CAD mesh has " + std::to_string(cad_regions.size()) + " regions, the " +
                         layout.scan_caption + " mesh " + std::to_string(scan_regions.size()) + ", with " +
                         std::to_string(intersections.size()) + " intersections");
  std::vector<std::vector<int>> faces;
  std::vector<std::vector<std::uint8_t>> inside;
  for (const RegionIntersection& r : intersections) {
    faces.push_back(r.intersection_faces);
    inside.push_back(r.inside);
  }
  SurfaceColours cad_colours, scan_colours;
  cad_colours.per_face = cadComparisonColours(cad, cad_regions, faces, style.base_colour);
  scan_colours.per_corner = scanComparisonColours(scan, scan_regions, inside, style.base_colour);
  const auto centres = [&](const TriangleMesh& mesh, const std::vector<std::vector<int>>& regions) {
    return layout.central_points ? regionCentralPoints(mesh, regions) : std::vector<int>{};
  };
  const auto cad_markers = graspMarkers(cad, cad_contacts, centres(cad, cad_regions), style.width);
  const auto scan_markers = graspMarkers(scan, scan_contacts, centres(scan, scan_regions), style.width);

  const std::size_t views = cameras.size();
  std::size_t done = 0;
  const auto step = [&] {
    if (progress) progress("render", ++done, 2 * views);
  };
  const std::vector<RgbImage> cad_views =
      captionedViews(cad, cameras, style, cad_colours, cad_markers, layout.cad_caption + ": ", step);
  const std::vector<RgbImage> scan_views =
      captionedViews(scan, cameras, style, scan_colours, scan_markers, layout.scan_caption + ": ", step);

  const std::size_t columns = layout.columns > 0 ? static_cast<std::size_t>(layout.columns) : std::max<std::size_t>(views, 1);
  const std::size_t rows = (views + columns - 1) / columns;
  std::vector<RgbImage> tiles;
  for (std::size_t row = 0; row < rows; ++row)
    for (const auto* set : {&cad_views, &scan_views})
      for (std::size_t c = 0; c < columns; ++c) {
        const std::size_t i = row * columns + c;
        tiles.push_back(i < views ? (*set)[i] : RgbImage(style.width, style.height, {255, 255, 255}));
      }
  const ComparisonPalette palette;
  std::vector<LegendEntry> legend{{palette.intersection, "I_n / inside the CAD region", false},
                                  {palette.missed, "CAD region outside I_n", false},
                                  {palette.false_positive, "false positive", false}};
  for (const LegendEntry& entry : graspMarkerLegend(layout.central_points)) legend.push_back(entry);
  return appendLegend(tileImages(tiles, static_cast<int>(columns)), legend);
}

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
  std::vector<RegionIntersection> intersections;
  for (std::size_t n = 0; n < cad_regions.size(); ++n)
    intersections.push_back(estimator.estimate(cad_regions[n], scan, scan_regions[n]));
  RenderStyle style;
  style.width = params.view_width;
  style.height = params.view_height;
  style.samples_per_axis = params.samples_per_axis;
  OrbitParameters orbit;
  orbit.count = params.views;
  orbit.aspect = static_cast<double>(params.view_width) / params.view_height;
  ComparisonLayout layout;
  layout.scan_caption = scan_label;
  layout.central_points = params.central_points;
  return renderRegionComparison(cad, cad_regions, cad_contacts, scan, scan_regions, scan_contacts, intersections,
                                orbitCameras(cad, orbit), style, layout);
}

std::vector<std::string> writeGraspRenders(const std::string& directory, const eval::DatasetMeshes& meshes,
                                           const eval::ExperimentConfig& config,
                                           const std::vector<eval::GraspRecord>& records, int count) {
  std::vector<std::string> files;
  const eval::RunFolder folder{directory};
  int left = count;
  for (const eval::GraspRecord& record : records) {
    if (left <= 0) break;
    if (!record.evaluated || record.dataset != meshes.name) continue;
    --left;
    const eval::GraspRegions regions = eval::regrowRegions(meshes, config, record);
    std::filesystem::create_directories(folder.renders());
    for (const auto& [label, scan, scan_regions, contacts] :
         {std::tuple{std::string("filtered"), meshes.filtered, &regions.filtered, &record.filtered.contacts},
          std::tuple{std::string("raw"), meshes.raw, &regions.raw, &record.raw.contacts}}) {
      const RgbImage image =
          renderGraspComparison(*meshes.cad, regions.cad, record.cad_contacts, *scan, *scan_regions, *contacts, label);
      files.push_back(folder.render(record, label));
      writePng(files.back(), image);
    }
  }
  return files;
}

}  // namespace icrkit::report
