#pragma once
/// \file
/// The paper's Section III-A made a study: how the ICRs on raw and filtered
/// meshes follow the sensor noise. A CAD mesh is sampled (Poisson disk, a
/// given spacing), Gaussian noise of a few multiples of that spacing is
/// added along the true normals (seeded), and for every noise level the
/// raw and the filtered mesh are built from the noisy sample (by a caller's
/// `SensitivityMeshBuilder`: eval does not know how meshes are made) and the
/// experiment of `icrkit evaluate` runs on them, once per preselection rule.
///
/// Every (level, rule) pair is one dataset of the grasp records, named
/// `sensitivityDatasetName`, so the records of shards merge like any other
/// study's, and the sensitivity table is computed from them.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/eval/experiment.hpp>
#include <icrkit/eval/experiment_records.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::eval {

struct SensitivityParameters {
  /// Poisson-disk spacing of the sample (metres, finite and > 0); unset:
  /// 1/150 of the CAD mesh's bounding-box diagonal.
  std::optional<double> spacing_m;
  /// Noise standard deviations along the normal, in multiples of the spacing.
  std::vector<double> noise_levels{0.0, 0.25, 0.5, 1.0};
  /// Sampling and noise; level i draws its noise with seed * 1000 + i.
  std::uint64_t seed = 1;
  /// Preselection rule names, one filtered mesh per rule (labels only: the
  /// builder applies them).
  std::vector<std::string> rules{"default", "paper-mean", "none"};
  ExperimentConfig experiment;
};

/// The meshes of one noise level: the raw mesh and, per rule of the
/// parameters (in their order), the filtered mesh with that rule's
/// `excluded` flags; `preselection` false where the rule is none.
struct SensitivityMeshes {
  TriangleMesh raw;
  struct Filtered {
    std::string rule;
    TriangleMesh mesh;
    bool preselection = true;
  };
  std::vector<Filtered> filtered;
};

/// Builds the meshes from a noisy sample (positions only are noisy; its
/// normals are the CAD surface's, for the builder to ignore or use).
using SensitivityMeshBuilder =
    std::function<SensitivityMeshes(const PointCloud& noisy_sample, double spacing_m, double noise_sigma_m)>;

/// "<object> noise=<level>x <rule>", e.g. "bun_zipper noise=0.50x default".
std::string sensitivityDatasetName(const std::string& object, double noise_level, const std::string& rule);

/// The spacing used for `cad` (parameters.spacing_m or the automatic one).
double sensitivitySpacing(const TriangleMesh& cad, const SensitivityParameters& params);

/// The clean sample and one noisy version of it (level i of the parameters).
PointCloud sensitivitySample(const TriangleMesh& cad, const SensitivityParameters& params);
PointCloud addNormalNoise(const PointCloud& sample, double sigma_m, std::uint64_t seed);

struct SensitivityLevelReport {
  double noise_level = 0.0;  ///< multiple of the spacing
  double sigma_m = 0.0;
  std::size_t sample_points = 0;
  std::size_t raw_faces = 0;
  std::size_t filtered_faces = 0;
  std::vector<std::size_t> excluded_vertices;  ///< per rule
  bool built = false;  ///< false when this shard had no work on the level
  double build_ms = 0.0, evaluate_ms = 0.0;
};

struct SensitivityResult {
  double spacing_m = 0.0;
  std::vector<SensitivityLevelReport> levels;
  std::vector<GraspRecord> records;
};

/// Nominal work items: levels x rules x finger counts x grasps per set.
std::size_t sensitivityItems(const SensitivityParameters& params);

/// Runs the study (items [shard begin, end) only: a shard builds the meshes
/// of the levels it touches). InputError for negative or non-finite noise
/// levels, no levels or rules, a bad experiment config; the builder's
/// errors pass through. Progress: "level i/n: <stage>".
SensitivityResult runSensitivityStudy(const TriangleMesh& cad, const std::string& object,
                                      const SensitivityParameters& params, const SensitivityMeshBuilder& build,
                                      const Shard& shard = {}, const ProgressCallback& progress = {});

/// One row of the sensitivity table: a noise level and a rule.
struct SensitivityRow {
  double noise_level = 0.0;
  std::string rule;
  std::size_t grasps = 0;
  std::optional<double> raw_eligible_percent, filtered_eligible_percent;
  /// After snapping to the nearest kept vertex (not the paper's check; JSON only).
  std::optional<double> filtered_eligible_after_snapping_percent;
  /// Eligibility of the grasps away from the rim of the seen surface
  /// (EligibilityCounts::off_rim_grasps; not the paper's check; JSON only).
  std::optional<double> off_rim_grasps_percent, raw_eligible_off_rim_percent, filtered_eligible_off_rim_percent;
  std::optional<double> raw_intersection_percent, raw_false_positive_percent;
  std::optional<double> filtered_intersection_percent, filtered_false_positive_percent;
  std::size_t evaluated = 0;
};

struct SensitivityTable {
  std::string object;
  double spacing_m = 0.0;
  std::vector<double> noise_levels;
  std::vector<std::string> rules;
  std::vector<SensitivityRow> rows;  ///< level-major, rules in order
};

/// From grasp records (of one run or merged shards).
SensitivityTable computeSensitivityTable(const std::vector<GraspRecord>& records, const std::string& object,
                                         double spacing_m, const std::vector<double>& noise_levels,
                                         const std::vector<std::string>& rules);

/// The table as JSON (sensitivity.json; the Markdown table and the plot are
/// icrkit/report/sensitivity_plot.hpp).
std::string sensitivityJson(const SensitivityTable& table);

}  // namespace icrkit::eval
