#pragma once
/// \file
/// The Fig. 6 picture of one evaluated grasp: the CAD mesh with its regions'
/// intersected (I_n) and missed parts, above the reconstructed mesh with its
/// regions' inside and false-positive parts, from the same cameras, with the
/// prototype contacts and the regions' central points as dots. Used by
/// `icrkit evaluate/paper --renders N` (RUN_DIR/renders/) for the report and
/// by `icrkit render --compare` from the cameras it is given.

#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/intersection_estimation.hpp>
#include <icrkit/report/mesh_render.hpp>

#include <string>
#include <vector>

namespace icrkit::report {

struct GraspRenderParameters {
  int view_width = 480;   ///< pixels per view
  int view_height = 360;
  int views = 3;          ///< orbit views around the CAD mesh (front first)
  int samples_per_axis = 2;
  bool central_points = true;
};

/// The geodesic central point of each region (Fig. 7), -1 for an empty one.
std::vector<int> regionCentralPoints(const TriangleMesh& mesh, const std::vector<std::vector<int>>& regions);

/// The dots of a grasp picture, sized for views `view_width` pixels wide:
/// central points (white, dark ring; skipped when -1), then contacts (dark,
/// white ring) on top, so both stand out on every palette colour and differ
/// from each other.
std::vector<Marker> graspMarkers(const TriangleMesh& mesh, const std::vector<int>& contacts,
                                 const std::vector<int>& central_points, int view_width);

/// Legend entries of those dots (contacts; central points when asked).
std::vector<LegendEntry> graspMarkerLegend(bool central_points);

/// The regions picture of one mesh (`icrkit render` without --compare).
struct RegionPicture {
  RgbImage image;
  std::vector<int> central_points;  ///< per region, -1 when empty or not marked
  int columns = 0;                  ///< views per row, as tiled
};

/// Views of `mesh` from `cameras`, each captioned with its camera's name:
/// regions[n] coloured as finger fingers[n] (fingerColour), the prototype
/// `contacts` and (with `central_points`) each region's geodesic central
/// point as dots; tiled `columns` per row (<= 0: about square), then a
/// legend (the fingers in ascending order, then the dots when there are
/// contacts or regions). Progress: "render", one step per view.
RegionPicture renderRegionViews(const TriangleMesh& mesh, const std::vector<int>& fingers,
                                const std::vector<std::vector<int>>& regions, const std::vector<int>& contacts,
                                const std::vector<RenderCamera>& cameras, const RenderStyle& style, int columns,
                                bool central_points, const ProgressCallback& progress = {});

/// How a comparison picture is laid out.
struct ComparisonLayout {
  int columns = 0;                             ///< views per row; <= 0: every view in one row
  std::string cad_caption = "CAD";             ///< each view's caption: "<caption>: <camera name>"
  std::string scan_caption = "reconstructed";
  bool central_points = true;                  ///< mark the regions' central points
};

/// The comparison picture from the given cameras: rows of `layout.columns`
/// CAD views (I_n green, the rest of each CAD region blue), each row followed
/// by the same views of the reconstruction (inside the CAD region green,
/// false positive vermillion), short rows padded white, and the legend.
/// `intersections[n]` is Algorithm 2's result for `cad_regions[n]` against
/// `scan_regions[n]`. The meshes share a frame, so one set of cameras puts a
/// place of the object at the same pixel in both rows. Progress: "render".
RgbImage renderRegionComparison(const TriangleMesh& cad, const std::vector<std::vector<int>>& cad_regions,
                                const std::vector<int>& cad_contacts, const TriangleMesh& scan,
                                const std::vector<std::vector<int>>& scan_regions,
                                const std::vector<int>& scan_contacts,
                                const std::vector<eval::RegionIntersection>& intersections,
                                const std::vector<RenderCamera>& cameras, const RenderStyle& style,
                                const ComparisonLayout& layout = {}, const ProgressCallback& progress = {});

/// `cad_regions[n]` and `scan_regions[n]` are finger n's regions (same
/// finger order), `cad_contacts` / `scan_contacts` the prototype grasps.
/// `scan_label` names the reconstruction in the captions ("filtered", "raw").
/// The CAD mesh needs unit vertex normals. Throws InputError for mismatched
/// region counts or indices out of range. The views orbit the CAD mesh
/// (renderRegionComparison in one row per mesh).
RgbImage renderGraspComparison(const TriangleMesh& cad, const std::vector<std::vector<int>>& cad_regions,
                               const std::vector<int>& cad_contacts, const TriangleMesh& scan,
                               const std::vector<std::vector<int>>& scan_regions,
                               const std::vector<int>& scan_contacts, const std::string& scan_label,
                               const GraspRenderParameters& params = {});

/// The Fig. 6 pictures (CAD vs filtered, CAD vs raw) of the first `count`
/// evaluated records of `meshes` (regions regrown: eval::regrowRegions),
/// written to eval::RunFolder{directory}.render(record, label); returns the
/// files in the order written.
std::vector<std::string> writeGraspRenders(const std::string& directory, const eval::DatasetMeshes& meshes,
                                           const eval::ExperimentConfig& config,
                                           const std::vector<eval::GraspRecord>& records, int count);

}  // namespace icrkit::report
