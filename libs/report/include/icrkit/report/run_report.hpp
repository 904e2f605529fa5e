#pragma once
/// \file
/// The HTML report of a run folder (eval/run_folder.hpp), as `icrkit report`
/// writes it: gathers run.json, the grasp records, the Fig. 8 SVGs (recomputed
/// from the records when missing), the renders and one grasp's meshes, whose
/// regions it grows again, and builds the page (html_report.hpp). Missing
/// files and unreadable parts do not stop it: they are listed in the page
/// and in RunReport::missing / warnings.

#include <icrkit/report/html_report.hpp>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::report {

struct RunReportOptions {
  /// The viewer's grasp, DATASET/FINGERS/INDEX; empty: the first evaluated
  /// record (the first record when none was evaluated).
  std::string grasp;
  std::size_t max_faces = 0;  ///< cap of each viewer mesh (makeReportMesh); 0 = all faces
  /// Human-readable notes on slow steps (regrowing regions); may be empty.
  std::function<void(const std::string&)> note;
};

/// One mesh of the viewer, as drawn.
struct RunReportMesh {
  std::string mesh;  ///< "cad", "raw" or "filtered"
  std::string file;
  std::size_t vertices = 0, faces = 0, source_faces = 0;
};

struct RunReport {
  HtmlReport page;
  std::vector<std::string> missing;   ///< "FILE (what it holds)"
  std::vector<std::string> warnings;
  std::size_t renders = 0;            ///< PNGs embedded
  std::string dataset;                ///< the viewer's dataset; empty when none is known
  std::optional<std::string> grasp;   ///< DATASET/FINGERS/INDEX of the viewer's grasp
  bool regions = false;               ///< the viewer shows that grasp's regions
  /// The meshes found for the dataset (unset when run.json does not say where they are).
  std::optional<std::vector<RunReportMesh>> meshes;
  std::string three_version;          ///< empty: three.js not vendored, no 3D viewer
};

/// InputError when `run_dir` does not exist or is not a folder, or for a
/// malformed --grasp (source "--grasp") or one that is not in grasps.jsonl.
RunReport buildRunReport(const std::string& run_dir, const RunReportOptions& options = {});

}  // namespace icrkit::report
