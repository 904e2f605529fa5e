#include <icrkit/eval/study.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

namespace icrkit::eval {
namespace {

using Clock = std::chrono::steady_clock;

ProgressCallback prefixed(const ProgressCallback& progress, const std::string& prefix) {
  if (!progress) return {};
  return [progress, prefix](const std::string& stage, std::size_t done, std::size_t total) {
    progress(prefix + stage, done, total);
  };
}

}  // namespace

std::unique_ptr<DatasetExperiment> experimentNamingFiles(const DatasetMeshes& meshes, const ExperimentConfig& config,
                                                         const RunMeshFiles& files) {
  try {
    return std::make_unique<DatasetExperiment>(meshes, config);
  } catch (const InputError& error) {
    const std::map<std::string, std::string> names{
        {"CAD mesh", files.cad}, {"raw mesh", files.raw}, {"filtered mesh", files.filtered}};
    const auto it = names.find(error.source());
    if (it == names.end() || it->second.empty()) throw;
    throw InputError(it->second, error.location(), error.detail() + " (" + it->first + ")");
  }
}

StudyResult runStudy(const std::vector<std::string>& datasets, const ExperimentConfig& config, const Shard& shard,
                     const StudyStages& stages, const ProgressCallback& progress) {
  shard.validate();
  config.validate();
  if (!stages.meshes) throw InputError("StudyStages::meshes", "", "the study needs a stage that makes the meshes");
  const std::size_t per_dataset = config.nominalItems();
  const auto [begin, end] = shard.range(per_dataset * datasets.size());
  StudyResult result;
  for (std::size_t d = 0; d < datasets.size(); ++d) {
    const std::size_t first = d * per_dataset, last = first + per_dataset;
    if (last <= begin || first >= end) continue;
    const std::string& name = datasets[d];
    const std::string prefix = "[" + std::to_string(d + 1) + "/" + std::to_string(datasets.size()) + "] " + name + ": ";
    StudyDatasetReport info;
    info.name = name;
    info.position = d;

    auto start = Clock::now();
    const StudyMeshes meshes = stages.meshes(name, d, prefixed(progress, prefix));
    info.meshes_ms = millisecondsSince(start);

    start = Clock::now();
    const DatasetMeshes view{name, &meshes.cad, &meshes.raw, &meshes.filtered};
    const std::unique_ptr<DatasetExperiment> experiment = experimentNamingFiles(view, config, meshes.files);
    const std::size_t local_begin = std::max(begin, first) - first, local_end = std::min(end, last) - first;
    if (stages.note)
      stages.note(prefix + "evaluating grasps " + std::to_string(local_begin) + ".." + std::to_string(local_end));
    std::vector<GraspRecord> part = experiment->run(local_begin, local_end, prefixed(progress, prefix));
    info.evaluate_ms = millisecondsSince(start);

    start = Clock::now();
    if (stages.after) stages.after(view, part);
    if (stages.first_shard && local_begin == 0) stages.first_shard(*experiment);
    info.after_ms = millisecondsSince(start);

    info.cad_vertices = meshes.cad.vertexCount();
    info.raw_vertices = meshes.raw.vertexCount();
    info.filtered_vertices = meshes.filtered.vertexCount();
    info.lambda_m = experiment->cadLambda();
    for (const std::size_t f : config.finger_counts) info.grasps_sampled.emplace_back(f, experiment->sampledGrasps(f));
    info.first_record = result.records.size();
    info.record_count = part.size();
    result.records.insert(result.records.end(), part.begin(), part.end());
    result.datasets.push_back(std::move(info));
  }
  return result;
}

std::size_t graspsWithoutSurface(const std::vector<GraspRecord>& records) {
  return static_cast<std::size_t>(std::count_if(records.begin(), records.end(), [](const GraspRecord& r) {
    return r.raw.contacts.empty() && r.filtered.contacts.empty();
  }));
}

}  // namespace icrkit::eval
