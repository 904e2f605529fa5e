#pragma once
/// \file
/// The Fig. 6 picture of one evaluated grasp: the CAD mesh with its regions'
/// intersected (I_n) and missed parts, above the reconstructed mesh with its
/// regions' inside and false-positive parts, from the same cameras, with the
/// prototype contacts and the regions' central points as dots. Used by
/// `icrkit evaluate/paper --renders N` (RUN_DIR/renders/) for the report.

#include <icrkit/core/triangle_mesh.hpp>
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

/// `cad_regions[n]` and `scan_regions[n]` are finger n's regions (same
/// finger order), `cad_contacts` / `scan_contacts` the prototype grasps.
/// `scan_label` names the reconstruction in the captions ("filtered", "raw").
/// The CAD mesh needs unit vertex normals. Throws InputError for mismatched
/// region counts or indices out of range.
RgbImage renderGraspComparison(const TriangleMesh& cad, const std::vector<std::vector<int>>& cad_regions,
                               const std::vector<int>& cad_contacts, const TriangleMesh& scan,
                               const std::vector<std::vector<int>>& scan_regions,
                               const std::vector<int>& scan_contacts, const std::string& scan_label,
                               const GraspRenderParameters& params = {});

}  // namespace icrkit::report
