#include <icrkit/report/run_report.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/mesh_normals.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/experiment_records.hpp>
#include <icrkit/eval/grasp_regions.hpp>
#include <icrkit/eval/quality_histogram.hpp>
#include <icrkit/eval/results_tables.hpp>
#include <icrkit/eval/rigid_alignment.hpp>
#include <icrkit/eval/run_folder.hpp>
#include <icrkit/report/quality_plot.hpp>
#include <icrkit/report/vendored_threejs.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <utility>
#include <fstream>
#include <iterator>
#include <memory>
#include <tuple>

namespace icrkit::report {
namespace {

namespace fs = std::filesystem;

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
    if (!parsed)
      throw InputError("RunReportOptions::grasp", "",
                       "expected DATASET/FINGERS/INDEX, e.g. cup_sr4000_A/4/0, got '" + wanted + "'");
    const std::string dataset = wanted.substr(0, slash1);
    for (const auto& r : records)
      if (r.dataset == dataset && r.fingers == fingers && r.index == index) return &r;
    throw InputError("RunReportOptions::grasp", "", "no grasp " + wanted + " in grasps.jsonl");
  }
  for (const auto& r : records)
    if (r.evaluated) return &r;
  return records.empty() ? nullptr : &records.front();
}

struct LoadedMesh {
  std::string key, label, path;
  std::unique_ptr<TriangleMesh> mesh;
};

}  // namespace

RunReport buildRunReport(const std::string& run_dir_text, const RunReportOptions& options) {
  const eval::RunFolder folder{run_dir_text};
  const fs::path run_dir(run_dir_text);
  std::error_code error;
  if (!fs::exists(run_dir, error))
    throw InputError(run_dir_text, "", "does not exist; expected the run folder of `icrkit evaluate` or `icrkit paper`");
  if (!fs::is_directory(run_dir, error))
    throw InputError(run_dir_text, "", "is not a directory; expected the run folder of `icrkit evaluate` or `icrkit paper`");

  RunReport result;
  HtmlReportInput input;
  input.run_dir = run_dir_text;
  input.generated_by = "Written by icrkit report.";
  auto missing = [&](const std::string& file, const std::string& what) {
    input.missing.push_back(file + " (" + what + ")");
  };

  // run.json: parameters, dataset order and where the meshes are.
  nlohmann::json run;
  if (const auto text = readText(folder.runJson())) {
    input.run_json = *text;
    try {
      run = nlohmann::json::parse(*text);
    } catch (const std::exception& e) {
      input.warnings.push_back("run.json is not valid JSON (" + std::string(e.what()) + "); parameters unknown");
    }
  } else {
    missing("run.json", "the run's parameters and datasets");
  }
  // planned.jsonl and surface.jsonl (optional: older runs lack them, and
  // runs with --plan-top 0 the first).
  for (auto [file, lines] : {std::pair<const char*, std::vector<std::string>*>{"planned.jsonl", &input.planned_lines},
                             {"surface.jsonl", &input.surface_lines}}) {
    const auto text = readText(run_dir / file);
    if (!text) continue;
    std::istringstream stream(*text);
    std::string line;
    for (std::size_t number = 1; std::getline(stream, line); ++number) {
      if (line.empty()) continue;
      try {
        (void)nlohmann::json::parse(line).at("dataset");
        lines->push_back(line);
      } catch (const std::exception& e) {
        input.warnings.push_back(std::string(file) + " line " + std::to_string(number) +
                                 " is not a per-dataset study (" + e.what() + "); skipped");
      }
    }
  }
  const eval::ExperimentConfig config =
      eval::experimentConfigFromJson(run.is_object() ? run.value("config", nlohmann::json()).dump() : "null");
  eval::TableOneOptions table_options;
  if (run.is_object() && run.contains("datasets"))
    for (const auto& d : run.at("datasets"))
      if (d.is_object() && d.contains("name") && d.at("name").is_string()) table_options.dataset_order.push_back(d.at("name"));

  // The records are the source of every table and histogram.
  std::vector<eval::GraspRecord> records;
  bool have_records = false;
  if (fs::exists(folder.records(), error)) {
    try {
      records = eval::readGraspRecords(folder.records());
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
                                    qualityHistogramSvg(eval::cumulativeQualityHistogram(records, fingers))});
    }
  }

  // Renders: every PNG under RUN_DIR/renders, in name order.
  const fs::path renders_dir = folder.renders();
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
  const eval::GraspRecord* grasp = chooseGrasp(records, options.grasp);
  result.dataset = grasp ? grasp->dataset : table_options.dataset_order.empty() ? "" : table_options.dataset_order.front();
  const std::string& dataset = result.dataset;
  if (grasp) {
    input.grasp_label = grasp->dataset + " / " + std::to_string(grasp->fingers) + " fingers / grasp " +
                        std::to_string(grasp->index) + (grasp->evaluated ? " (evaluated)" : " (not evaluated)");
    result.grasp = grasp->dataset + "/" + std::to_string(grasp->fingers) + "/" + std::to_string(grasp->index);
    if (!grasp->evaluated)
      input.viewer_note = "No grasp of this run was evaluated (eligible on both meshes), so the meshes are shown "
                          "without regions; the spheres mark the contacts where they were mapped.";
  } else if (!dataset.empty()) {
    input.viewer_note = "No grasp records: the meshes of " + dataset + " are shown without regions.";
  }
  const auto files = dataset.empty() ? std::nullopt : eval::runMeshFiles(input.run_json, folder, dataset);
  if (!files) {
    input.warnings.push_back(dataset.empty() ? "no dataset known (run.json and grasps.jsonl missing): no 3D viewer"
                                             : "run.json does not list dataset " + dataset + ": no 3D viewer");
  } else {
    std::vector<LoadedMesh> loaded;
    for (auto [key, label, path] : {std::tuple<const char*, const char*, std::string>{"cad", "CAD", files->cad},
                                    {"raw", "raw", files->raw},
                                    {"filtered", "filtered", files->filtered}}) {
      if (!fs::exists(path, error)) {
        missing(path, std::string(label) + " mesh of " + dataset);
        continue;
      }
      try {
        auto mesh = std::make_unique<TriangleMesh>(io::readTriangleMesh(path));
        if (!mesh->vertices.hasNormals() && !mesh->faces.empty()) {
          computeVertexNormals(*mesh);
          input.warnings.push_back(path + " has no vertex normals; computed from the faces (regions may "
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
          if (options.note) options.note("icrkit report: regrowing the regions of " + *result.grasp);
          regions = eval::regrowRegions(eval::DatasetMeshes{dataset, find("cad"), find("raw"), find("filtered")}, config,
                                        *grasp);
          result.regions = true;
        } catch (const InputError& e) {
          input.warnings.push_back(std::string("regions of the grasp could not be regrown: ") + e.what());
        }
      } else {
        input.viewer_note = "The regions need all three meshes; they are shown without regions.";
      }
    }
    input.fingers = grasp ? grasp->fingers : 0;
    result.meshes.emplace();
    for (const LoadedMesh& l : loaded) {
      const bool cad = l.key == "cad", raw = l.key == "raw";
      const std::vector<int> none;
      const std::vector<int>& contacts = !grasp ? none : cad ? grasp->cad_contacts : raw ? grasp->raw.contacts : grasp->filtered.contacts;
      const auto& mesh_regions = cad ? regions.cad : raw ? regions.raw : regions.filtered;
      input.meshes.push_back(makeReportMesh(l.key, l.label, l.path, *l.mesh, mesh_regions, contacts, options.max_faces));
      const ReportMesh& m = input.meshes.back();
      result.meshes->push_back({l.key, l.path, m.positions.size(), m.faces.size(), m.source_faces});
    }
  }
  input.three_version = vendoredThreeVersion();
  input.three_module_base64 = vendoredThreeModuleBase64();
  input.orbit_controls_base64 = vendoredOrbitControlsBase64();
  input.three_license = vendoredThreeLicense();
  result.three_version = input.three_version;

  result.page = buildHtmlReport(input);
  result.missing = input.missing;
  result.warnings = input.warnings;
  result.renders = input.renders.size();
  return result;
}

}  // namespace icrkit::report
