#include <icrkit/eval/sensitivity_study.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/mesh_sampling.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

namespace icrkit::eval {

std::string sensitivityDatasetName(const std::string& object, double noise_level, const std::string& rule) {
  char level[32];
  std::snprintf(level, sizeof level, "%.2f", noise_level);
  return object + " noise=" + level + "x " + rule;
}

double sensitivitySpacing(const TriangleMesh& cad, const SensitivityParameters& params) {
  if (params.spacing_m) return *params.spacing_m;
  const Eigen::AlignedBox3d box = cad.vertices.bounds();
  return box.diagonal().norm() / 150.0;
}

PointCloud sensitivitySample(const TriangleMesh& cad, const SensitivityParameters& params) {
  return samplePointsPoissonDisk(cad, sensitivitySpacing(cad, params), params.seed);
}

PointCloud addNormalNoise(const PointCloud& sample, double sigma_m, std::uint64_t seed) {
  PointCloud noisy = sample;
  if (sigma_m == 0.0) return noisy;
  // Serial, in point order: the same noise for a seed whatever the threads.
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < noisy.size(); ++i) noisy.positions[i] += sigma_m * gauss(random) * noisy.normals[i];
  return noisy;
}

std::size_t sensitivityItems(const SensitivityParameters& params) {
  return params.noise_levels.size() * params.rules.size() * params.experiment.nominalItems();
}

namespace {

void validate(const TriangleMesh& cad, const SensitivityParameters& params) {
  if (params.noise_levels.empty()) throw InputError("SensitivityParameters::noise_levels", "", "at least one noise level");
  for (const double level : params.noise_levels)
    if (!(std::isfinite(level) && level >= 0))
      throw InputError("SensitivityParameters::noise_levels", "", "noise levels are multiples of the spacing >= 0, got " + std::to_string(level));
  if (params.rules.empty()) throw InputError("SensitivityParameters::rules", "", "at least one preselection rule");
  if (params.spacing_m && !(std::isfinite(*params.spacing_m) && *params.spacing_m > 0))
    throw InputError("SensitivityParameters::spacing_m", "", "expected metres > 0 (or unset: automatic)");
  if (cad.faceCount() == 0) throw InputError("CAD mesh", "", "has no faces to sample");
  params.experiment.validate();
}

}  // namespace

SensitivityResult runSensitivityStudy(const TriangleMesh& cad, const std::string& object,
                                      const SensitivityParameters& params, const SensitivityMeshBuilder& build,
                                      const Shard& shard, const ProgressCallback& progress) {
  validate(cad, params);
  shard.validate();
  SensitivityResult result;
  result.spacing_m = sensitivitySpacing(cad, params);
  const std::size_t per_dataset = params.experiment.nominalItems();
  const std::size_t rules = params.rules.size();
  const auto [begin, end] = shard.range(sensitivityItems(params));
  PointCloud sample;
  for (std::size_t level = 0; level < params.noise_levels.size(); ++level) {
    SensitivityLevelReport info;
    info.noise_level = params.noise_levels[level];
    info.sigma_m = info.noise_level * result.spacing_m;
    const std::size_t first = level * rules * per_dataset, last = first + rules * per_dataset;
    if (last <= begin || first >= end) {
      result.levels.push_back(info);
      continue;
    }
    const std::string prefix =
        "level " + std::to_string(level + 1) + "/" + std::to_string(params.noise_levels.size()) + ": ";
    if (progress) progress(prefix + "meshing", 0, 1);
    auto start = std::chrono::steady_clock::now();
    if (sample.empty()) sample = sensitivitySample(cad, params);
    const PointCloud noisy = addNormalNoise(sample, info.sigma_m, params.seed * 1000 + level);
    SensitivityMeshes meshes = build(noisy, result.spacing_m, info.sigma_m);
    if (meshes.filtered.size() != rules)
      throw std::logic_error("sensitivity: the mesh builder returned " + std::to_string(meshes.filtered.size()) +
                             " filtered meshes for " + std::to_string(rules) + " rules");
    info.built = true;
    info.sample_points = noisy.size();
    info.raw_faces = meshes.raw.faceCount();
    info.filtered_faces = meshes.filtered.front().mesh.faceCount();
    info.build_ms = millisecondsSince(start);

    start = std::chrono::steady_clock::now();
    for (std::size_t r = 0; r < rules; ++r) {
      const SensitivityMeshes::Filtered& filtered = meshes.filtered[r];
      std::size_t excluded = 0;
      if (const Attribute* flags = filtered.mesh.vertices.attributes.find("excluded"))
        for (const double v : flags->values) excluded += v != 0.0;
      info.excluded_vertices.push_back(filtered.preselection ? excluded : 0);
      const std::size_t from = first + r * per_dataset, to = from + per_dataset;
      if (to <= begin || from >= end) continue;
      ExperimentConfig config = params.experiment;
      config.preselection = filtered.preselection;
      const std::string name = sensitivityDatasetName(object, info.noise_level, params.rules[r]);
      DatasetExperiment experiment(DatasetMeshes{name, &cad, &meshes.raw, &filtered.mesh}, config);
      const std::size_t local_begin = std::max(begin, from) - from, local_end = std::min(end, to) - from;
      ProgressCallback staged;
      if (progress)
        staged = [&](const std::string& stage, std::size_t done, std::size_t total) {
          progress(prefix + params.rules[r] + " " + stage, done, total);
        };
      std::vector<GraspRecord> part = experiment.run(local_begin, local_end, staged);
      result.records.insert(result.records.end(), part.begin(), part.end());
    }
    info.evaluate_ms = millisecondsSince(start);
    result.levels.push_back(info);
  }
  return result;
}

}  // namespace icrkit::eval
