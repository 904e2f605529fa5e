// Naming, selecting and describing datasets (dataset.hpp); the simulation
// itself is dataset.cpp.
#include <icrkit/sim/dataset.hpp>

#include <icrkit/core/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>

namespace icrkit::sim {

std::vector<DatasetSpec> paperDatasets(const std::vector<std::string>& names) {
  const std::vector<DatasetSpec> all = paperDatasets();
  if (names.empty()) return all;
  std::vector<DatasetSpec> chosen;
  for (const std::string& name : names) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const DatasetSpec& s) { return datasetName(s) == name; });
    if (it == all.end()) {
      std::string known;
      for (const DatasetSpec& s : all) known += (known.empty() ? "" : ", ") + datasetName(s);
      throw InputError("dataset names", "", "unknown dataset '" + name + "'; the paper's are " + known);
    }
    chosen.push_back(*it);
  }
  return chosen;
}

std::string datasetFolderName(const DatasetSpec& spec, const std::string& pose_error) {
  std::string tag = pose_error;
  std::transform(tag.begin(), tag.end(), tag.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (tag == "arm") return datasetName(spec);
  std::replace(tag.begin(), tag.end(), ',', '_');
  return datasetName(spec) + "_" + tag;
}

std::string datasetRecordJson(const DatasetSpec& spec, const SimulationReport& s) {
  nlohmann::json record{
      {"name", datasetName(spec)},
      {"directory", s.directory},
      {"object", spec.mesh_path.empty() ? spec.object : spec.mesh_path},
      {"sensor", sensorTypeName(spec.sensor)},
      {"setup", setupName(spec.acquisition.setup)},
      {"views", s.views},
      {"seed", spec.acquisition.seed},
      {"pose_error", spec.acquisition.errors.name},
      {"object_vertices", s.object_vertices},
      {"valid_pixel_fraction", s.valid_pixel_fraction},
      {"object_pixel_fraction", s.object_pixel_fraction},
      {"files", {"scans.rawlog", "ground_truth.txt", "reported_poses.txt", "object.ply", "scene.ply", "manifest.json"}},
      {"time_ms", s.time_ms}};
  if (spec.correlated_noise_share != 0.0)
    record["correlated_depth_noise"] = {{"share", spec.correlated_noise_share},
                                        {"length_px", spec.correlated_noise_length_px}};
  return record.dump();
}

std::string paperDatasetsJson() {
  nlohmann::json list = nlohmann::json::array();
  for (const DatasetSpec& s : paperDatasets())
    list.push_back({{"name", datasetName(s)},
                    {"object", s.object},
                    {"sensor", sensorTypeName(s.sensor)},
                    {"setup", setupName(s.acquisition.setup)},
                    {"views", s.acquisition.views},
                    {"seed", s.acquisition.seed}});
  return nlohmann::json{{"datasets", list}}.dump();
}

}  // namespace icrkit::sim
