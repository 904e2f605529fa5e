#include <icrkit/eval/run_folder.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/icr/contact_model.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>

namespace icrkit::eval {
namespace {

namespace fs = std::filesystem;

std::string join(const std::string& dir, const std::string& a, const std::string& b = "",
                 const std::string& c = "") {
  fs::path path = fs::path(dir) / a;
  if (!b.empty()) path /= b;
  if (!c.empty()) path /= c;
  return path.string();
}

}  // namespace

std::string RunFolder::records() const { return join(dir, "grasps.jsonl"); }
std::string RunFolder::runJson() const { return join(dir, "run.json"); }
std::string RunFolder::renders() const { return join(dir, "renders"); }
bool RunFolder::hasRecording(const std::string& dataset) const {
  std::error_code error;
  return fs::exists(join(dir, "datasets", dataset, "manifest.json"), error);
}

bool RunFolder::hasReconstruction(const std::string& dataset) const {
  std::error_code error;
  return fs::exists(rawMesh(dataset), error) && fs::exists(filteredMesh(dataset), error);
}

std::string RunFolder::render(const GraspRecord& record, const std::string& label) const {
  return join(dir, "renders", renderStem(record) + label + ".png");
}

std::string renderStem(const GraspRecord& record) {
  return record.dataset + "_" + std::to_string(record.fingers) + "fingers_grasp" + std::to_string(record.index) + "_";
}
std::string RunFolder::datasetDir(const std::string& dataset) const { return join(dir, "datasets", dataset); }
std::string RunFolder::cadMesh(const std::string& dataset) const { return join(dir, "datasets", dataset, "object.ply"); }
std::string RunFolder::reconstructionDir(const std::string& dataset) const {
  return join(dir, "reconstructions", dataset);
}
std::string RunFolder::rawMesh(const std::string& dataset) const { return join(dir, "reconstructions", dataset, "raw.ply"); }
std::string RunFolder::filteredMesh(const std::string& dataset) const {
  return join(dir, "reconstructions", dataset, "filtered.ply");
}

std::string experimentConfigJson(const ExperimentConfig& config) {
  nlohmann::json json = {
      {"finger_counts", config.finger_counts},
      {"grasps_per_set", config.grasps_per_set},
      {"seed", config.seed},
      {"contact_model", nlohmann::json::parse(icr::contactModelJson(config.contactModel()))},
      {"alpha", config.alpha},
      {"growth", config.growth == icr::GrowthMode::BreadthFirst ? "bfs" : "full"},
      {"metric", config.metric == DistanceMetric::Euclidean                 ? "euclidean"
                 : config.paths == GeodesicPaths::EdgesAndUnfoldedDiagonals ? "geodesic_edges_and_unfolded_diagonals"
                                                                            : "geodesic_edges"},
      {"max_line_distance_m", config.mapping.max_line_distance},
      // 0: automatic, as run.json has always said it.
      {"neighbourhood_radius_m", config.mapping.neighbourhood_radius.value_or(0.0)},
      {"preselection", config.preselection},
      {"conservative_sigmas", config.conservative_sigmas},
      {"wrench_frame", "CAD mesh centroid, lambda = largest CAD vertex distance from it"}};
  if (config.patch) json["patch"] = {{"radius_m", config.patch->radius_m}, {"filter_border", config.patch->filter_border}};
  return json.dump();
}

ExperimentConfig experimentConfigFromJson(const std::string& config_json) {
  ExperimentConfig out;
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(config_json);
  } catch (const std::exception& error) {
    throw InputError("run.json", "config", std::string("is not valid JSON: ") + error.what());
  }
  if (!config.is_object()) return out;
  if (config.contains("finger_counts")) out.finger_counts = config.at("finger_counts").get<std::vector<std::size_t>>();
  out.grasps_per_set = config.value("grasps_per_set", out.grasps_per_set);
  out.seed = config.value("seed", out.seed);
  out.alpha = config.value("alpha", out.alpha);
  if (config.contains("contact_model")) {
    const auto& model = config.at("contact_model");
    out.friction = model.value("mu", out.friction);
    out.cone_edges = model.value("edges", out.cone_edges);
  }
  out.growth = config.value("growth", std::string("bfs")) == "full" ? icr::GrowthMode::Full : icr::GrowthMode::BreadthFirst;
  const std::string metric = config.value("metric", std::string("geodesic_edges_and_unfolded_diagonals"));
  out.metric = metric == "euclidean" ? DistanceMetric::Euclidean : DistanceMetric::Geodesic;
  if (metric == "geodesic_edges") out.paths = GeodesicPaths::Edges;
  out.mapping.max_line_distance = config.value("max_line_distance_m", out.mapping.max_line_distance);
  if (const double radius = config.value("neighbourhood_radius_m", 0.0); radius > 0.0)
    out.mapping.neighbourhood_radius = radius;
  out.preselection = config.value("preselection", out.preselection);
  if (config.contains("conservative_sigmas"))
    out.conservative_sigmas = config.at("conservative_sigmas").get<std::vector<double>>();
  if (config.contains("patch")) {
    if (!config.at("patch").is_object())
      throw InputError("run.json", "config.patch", "expected an object with radius_m and filter_border");
    out.patch = icr::PatchParameters{};
    out.patch->radius_m = config.at("patch").value("radius_m", out.patch->radius_m);
    out.patch->filter_border = config.at("patch").value("filter_border", out.patch->filter_border);
  }
  return out;
}

std::optional<RunMeshFiles> runMeshFiles(const std::string& run_json, const RunFolder& folder,
                                         const std::string& dataset) {
  nlohmann::json run;
  try {
    run = nlohmann::json::parse(run_json);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (!run.is_object() || !run.contains("datasets")) return std::nullopt;
  for (const auto& d : run.at("datasets")) {
    if (!d.is_object() || d.value("name", std::string()) != dataset) continue;
    if (d.contains("cad") && d.contains("raw") && d.contains("filtered")) {
      // Relative paths were relative to where `evaluate` ran; that is unknown
      // here, so try the current folder, then the run folder.
      const auto locate = [&](const std::string& p) {
        const fs::path path(p);
        std::error_code error;
        if (path.is_relative() && !fs::exists(path, error) && fs::exists(fs::path(folder.dir) / path, error))
          return (fs::path(folder.dir) / path).string();
        return path.string();
      };
      return RunMeshFiles{locate(d.at("cad")), locate(d.at("raw")), locate(d.at("filtered"))};
    }
    return RunMeshFiles{folder.cadMesh(dataset), folder.rawMesh(dataset), folder.filteredMesh(dataset)};
  }
  return std::nullopt;
}

}  // namespace icrkit::eval
