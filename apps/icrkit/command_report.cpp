// `icrkit report RUN_DIR -o report.html`: one self-contained HTML page of a
// run folder of `icrkit evaluate` or `icrkit paper` (docs/evaluation.md,
// "Report"). The page is report::buildRunReport's; this file maps the flags
// and prints. A run folder that lacks files still gets a report, which says
// what is missing: a half-copied run is worth looking at.

#include "commands.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/report/run_report.hpp>

#include <filesystem>
#include <memory>

namespace icrkit::app {

namespace {

struct ReportOptions {
  std::string run_dir;
  std::string output;  ///< empty: RUN_DIR/report.html
  std::string grasp;   ///< DATASET/FINGERS/INDEX; empty: the first evaluated record
  std::size_t max_faces = 0;
};

nlohmann::json report(const ReportOptions& o, CommandContext& context) {
  namespace fs = std::filesystem;
  std::error_code error;
  const std::string output = o.output.empty() ? (fs::path(o.run_dir) / "report.html").string() : o.output;
  // After the run folder's own checks (buildRunReport), before the slow part.
  if (fs::is_directory(o.run_dir, error) && fs::is_directory(output, error))
    throw InputError(output, "", "is a directory; expected the report's file name");
  report::RunReportOptions options;
  options.grasp = o.grasp;
  options.max_faces = o.max_faces;
  options.note = [&context](const std::string& message) { context.note(message); };
  report::RunReport run;
  try {
    run = report::buildRunReport(o.run_dir, options);
  } catch (const InputError& e) {
    if (e.source() == "RunReportOptions::grasp") throw InputError("--grasp", e.location(), e.detail());
    throw;
  }
  if (run.three_version.empty()) context.note("icrkit report: three.js was not vendored at build time; no 3D viewer");
  writeFileAtomically(output, [&](std::ostream& out) { out << run.page.html; });
  for (const std::string& m : run.missing) context.note("icrkit report: missing " + m);

  nlohmann::json viewer{{"dataset", run.dataset},
                        {"grasp", run.grasp ? nlohmann::json(*run.grasp) : nlohmann::json(nullptr)},
                        {"regions", run.regions}};
  if (run.meshes) {
    viewer["meshes"] = nlohmann::json::array();
    for (const report::RunReportMesh& m : *run.meshes)
      viewer["meshes"].push_back({{"mesh", m.mesh},
                                  {"file", m.file},
                                  {"vertices", m.vertices},
                                  {"faces", m.faces},
                                  {"source_faces", m.source_faces}});
  }
  viewer["threejs"] = run.three_version.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.three_version);
  const report::HtmlReportSizes& sizes = run.page.sizes;
  return {{"output", output},
          {"run_dir", o.run_dir},
          {"missing", run.missing},
          {"warnings", run.warnings},
          {"viewer", viewer},
          {"renders", run.renders},
          {"bytes",
           {{"total", sizes.total},
            {"meshes", sizes.meshes},
            {"renders", sizes.renders},
            {"threejs", sizes.threejs},
            {"histograms", sizes.histograms}}},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addReportCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "report",
      "One self-contained HTML page of a run folder of `icrkit evaluate` or `icrkit paper`: parameters, Table I beside "
      "the paper's values, eligibility, Fig. 8, renders and a 3D viewer (three.js, embedded) of one grasp's regions "
      "on the CAD, raw and filtered meshes. Missing files are listed in the page (docs/evaluation.md, \"Report\")");
  auto o = std::make_shared<ReportOptions>();
  command->add_option("run_dir", o->run_dir, "Run folder (icrkit evaluate/paper -o DIR)")->required();
  command->add_option("-o,--output", o->output, "The HTML file (default RUN_DIR/report.html; replaced atomically)");
  command->add_option("--grasp", o->grasp,
                      "Grasp in the viewer, DATASET/FINGERS/INDEX (default: the first evaluated one in grasps.jsonl)");
  command->add_option("--max-faces", o->max_faces,
                      "Cap each viewer mesh at about N faces by keeping every k-th face (holes, not a decimation); "
                      "0 = all faces")
      ->capture_default_str();
  command->callback([&runner, o] { runner = [o](CommandContext& context) { context.emit(report(*o, context)); }; });
}

}  // namespace icrkit::app
