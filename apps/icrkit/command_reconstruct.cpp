// `icrkit reconstruct RAWLOG|FOLDER -o DIR`: the whole of Section II-A
// (reconstruction::reconstructRawlog) on a rawlog or a TUM RGB-D folder, and
// its files (reconstruction::writeReconstructionFiles,
// reconstructionRecordJson): DIR/cloud.ply (fused cloud), DIR/raw.ply and
// DIR/filtered.ply (meshes), DIR/poses.txt (TUM, MRPT's sensor axes, like a
// rawlog's sensorPose) and DIR/reconstruction.json.

#include "commands.hpp"
#include "depth_folder_options.hpp"
#include "reconstruct_options.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/eval/rigid_alignment.hpp>
#include <icrkit/eval/surface_accuracy.hpp>
#include <icrkit/reconstruction/reconstruction_outputs.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace icrkit::app {
namespace {

nlohmann::json reconstruct(const ReconstructOptions& options, CommandContext& context) {
  const reconstruction::ReconstructionParameters params = reconstructionParameters(options);
  // Bad values fail before the ground truth is read (reconstructRawlog checks them again).
  reconstruction::validateReconstructionParameters(params);
  reconstruction::ReconstructionRecordInput record{options.input, options.output, options.range_correction, {}, ""};
  // The ground truth is read (and for a folder matched to its frames)
  // before the long run, so that a bad file fails at once.
  if (!options.gt_poses.empty())
    record.ground_truth = reconstruction::readGroundTruthPoses(options.input, options.gt_poses, params);
  std::optional<TriangleMesh> gt_mesh;
  if (!options.gt_mesh.empty()) {
    gt_mesh = io::readTriangleMesh(options.gt_mesh);
    if (gt_mesh->faces.empty()) throw InputError(options.gt_mesh, "", "has no faces; --gt-mesh needs a surface");
    if (!params.make_meshes) throw InputError("--gt-mesh", "", "measures the meshes, which --no-meshes skips");
  }
  // A bag's topics and frames, chosen by its reader; read before the long
  // run so that a bag without camera or poses fails at once.
  std::optional<nlohmann::json> bag_input;
  if (reconstruction::isBag(options.input)) {
    const reconstruction::McapReader bag(options.input, params.mcap);
    bag_input = nlohmann::json{{"kind", "ros2 bag (mcap)"},
                               {"depth_topic", bag.depthTopic()},
                               {"depth_encoding", bag.depthEncoding()},
                               {"camera_info_topic", bag.cameraInfoTopic()},
                               {"pose_source", bag.poseMatching()},
                               {"pose_topic", bag.poseTopic()},
                               {"frames", bag.poseSource() == reconstruction::BagPoseSource::Tf
                                              ? nlohmann::json{bag.parentFrame(), bag.childFrame()}
                                              : nlohmann::json(nullptr)},
                               {"max_time_difference_s", params.mcap.max_time_difference},
                               {"images", bag.scanCount()}};
  }
  requireOutputFolder(options.output);

  const reconstruction::ReconstructionResult result =
      reconstruction::reconstructRawlog(options.input, params, context.progress());
  if (result.depth_camera) context.note(depthScaleNote(*result.depth_camera));
  // Everything is computed (and the ground truth checked) before the first file is written.
  nlohmann::json summary = nlohmann::json::parse(reconstruction::reconstructionRecordJson(result, params, record));
  std::string surface;
  if (gt_mesh) {
    const double start = context.elapsedMs();
    // A reconstruction lies in the frame of the robot's first pose: fit each
    // mesh to the reference rigidly, as evaluate --align icp does.
    nlohmann::json fits = nlohmann::json::object();
    TriangleMesh raw = result.raw_mesh, filtered = result.filtered_mesh;
    for (auto [mesh, name] : {std::pair<TriangleMesh*, const char*>{&raw, "raw"}, {&filtered, "filtered"}}) {
      const eval::AlignmentResult fit = eval::alignToCad(*mesh, *gt_mesh);
      eval::transformMesh(*mesh, fit.transform);
      fits[name] = {{"rms_before_m", fit.rms_before_m}, {"rms_after_m", fit.rms_after_m}, {"converged", fit.converged}};
    }
    nlohmann::json s = nlohmann::json::parse(
        eval::datasetSurfaceAccuracyJson(std::filesystem::path(options.input).stem().string(), *gt_mesh, raw, filtered));
    s["gt_mesh"] = options.gt_mesh;
    s["fit"] = fits;
    summary["surface"] = s;
    surface = s.dump();
    summary["time_ms"]["surface"] = context.elapsedMs() - start;
  }
  const double write_start = context.elapsedMs();
  reconstruction::writeReconstructionFiles(options.output, result, params.make_meshes,
                                           options.write_registration_input);
  // The command line's names for where the camera's values came from.
  if (result.depth_camera) summary["depth_camera"] = depthCameraJson(*result.depth_camera);
  if (bag_input) summary["bag"] = *bag_input;
  summary["time_ms"]["write"] = context.elapsedMs() - write_start;
  summary["time_ms"]["total"] = context.elapsedMs();
  if (!surface.empty())
    writeFileAtomically((std::filesystem::path(options.output) / "surface.json").string(), surface + "\n");
  writeSummaryFile((std::filesystem::path(options.output) / "reconstruction.json").string(), summary);
  return summary;
}

}  // namespace

void addReconstructCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "reconstruct",
      "Object reconstruction from an MRPT rawlog of range scans (Section II-A of Krug et al.): per-scan filters "
      "(confidence, jump edges, range, crop box, support plane), scan-to-model 3D-NDT registration from the "
      "reported poses, pair-wise registrations and loop closure in a pose graph (CHOLMOD), OctoMap fusion, then "
      "ball pivoting of the fused cloud (raw mesh) and of its 3D-NDT smoothed, preselected version (filtered "
      "mesh). Writes DIR/cloud.ply, DIR/raw.ply, DIR/filtered.ply, DIR/poses.txt (TUM, MRPT's sensor axes like a "
      "rawlog's sensorPose, for a folder too) and DIR/reconstruction.json. The input may also be a TUM RGB-D "
      "folder (depth.txt, 16-bit depth PNGs) or a ROS 2 bag (MCAP: --depth-topic, --pose-topic or --frames; "
      "docs/reconstruction_input.md)");
  auto options = std::make_shared<ReconstructOptions>();
  addReconstructOptions(*command, *options);
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      context.mapFields({{"ReconstructionParameters::rotation_tolerance", "--rotation-tolerance"},
                         {"ReconstructionParameters::auto_crop_half_size", "--crop-size"},
                         {"ReconstructionParameters::crop_box", "--crop"},
                         {"ReconstructionParameters::board", "--board-square"},
                         {"BoardLattice::square_size", "--board-square"},
                         {"ConfidenceFilterParameters::min_confidence", "--min-confidence"},
                         {"ConfidenceFilterParameters::min_amplitude", "--min-amplitude"},
                         {"RangeGateParameters::max_range", "--max-range"},
                         {"OctreeFusionParameters::resolution", "--voxel"},
                         {"SmoothingParameters::radius", "--smoothing-radius"},
                         {"SmoothingParameters::passes", "--passes"},
                         {"DepthCameraOptions::depth_scale", "--depth-scale"},
                         {"DepthCameraOptions::intrinsics", "--intrinsics"},
                         {"McapReaderOptions::depth_topic", "--depth-topic"},
                         {"McapReaderOptions::camera_info_topic", "--camera-info-topic"},
                         {"McapReaderOptions::pose_topic", "--pose-topic"},
                         {"McapReaderOptions::parent_frame", "--frames"},
                         {"McapReaderOptions::child_frame", "--frames"},
                         {"McapReaderOptions::intrinsics", "--intrinsics"},
                         {"McapReaderOptions::depth_scale", "--depth-scale"},
                         {"McapReaderOptions::max_time_difference", "--max-time-difference"},
                         {"ReconstructionParameters::pose_file", "--poses"},
                         {"BallPivotingParameters::thinning_factor", "--mesh-thinning"}});
      context.emit(reconstruct(*options, context));
    };
  });
}

}  // namespace icrkit::app
