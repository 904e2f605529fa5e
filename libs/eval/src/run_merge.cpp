#include <icrkit/eval/run_merge.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/eval/run_folder.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace icrkit::eval {
namespace {

namespace fs = std::filesystem;

nlohmann::json readRunJson(const RunFolder& folder) {
  const std::string path = folder.runJson();
  std::ifstream in(path);
  if (!in) throw InputError(path, "", "cannot be read; expected the run folder of `icrkit evaluate` or `icrkit paper`");
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception& error) {
    throw InputError(path, "", std::string("is not valid JSON: ") + error.what());
  }
}

// The renders an unsharded run keeps: those of the first `renders` evaluated
// grasps of each dataset.
std::vector<std::string> wantedRenders(const std::vector<std::string>& folders, const std::vector<GraspRecord>& records,
                                       const nlohmann::json& run) {
  std::set<std::string> wanted;
  const bool filter = run.contains("renders");
  if (filter) {
    std::map<std::string, long> left;
    for (const GraspRecord& r : records) {
      if (!r.evaluated) continue;
      long& n = left.try_emplace(r.dataset, run.at("renders").get<long>()).first->second;
      if (n-- > 0) wanted.insert(renderStem(r));
    }
  }
  const auto keep = [&](const std::string& file) {
    if (!filter) return true;
    for (const std::string& stem : wanted)
      if (file.rfind(stem, 0) == 0) return true;
    return false;
  };
  std::vector<std::string> files;
  for (const std::string& folder : folders) {
    const fs::path from = RunFolder{folder}.renders();
    if (!fs::is_directory(from)) continue;
    for (const auto& entry : fs::directory_iterator(from))
      if (entry.path().extension() == ".png" && keep(entry.path().filename().string()))
        files.push_back(entry.path().string());
  }
  return files;
}

// The lines of a per-dataset file (one JSON object with "dataset" per line,
// each dataset in one shard only) over all shards, in dataset order.
std::vector<std::string> datasetLines(const std::vector<std::string>& folders, const std::string& file,
                                      const std::vector<std::string>& order) {
  std::map<std::string, std::string> lines;  // dataset -> line
  for (const std::string& folder : folders) {
    const fs::path path = fs::path(folder) / file;
    std::ifstream in(path);
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
      if (line.empty()) continue;
      std::string dataset;
      try {
        dataset = nlohmann::json::parse(line).at("dataset").get<std::string>();
      } catch (const std::exception& error) {
        throw InputError(path.string(), "line " + std::to_string(number),
                         std::string("expected a JSON object with \"dataset\": ") + error.what());
      }
      if (!lines.emplace(dataset, line).second)
        throw InputError(path.string(), "line " + std::to_string(number), dataset + " appears in two shards");
    }
  }
  std::vector<std::string> ordered;
  for (const std::string& name : order)
    if (const auto it = lines.find(name); it != lines.end()) ordered.push_back(it->second);
  return ordered;
}

}  // namespace

MergedRun mergeRunFolders(const std::vector<std::string>& folders) {
  if (folders.empty()) throw InputError("run folders", "", "expected at least one run folder");
  MergedRun merged;
  std::set<std::size_t> shards;
  nlohmann::json first;
  std::size_t count = 0;
  for (const std::string& folder : folders) {
    const nlohmann::json run = readRunJson(RunFolder{folder});
    const std::size_t index = run.at("shard").at("index"), n = run.at("shard").at("count");
    nlohmann::json comparable = run;
    comparable.erase("shard");
    comparable.erase("time_ms");
    if (first.is_null()) {
      first = comparable;
      count = n;
    } else if (comparable != first || n != count) {
      throw InputError(RunFolder{folder}.runJson(), "",
                       "its parameters, datasets or shard count differ from those of " + folders.front());
    }
    if (!shards.insert(index).second)
      throw InputError(folder, "", "shard " + std::to_string(index) + " is given twice");
    auto part = readGraspRecords(RunFolder{folder}.records());
    merged.records.insert(merged.records.end(), part.begin(), part.end());
  }
  std::string missing;
  for (std::size_t i = 0; i < count; ++i)
    if (!shards.count(i)) missing += (missing.empty() ? "" : ",") + std::to_string(i);
  if (!missing.empty())
    throw InputError("run folders", "", "shards missing: " + missing + " of " + std::to_string(count));
  std::sort(merged.records.begin(), merged.records.end());
  for (std::size_t i = 1; i < merged.records.size(); ++i)
    if (!(merged.records[i - 1] < merged.records[i]))
      throw InputError("run folders", "",
                       "grasp " + merged.records[i].dataset + "/" + std::to_string(merged.records[i].fingers) + "/" +
                           std::to_string(merged.records[i].index) + " appears in two shards");

  nlohmann::json run = first;
  run["shard"] = {{"index", 0}, {"count", 1}};
  run["merged_from"] = folders;
  merged.run_json = run.dump();
  for (const auto& dataset : first.at("datasets")) merged.dataset_order.push_back(dataset.at("name"));
  for (const auto& f : first.at("config").at("finger_counts")) merged.finger_counts.push_back(f);
  if (first.contains("sensitivity")) {
    const nlohmann::json& study = first.at("sensitivity");
    merged.sensitivity = computeSensitivityTable(
        merged.records, study.at("object").get<std::string>(), study.at("spacing_m").get<double>(),
        study.at("noise_levels").get<std::vector<double>>(), study.at("rules").get<std::vector<std::string>>());
  }
  merged.render_files = wantedRenders(folders, merged.records, first);
  merged.planned_lines = datasetLines(folders, "planned.jsonl", merged.dataset_order);
  merged.surface_lines = datasetLines(folders, "surface.jsonl", merged.dataset_order);
  return merged;
}

}  // namespace icrkit::eval
