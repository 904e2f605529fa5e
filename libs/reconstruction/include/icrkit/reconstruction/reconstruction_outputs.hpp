#pragma once
/// \file
/// The files of one reconstruction, as `icrkit reconstruct -o DIR` writes
/// them (docs/formats.md): DIR/cloud.ply, DIR/raw.ply, DIR/filtered.ply,
/// DIR/poses.txt, optionally the registration's input, and the record
/// DIR/reconstruction.json; and the ground truth whose registration error
/// the record reports.

#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// True sensor poses of a recording's scans (object frame, MRPT sensor axes).
struct GroundTruthPoses {
  std::string file;
  std::vector<StampedPose> poses;
  std::size_t orthonormalised = 0;  ///< poses projected onto the nearest rotation as read
};

/// Reads the ground truth `file` of the recording `input`: for a rawlog a
/// TUM file in MRPT's sensor axes, pose i for scan i; for a TUM RGB-D folder
/// or a ROS 2 bag a TUM file in the camera's optical axes, matched to the
/// folder's frames or the bag's image stamps
/// like ReconstructionParameters::pose_file (by order or time stamp, with
/// params.depth_camera and params.max_time_difference). Read before the
/// long run, a bad file fails at once: InputError naming it and the line.
GroundTruthPoses readGroundTruthPoses(const std::string& input, const std::string& file,
                                      const ReconstructionParameters& params);

/// What the record says beside the result and the parameters.
struct ReconstructionRecordInput {
  std::string input;                  ///< the rawlog, folder or bag reconstructed
  std::string output;                 ///< the output directory
  std::string range_correction_file;  ///< where params.range_correction came from; empty: none
  std::optional<GroundTruthPoses> ground_truth;
  /// "rawlog", "tum_folder", "ros2_bag" or, for scans fed from memory,
  /// "memory"; empty: told from `input`.
  std::string input_format;
};

/// reconstruction.json as JSON text (keys sorted): the input, crop box,
/// per-scan filter, board, registration and fusion counts, the pose graph,
/// fusion, meshing and smoothing summaries, stage times (time_ms) and, with
/// a ground truth, the registration error of the registered and of the
/// reported poses after the best rigid alignment (trajectory_error.hpp),
/// per scan and as medians. The depth camera's `*_source` fields say
/// "options" where the caller's options set a value.
/// InputError naming the ground-truth file and the first scan without a
/// pose when it has fewer poses than the result has scans.
std::string reconstructionRecordJson(const ReconstructionResult& result, const ReconstructionParameters& params,
                                     const ReconstructionRecordInput& record);

/// Writes `directory`/cloud.ply, raw.ply and filtered.ply (when `meshes`;
/// raw.ply only when the result has a raw mesh)
/// and poses.txt (TUM, the final poses in MRPT's sensor axes); with a
/// `registration_input_directory` (needs result.registration_input) also
/// its view_NNN.ply (each scan's object points, sensor frame) and start.txt
/// (their reported poses). Directories are created, each file atomically;
/// InputError naming a directory that cannot be created.
void writeReconstructionFiles(const std::string& directory, const ReconstructionResult& result, bool meshes,
                              const std::string& registration_input_directory = {});

}  // namespace icrkit::reconstruction
