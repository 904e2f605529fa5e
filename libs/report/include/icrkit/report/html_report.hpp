#pragma once
/// \file
/// The self-contained HTML report of a run folder (`icrkit report`): run
/// parameters, Table I beside the paper's values, eligibility rates, the
/// Fig. 8 histograms, renders and a three.js viewer of the CAD, raw and
/// filtered meshes with one grasp's regions. Plain data in, one HTML string
/// out: the caller gathers the pieces (and says which files were missing);
/// nothing here reads files, and the page never fetches anything.

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/results_tables.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::report {

/// One mesh of the viewer, already reduced to what the page draws.
struct ReportMesh {
  std::string key;     ///< "cad", "raw" or "filtered" (checkbox ids)
  std::string label;   ///< "CAD", "raw", "filtered"
  std::string source;  ///< the file it came from, shown in the legend
  std::size_t source_vertices = 0, source_faces = 0;  ///< before any --max-faces cap
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<std::uint32_t, 3>> faces;
  /// Per vertex: the finger whose region holds it (the lowest one when
  /// regions overlap), -1 for none. Empty: no regions.
  std::vector<std::int8_t> region;
  /// Per finger: the contact's position on this mesh; unset when unmapped.
  std::vector<std::optional<std::array<float, 3>>> contacts;
};

/// Keeps at most `max_faces` faces of `mesh` (every k-th face, k =
/// ceil(faces / max_faces); 0 = keep all) and drops the vertices no kept face
/// uses. `regions` (one vertex list per finger, may be empty) become the
/// per-vertex finger ids; `contacts` (vertex ids, -1 = none) become
/// positions. Dropping faces leaves holes: it is a size cap, not a decimation.
ReportMesh makeReportMesh(const std::string& key, const std::string& label, const std::string& source,
                          const TriangleMesh& mesh, const std::vector<std::vector<int>>& regions,
                          const std::vector<int>& contacts, std::size_t max_faces);

struct ReportImage {
  std::string name;                 ///< file name, shown as caption
  std::vector<unsigned char> png;   ///< PNG bytes (embedded as a data: URI)
};

struct ReportSvg {
  std::string name;  ///< file name
  std::string svg;   ///< an SVG document (inlined; its XML declaration is dropped)
};

struct HtmlReportInput {
  std::string title = "icrkit report";
  std::string run_dir;
  std::string generated_by;                ///< e.g. "icrkit report" and its version
  std::string run_json;                    ///< run.json as text (pretty-printed in the page); empty if missing
  std::vector<std::pair<std::string, std::string>> parameters;  ///< key facts shown in the header
  std::optional<eval::TableOne> table;           ///< unset: Table I unavailable
  std::optional<eval::EligibilitySummary> eligibility;
  std::vector<ReportSvg> histograms;       ///< Fig. 8
  std::vector<ReportImage> renders;
  std::string renders_note;                ///< shown when `renders` is empty
  /// planned.jsonl's lines (eval/planned_grasps.hpp): the planned grasps
  /// executed on the CAD mesh beside the random baseline; empty: no section.
  std::vector<std::string> planned_lines;
  /// surface.jsonl's lines (eval/surface_accuracy.hpp): each reconstructed
  /// mesh's distance and normal error against the CAD mesh; empty: no section.
  std::vector<std::string> surface_lines;
  std::vector<std::string> missing;        ///< files the run folder lacks ("what" strings)
  std::vector<std::string> warnings;       ///< other problems worth stating (e.g. a mesh that failed to read)

  /// The viewer: one grasp on up to three meshes.
  std::vector<ReportMesh> meshes;
  std::string grasp_label;                 ///< e.g. "toy / 4 fingers / grasp 0"
  std::string viewer_note;                 ///< why there are no regions, etc.; empty if none
  std::size_t fingers = 0;                 ///< checkboxes for fingers 0..fingers-1

  /// three.js as vendored at build time; an empty module = viewer unavailable.
  std::string three_version;
  std::string three_module_base64;
  std::string orbit_controls_base64;
  std::string three_license;
};

/// Byte counts of what went into the page (reported by the command).
struct HtmlReportSizes {
  std::size_t total = 0;          ///< the whole HTML
  std::size_t meshes = 0;         ///< base64 of positions, faces and regions
  std::size_t renders = 0;        ///< base64 of the PNGs
  std::size_t threejs = 0;        ///< base64 of three.js and OrbitControls
  std::size_t histograms = 0;     ///< inline SVGs
};

struct HtmlReport {
  std::string html;
  HtmlReportSizes sizes;
};

/// Builds the page. Quantizes mesh positions to uint16 over the common
/// bounding box (base64), faces as uint32 and regions as int8 (base64); the
/// page computes normals.
HtmlReport buildHtmlReport(const HtmlReportInput& input);

/// RFC 4648 base64 (with padding), as used for every embedded payload.
std::string base64Encode(const unsigned char* data, std::size_t size);

/// Text safe inside HTML element content and attribute values.
std::string htmlEscape(const std::string& text);

}  // namespace icrkit::report
