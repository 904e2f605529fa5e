// `icrkit report RUN_DIR -o report.html`: one self-contained HTML page of a
// run folder of `icrkit evaluate` or `icrkit paper` (docs/evaluation.md,
// "Report"). This file only gathers the pieces; the page itself is built by
// icrkit::report::buildHtmlReport. A run folder that lacks files still gets a
// report, which says what is missing: a half-copied run is worth looking at.

#include "commands.hpp"
#include "experiment_options.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/eval/grasp_regions.hpp>
#include <icrkit/eval/quality_histogram.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/rigid_alignment.hpp>
#include <icrkit/report/html_report.hpp>
#include <icrkit/report/quality_plot.hpp>
#include <icrkit/report/vendored_threejs.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>

namespace icrkit::app {

namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::string run_dir;
  std::string output;  ///< empty: RUN_DIR/report.html
  std::string grasp;   ///< DATASET/FINGERS/INDEX; empty: the first evaluated record
  std::size_t max_faces = 0;
};

std::optional<std::string> readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string scalarText(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

/// The header's key facts: the command, the datasets and every config entry.
std::vector<std::pair<std::string, std::string>> keyParameters(const nlohmann::json& run, std::size_t records) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!run.is_object()) return out;
  if (run.contains("command")) out.emplace_back("command", "icrkit " + scalarText(run.at("command")));
  if (run.contains("datasets") && run.at("datasets").is_array()) {
    std::string names;
    for (const auto& d : run.at("datasets"))
      if (d.is_object() && d.contains("name")) names += (names.empty() ? "" : ", ") + scalarText(d.at("name"));
    out.emplace_back("datasets", names);
  }
  if (run.contains("config") && run.at("config").is_object())
    for (const auto& [key, value] : run.at("config").items()) {
      if (value.is_object()) {
        for (const auto& [inner, v] : value.items()) out.emplace_back(key + "." + inner, scalarText(v));
      } else {
        out.emplace_back(key, scalarText(value));
      }
    }
  for (const char* key : {"align", "views", "reconstruction"})
    if (run.contains(key)) out.emplace_back(key, scalarText(run.at(key)));
  if (run.contains("shard"))
    out.emplace_back("shard", scalarText(run.at("shard").value("index", nlohmann::json(0))) + "/" +
                                  scalarText(run.at("shard").value("count", nlohmann::json(1))));
  out.emplace_back("grasp records", std::to_string(records));
  return out;
}

struct MeshFiles {
  fs::path cad, raw, filtered;
};

/// Where a dataset's meshes are: `evaluate` records their paths, `paper`
/// keeps them inside the run folder.
std::optional<MeshFiles> meshFilesOf(const nlohmann::json& run, const fs::path& run_dir, const std::string& dataset) {
  if (!run.is_object() || !run.contains("datasets")) return std::nullopt;
  for (const auto& d : run.at("datasets")) {
    if (!d.is_object() || d.value("name", std::string()) != dataset) continue;
    if (d.contains("cad") && d.contains("raw") && d.contains("filtered")) {
      // Relative paths were relative to where `evaluate` ran; that is unknown
      // here, so try the current folder, then the run folder.
      auto locate = [&](const std::string& p) {
        const fs::path path(p);
        std::error_code error;
        if (path.is_relative() && !fs::exists(path, error) && fs::exists(run_dir / path, error)) return run_dir / path;
        return path;
      };
      return MeshFiles{locate(d.at("cad")), locate(d.at("raw")), locate(d.at("filtered"))};
    }
    return MeshFiles{run_dir / "datasets" / dataset / "object.ply", run_dir / "reconstructions" / dataset / "raw.ply",
                     run_dir / "reconstructions" / dataset / "filtered.ply"};
  }
  return std::nullopt;
}

const eval::GraspRecord* chooseGrasp(const std::vector<eval::GraspRecord>& records, const std::string& wanted) {
  if (!wanted.empty()) {
    const auto slash2 = wanted.rfind('/');
    const auto slash1 = slash2 == std::string::npos || slash2 == 0 ? std::string::npos : wanted.rfind('/', slash2 - 1);
    std::size_t fingers = 0, index = 0;
    bool parsed = slash1 != std::string::npos;
    if (parsed) {
      try {
        std::size_t used1 = 0, used2 = 0;
        const std::string f = wanted.substr(slash1 + 1, slash2 - slash1 - 1), i = wanted.substr(slash2 + 1);
        fingers = std::stoul(f, &used1);
        index = std::stoul(i, &used2);
        parsed = used1 == f.size() && used2 == i.size();
      } catch (const std::exception&) {
        parsed = false;
      }
    }
    if (!parsed) throw InputError("--grasp", "", "expected DATASET/FINGERS/INDEX, e.g. cup_sr4000_A/4/0, got '" + wanted + "'");
    const std::string dataset = wanted.substr(0, slash1);
    for (const auto& r : records)
      if (r.dataset == dataset && r.fingers == fingers && r.index == index) return &r;
    throw InputError("--grasp", "", "no grasp " + wanted + " in grasps.jsonl");
  }
  for (const auto& r : records)
    if (r.evaluated) return &r;
  return records.empty() ? nullptr : &records.front();
}

nlohmann::json report(const ReportOptions& o, CommandContext& context) {
  const fs::path run_dir(o.run_dir);
  std::error_code error;
  if (!fs::exists(run_dir, error))
    throw InputError(o.run_dir, "", "does not exist; expected the run folder of `icrkit evaluate` or `icrkit paper`");
  if (!fs::is_directory(run_dir, error))
    throw InputError(o.run_dir, "", "is not a directory; expected the run folder of `icrkit evaluate` or `icrkit paper`");
  const std::string output = o.output.empty() ? (run_dir / "report.html").string() : o.output;
  if (fs::is_directory(output, error)) throw InputError(output, "", "is a directory; expected the report's file name");

  report::HtmlReportInput input;
  input.run_dir = o.run_dir;
  input.generated_by = "Written by icrkit report.";
  auto missing = [&](const std::string& file, const std::string& what) {
    input.missing.push_back(file + " (" + what + ")");
  };

  // run.json: parameters, dataset order and where the meshes are.
  nlohmann::json run;
  if (const auto text = readText(run_dir / "run.json")) {
    input.run_json = *text;
    try {
      run = nlohmann::json::parse(*text);
    } catch (const std::exception& e) {
      input.warnings.push_back("run.json is not valid JSON (" + std::string(e.what()) + "); parameters unknown");
    }
  } else {
    missing("run.json", "the run's parameters and datasets");
  }
  const eval::ExperimentConfig config = experimentConfigFromJson(run.is_object() ? run.value("config", nlohmann::json()) : nlohmann::json());
  eval::TableOneOptions table_options;
  if (run.is_object() && run.contains("datasets"))
    for (const auto& d : run.at("datasets"))
      if (d.is_object() && d.contains("name") && d.at("name").is_string()) table_options.dataset_order.push_back(d.at("name"));

  // The records are the source of every table and histogram.
  std::vector<eval::GraspRecord> records;
  bool have_records = false;
  if (fs::exists(run_dir / "grasps.jsonl", error)) {
    try {
      records = eval::readGraspRecords((run_dir / "grasps.jsonl").string());
      have_records = true;
    } catch (const InputError& e) {
      input.warnings.push_back(std::string(e.what()));
    }
  } else {
    missing("grasps.jsonl", "the per-grasp records; Table I, eligibility and the viewer's regions come from them");
  }
  for (const char* file : {"table1.json", "table1.md", "table1.csv", "eligibility.json"})
    if (!fs::exists(run_dir / file, error)) missing(file, "written by icrkit evaluate/paper");
  if (have_records) {
    input.table = eval::computeTableOne(records, table_options);
    input.eligibility = eval::computeEligibility(records, table_options);
  }
  input.parameters = keyParameters(run, records.size());

  // Fig. 8 as written; recomputed from the records when a file is missing.
  for (const std::size_t fingers : config.finger_counts) {
    const std::string name = "fig8_" + std::to_string(fingers) + "fingers.svg";
    if (const auto svg = readText(run_dir / name)) {
      input.histograms.push_back({name, *svg});
    } else {
      missing(name, "Fig. 8 for " + std::to_string(fingers) + " fingers");
      if (have_records)
        input.histograms.push_back({name + " (recomputed from grasps.jsonl)",
                                    report::qualityHistogramSvg(eval::cumulativeQualityHistogram(records, fingers))});
    }
  }

  // Renders: every PNG under RUN_DIR/renders, in name order.
  const fs::path renders_dir = run_dir / "renders";
  if (fs::is_directory(renders_dir, error)) {
    std::vector<fs::path> pngs;
    for (auto it = fs::recursive_directory_iterator(renders_dir, error); !error && it != fs::recursive_directory_iterator();
         it.increment(error))
      if (it->is_regular_file(error) && it->path().extension() == ".png") pngs.push_back(it->path());
    std::sort(pngs.begin(), pngs.end());
    for (const fs::path& png : pngs)
      if (const auto bytes = readText(png))
        input.renders.push_back({fs::relative(png, run_dir, error).generic_string(),
                                 std::vector<unsigned char>(bytes->begin(), bytes->end())});
    if (input.renders.empty()) input.renders_note = "renders/ holds no PNG files (icrkit render writes them).";
  } else {
    input.renders_note = "No renders in this run folder (icrkit render writes them).";
  }

  // The viewer: one grasp's meshes and regions.
  const eval::GraspRecord* grasp = chooseGrasp(records, o.grasp);
  std::string dataset = grasp ? grasp->dataset : table_options.dataset_order.empty() ? "" : table_options.dataset_order.front();
  nlohmann::json viewer{{"dataset", dataset}, {"grasp", nullptr}, {"regions", false}};
  if (grasp) {
    input.grasp_label = grasp->dataset + " / " + std::to_string(grasp->fingers) + " fingers / grasp " +
                        std::to_string(grasp->index) + (grasp->evaluated ? " (evaluated)" : " (not evaluated)");
    viewer["grasp"] = grasp->dataset + "/" + std::to_string(grasp->fingers) + "/" + std::to_string(grasp->index);
    if (!grasp->evaluated)
      input.viewer_note = "No grasp of this run was evaluated (eligible on both meshes), so the meshes are shown "
                          "without regions; the spheres mark the contacts where they were mapped.";
  } else if (!dataset.empty()) {
    input.viewer_note = "No grasp records: the meshes of " + dataset + " are shown without regions.";
  }
  const auto files = dataset.empty() ? std::nullopt : meshFilesOf(run, run_dir, dataset);
  if (!files) {
    input.warnings.push_back(dataset.empty() ? "no dataset known (run.json and grasps.jsonl missing): no 3D viewer"
                                             : "run.json does not list dataset " + dataset + ": no 3D viewer");
  } else {
    struct Loaded {
      std::string key, label;
      fs::path path;
      std::unique_ptr<TriangleMesh> mesh;
    };
    std::vector<Loaded> loaded;
    for (auto [key, label, path] : {std::tuple<const char*, const char*, fs::path>{"cad", "CAD", files->cad},
                                    {"raw", "raw", files->raw},
                                    {"filtered", "filtered", files->filtered}}) {
      if (!fs::exists(path, error)) {
        missing(path.string(), std::string(label) + " mesh of " + dataset);
        continue;
      }
      try {
        auto mesh = std::make_unique<TriangleMesh>(io::readTriangleMesh(path.string()));
        if (!mesh->vertices.hasNormals() && !mesh->faces.empty()) {
          computeVertexNormals(*mesh);
          input.warnings.push_back(path.string() + " has no vertex normals; computed from the faces (regions may "
                                                   "differ slightly from the experiment's)");
        }
        loaded.push_back({key, label, path, std::move(mesh)});
      } catch (const InputError& e) {
        input.warnings.push_back(std::string(e.what()));
      }
    }
    auto find = [&](const std::string& key) -> TriangleMesh* {
      for (auto& l : loaded)
        if (l.key == key) return l.mesh.get();
      return nullptr;
    };
    // The experiment moved raw and filtered onto the CAD surface first when
    // run with --align icp (deterministic), so the same is done here.
    if (run.is_object() && run.value("align", std::string("none")) == "icp" && find("cad")) {
      for (const char* key : {"raw", "filtered"})
        if (TriangleMesh* mesh = find(key)) {
          try {
            eval::transformMesh(*mesh, eval::alignToCad(*mesh, *find("cad")).transform);
          } catch (const InputError& e) {
            input.warnings.push_back(std::string(key) + " mesh: --align icp failed again: " + e.detail());
          }
        }
    }
    eval::GraspRegions regions;
    if (grasp && grasp->evaluated) {
      if (find("cad") && find("raw") && find("filtered")) {
        try {
          context.note("icrkit report: regrowing the regions of " + viewer["grasp"].get<std::string>());
          regions = eval::regrowRegions(eval::DatasetMeshes{dataset, find("cad"), find("raw"), find("filtered")}, config,
                                        *grasp);
          viewer["regions"] = true;
        } catch (const InputError& e) {
          input.warnings.push_back(std::string("regions of the grasp could not be regrown: ") + e.what());
        }
      } else {
        input.viewer_note = "The regions need all three meshes; they are shown without regions.";
      }
    }
    input.fingers = grasp ? grasp->fingers : 0;
    nlohmann::json mesh_summary = nlohmann::json::array();
    for (const Loaded& l : loaded) {
      const bool cad = l.key == "cad", raw = l.key == "raw";
      const std::vector<int> none;
      const std::vector<int>& contacts = !grasp ? none : cad ? grasp->cad_contacts : raw ? grasp->raw.contacts : grasp->filtered.contacts;
      const auto& mesh_regions = cad ? regions.cad : raw ? regions.raw : regions.filtered;
      input.meshes.push_back(
          report::makeReportMesh(l.key, l.label, l.path.string(), *l.mesh, mesh_regions, contacts, o.max_faces));
      const report::ReportMesh& m = input.meshes.back();
      mesh_summary.push_back({{"mesh", l.key},
                              {"file", l.path.string()},
                              {"vertices", m.positions.size()},
                              {"faces", m.faces.size()},
                              {"source_faces", m.source_faces}});
    }
    viewer["meshes"] = mesh_summary;
  }
  input.three_version = report::vendoredThreeVersion();
  input.three_module_base64 = report::vendoredThreeModuleBase64();
  input.orbit_controls_base64 = report::vendoredOrbitControlsBase64();
  input.three_license = report::vendoredThreeLicense();
  viewer["threejs"] = input.three_version.empty() ? nlohmann::json(nullptr) : nlohmann::json(input.three_version);
  if (input.three_version.empty()) context.note("icrkit report: three.js was not vendored at build time; no 3D viewer");

  const report::HtmlReport page = report::buildHtmlReport(input);
  writeFileAtomically(output, [&](std::ostream& out) { out << page.html; });
  for (const std::string& m : input.missing) context.note("icrkit report: missing " + m);
  return {{"output", output},
          {"run_dir", o.run_dir},
          {"missing", input.missing},
          {"warnings", input.warnings},
          {"viewer", viewer},
          {"renders", input.renders.size()},
          {"bytes",
           {{"total", page.sizes.total},
            {"meshes", page.sizes.meshes},
            {"renders", page.sizes.renders},
            {"threejs", page.sizes.threejs},
            {"histograms", page.sizes.histograms}}},
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
