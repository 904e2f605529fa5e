// The files and the record of one reconstruction (reconstruction_outputs.hpp)
// and the parameter checks before the long run: a small perfect-pose
// recording, its files read back, its record against the result, the
// ground truth's error (zero for the true poses) and every refused value
// naming its field.

#include <icrkit/reconstruction/reconstruction_outputs.hpp>

#include "simulated_recordings.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>

#include <test_support.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

namespace icrkit::reconstruction {
namespace {

using testing_support::scratchFolder;
using testing_support::simulatedRecording;

TEST(ReconstructionOutputs, FilesAndRecordOfAPerfectRecording) {
  const std::string dir = simulatedRecording(4, true);
  ReconstructionParameters params;
  params.pose_file = dir + "/ground_truth.txt";
  params.keep_registration_input = true;
  const ReconstructionResult result = reconstructRawlog(dir + "/scans.rawlog", params);
  ASSERT_EQ(result.poses.size(), 4u);

  ReconstructionRecordInput input{dir + "/scans.rawlog", "out", "", {}, ""};
  input.ground_truth = readGroundTruthPoses(input.input, dir + "/ground_truth.txt", params);
  ASSERT_EQ(input.ground_truth->poses.size(), 4u);
  const nlohmann::json record = nlohmann::json::parse(reconstructionRecordJson(result, params, input));
  EXPECT_EQ(record["input_format"], "rawlog");
  EXPECT_EQ(record["scans"], 4);
  EXPECT_EQ(record["poses"], params.pose_file);
  EXPECT_TRUE(record["range_correction"].is_null());
  EXPECT_EQ(record["cloud_points"], result.cloud.positions.size());
  EXPECT_EQ(record["per_scan"].size(), 4u);
  EXPECT_EQ(record["raw_mesh"]["triangles"], result.raw_meshing.triangles);
  EXPECT_EQ(record["smoothing"]["preselection"]["rule"], "default");
  EXPECT_EQ(record["registration_error"]["ground_truth"], dir + "/ground_truth.txt");
  // Registered from the true poses, the trajectory stays within millimetres of them.
  EXPECT_LT(record["registration_error"]["registered"]["aligned"]["max_sensor_translation_mm"].get<double>(), 3.0);
  EXPECT_LT(record["registration_error"]["reported"]["aligned"]["max_sensor_translation_mm"].get<double>(), 1e-6)
      << "the reported poses are the ground truth";
  EXPECT_TRUE(record["time_ms"].contains("pipeline"));

  // A ground truth with fewer poses than scans names the first scan without one.
  ReconstructionRecordInput short_truth = input;
  short_truth.ground_truth->poses.resize(3);
  const InputError error = test::expectInputError([&] { reconstructionRecordJson(result, params, short_truth); });
  EXPECT_EQ(error.location(), "scan 3");

  const std::filesystem::path out = scratchFolder("outputs");
  writeReconstructionFiles((out / "rec").string(), result, true, (out / "views").string());
  EXPECT_EQ(io::readPointCloud((out / "rec/cloud.ply").string()).positions.size(), result.cloud.positions.size());
  EXPECT_EQ(io::readTriangleMesh((out / "rec/raw.ply").string()).faceCount(), result.raw_mesh.faceCount());
  EXPECT_EQ(io::readTriangleMesh((out / "rec/filtered.ply").string()).faceCount(), result.filtered_mesh.faceCount());
  const std::vector<StampedPose> poses = readTumTrajectory((out / "rec/poses.txt").string());
  ASSERT_EQ(poses.size(), 4u);
  EXPECT_TRUE(poses[2].pose.isApprox(result.poses[2], 1e-6));
  EXPECT_TRUE(std::filesystem::exists(out / "views/view_003.ply"));
  EXPECT_EQ(readTumTrajectory((out / "views/start.txt").string()).size(), 4u);

  // Without meshes only the cloud and the poses; a file in the directory's place is refused.
  writeReconstructionFiles((out / "cloud_only").string(), result, false);
  EXPECT_TRUE(std::filesystem::exists(out / "cloud_only/cloud.ply"));
  EXPECT_FALSE(std::filesystem::exists(out / "cloud_only/raw.ply"));
  writeFileAtomically((out / "file").string(), std::string("x"));
  EXPECT_EQ(test::expectInputError([&] { writeReconstructionFiles((out / "file").string(), result, false); }).source(),
            (out / "file").string());
  std::filesystem::remove_all(out);
}

TEST(ReconstructionOutputs, ParametersOutOfRangeNameTheirField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::function<void(ReconstructionParameters&)>>> cases = {
      {"ReconstructionParameters::rotation_tolerance", [](auto& p) { p.rotation_tolerance = -1; }},
      {"ReconstructionParameters::auto_crop_half_size", [&](auto& p) { p.auto_crop_half_size = nan; }},
      {"ReconstructionParameters::crop_box",
       [](auto& p) { p.crop_box = Eigen::AlignedBox3d(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1)); }},
      {"BoardLattice::square_size", [](auto& p) { p.board = BoardLattice{}, p.board->square_size = 0; }},
      {"ReconstructionParameters::board", [](auto& p) { p.board = BoardLattice{}, p.register_scans = false; }},
      {"ConfidenceFilterParameters::min_confidence", [](auto& p) { p.confidence.min_confidence = 256; }},
      {"ConfidenceFilterParameters::min_amplitude", [](auto& p) { p.confidence.min_amplitude = -1; }},
      {"RangeGateParameters::max_range", [](auto& p) { p.range.max_range = -0.5; }},
      {"OctreeFusionParameters::resolution", [](auto& p) { p.fusion.resolution = 0; }},
      {"SmoothingParameters::passes", [](auto& p) { p.smoothing.passes = 0; }},
      {"BallPivotingParameters::thinning_factor", [](auto& p) { p.meshing.thinning_factor = -2; }},
  };
  EXPECT_NO_THROW(validateReconstructionParameters(ReconstructionParameters{}));
  for (const auto& [field, spoil] : cases) {
    ReconstructionParameters params;
    spoil(params);
    EXPECT_EQ(test::expectInputError([&] { validateReconstructionParameters(params); }).source(), field);
    // reconstructRawlog refuses them before it opens the input.
    EXPECT_EQ(test::expectInputError([&] { reconstructRawlog("/nonexistent.rawlog", params); }).source(), field);
  }
}

}  // namespace
}  // namespace icrkit::reconstruction
