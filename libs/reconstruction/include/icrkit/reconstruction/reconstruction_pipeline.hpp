#pragma once
/// \file
/// Section II-A of Krug et al. as one call: a recording of range scans with
/// robot-reported poses (an MRPT rawlog or a TUM RGB-D folder of depth
/// images, scan_source.hpp) -> filtered scans -> scan-to-model 3D-NDT
/// registration and pose graph -> OctoMap fusion -> the raw mesh (ball
/// pivoting on the fused cloud) and the filtered mesh (3D-NDT smoothing and
/// preselection, then ball pivoting). See docs/reconstruction.md.
///
/// The recording is read once, scan by scan, into a Reconstructor
/// (reconstructor.hpp), which keeps each scan's filtered points until the
/// registration has placed them all.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/ndt/smoothing.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>
#include <icrkit/reconstruction/fusion/octree_fusion.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>
#include <icrkit/reconstruction/calibration/board_lattice_pose.hpp>
#include <icrkit/reconstruction/input/scan_filters.hpp>
#include <icrkit/reconstruction/input/mcap_reader.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// The one-sided smoothing window of the feature-preserving default
/// (radians, 30 deg): a window keeps the points whose input normal is within
/// it of the centre's. Chosen on the nine simulated datasets (mobile-robot
/// poses): the filtered meshes' median normal error within 4 mm of a sharp
/// edge fell from 26-30 deg (the paper's window) to 4-10 deg on the wooden
/// toys, below the raw meshes' 24-26 deg (docs/smoothing.md).
inline constexpr double kFeatureWindowNormalAngle = M_PI / 6.0;

struct ReconstructionParameters {
  /// TUM file overriding the recorded sensor poses: for a rawlog in MRPT's
  /// sensor axes, for a folder in the camera's optical axes
  /// (ScanReaderOptions); a rawlog's images folder (RawlogReaderOptions).
  std::string pose_file;
  std::string images_folder;
  /// A folder's camera and pose matching (TumFolderOptions); a rawlog's
  /// rotation tolerance (RawlogReaderOptions).
  DepthCameraOptions depth_camera;
  double max_time_difference = kTumMaxTimeDifference;
  double rotation_tolerance = kReadRotationTolerance;
  /// A ROS 2 bag's topics and frames (mcap_reader.hpp).
  McapReaderOptions mcap;

  /// A ToF camera's systematic range error (range_calibration.hpp), removed
  /// from every scan before anything else; zero: none.
  RangeErrorModel range_correction;
  /// Per-scan filters, in this order.
  ConfidenceFilterParameters confidence;
  bool jump_edge_filter = true;
  JumpEdgeParameters jump_edges;
  ForegroundEdgeParameters foreground_edges;
  RangeGateParameters range;
  /// The object's region (object frame, metres). Unset: a cube of
  /// `auto_crop_half_size` around the point closest to all the views'
  /// optical axes (the robot looks at the object).
  std::optional<Eigen::AlignedBox3d> crop_box;
  double auto_crop_half_size = 0.15;
  /// Removes the table / support plate: the plane is searched among the
  /// points of the box's lower half along `up` (band = half the box's
  /// extent along it); `support_plane.up` is replaced by `up`.
  bool remove_support_plane = true;
  PlaneRemovalParameters support_plane;
  /// The object frame's up direction (unit). Unset: estimated from the
  /// sensors' poses (estimateUpAxis: +z unless the views say otherwise,
  /// then the frame's axis nearest their up). Set it when the views are
  /// not upright (a handheld camera rolled about its axis).
  std::optional<Eigen::Vector3d> up;

  /// false: keep the reported poses (no registration).
  bool register_scans = true;
  SequenceRegistrationParameters registration;
  /// The paper's setup B: the object stands on a checkerboard. Wherever the
  /// board is found in a scan's intensity image (latticeCameraPose, its
  /// corners predicted by the reported pose), the camera pose relative to
  /// the board enters the registration's pose graph as a robust absolute
  /// prior with `board_prior_sigma_*`, next to the robot's odometry and its
  /// weaker reported-pose priors: the board fixes the object frame (most of
  /// the robot's constant hand-eye error drops out), the robot's relative
  /// motion keeps the scans together. The NDT still starts from the reported
  /// poses (docs/calibration.md says why). A board pose further than half a
  /// square or `board_max_rotation` from the reported pose is not used (a
  /// lattice locked one square off). Needs `register_scans`. Unset: no board.
  std::optional<BoardLattice> board;
  LatticePoseParameters board_detection;
  double board_prior_sigma_translation = 0.002;  ///< metres
  double board_prior_sigma_rotation = 0.004;     ///< radians
  double board_max_rotation = 0.035;             ///< radians (2 deg)

  /// Fusion; its `bounds` are replaced by the crop box.
  OctreeFusionParameters fusion;
  /// Normals of the fused cloud, each facing its own view's sensor; a
  /// radius relative to the spacing (default 3 spacings) is taken of a
  /// single scan's spacing, for the reason given at `smoothing`.
  ndt::NormalEstimationParameters normals;
  /// Smoothing: a radius relative to the spacing (default 4 spacings) is
  /// taken of the spacing of a single scan (median nearest-neighbour distance of the
  /// first scan's object points), not of the fused cloud: many overlapping
  /// views make the fused cloud far denser than its noise is thin, and a
  /// window of a few fused spacings would not reach across the noise.
  ///
  /// Feature-preserving by default: one-sided windows (max_normal_angle
  /// kFeatureWindowNormalAngle, 30 deg) keep Algorithm 1 where a window is
  /// one surface and do not blend across creases and thin walls (issue 34,
  /// docs/smoothing.md). The paper's window (every point of the radius):
  /// max_normal_angle = pi (`--smoothing paper`).
  ndt::SmoothingParameters smoothing = [] {
    ndt::SmoothingParameters p;
    p.max_normal_angle = kFeatureWindowNormalAngle;
    return p;
  }();
  /// Ball pivoting of both clouds (radii relative to each cloud's own
  /// spacing by default: the smoothed layer is thin and dense). Flakes of
  /// fewer than 24 faces beside the surface are dropped: a fused cloud's
  /// noise layer leaves them, and each adds a boundary loop.
  ///
  /// The smoothed cloud's noise layer is thinned where it is thick against
  /// its spacing (`thinning_factor` 8, the simulated Kinect B sets; the
  /// real recording's smoothed layer is too thin to be) and the thinned
  /// points are put back into the faces afterwards (`reinsert_thinned`):
  /// one piece, and every vertex of the unthinned mesh's density. Without
  /// the reinsertion a thinned mesh is coarse, and the paper's
  /// intersection estimate (Algorithm 2), which maps a region's vertices,
  /// covers less of the CAD region (bottle_kinect_B: filtered Int 20 %
  /// thinned, 71 % unthinned; docs/results.md).
  BallPivotingParameters meshing = [] {
    BallPivotingParameters p;
    p.min_component_faces = 24;
    return p;
  }();
  /// The raw mesh is the paper's baseline, every fused point as it is:
  /// false keeps its noise layer unthinned and its folded holes open
  /// (`meshing.thinning_factor` and `meshing.fill_folded_holes` apply to
  /// the smoothed cloud only); its holes are then many.
  bool thin_raw_cloud = false;
  /// Drop the preselection's excluded points before ball pivoting the
  /// smoothed cloud (RawAndFilteredParameters::mesh_kept_points_only).
  bool mesh_kept_points_only = false;
  /// false: stop after the fused cloud (no meshes).
  bool make_meshes = true;
  /// false: the filtered mesh only (`raw_mesh` stays empty, raw.ply is not
  /// written): what a robot grasps, a third sooner after the last scan.
  bool make_raw_mesh = true;
  /// Keep each scan's object points (sensor frame) as handed to the
  /// registration, for comparisons with other registration tools on exactly
  /// the same input (`ReconstructionResult::registration_input`).
  bool keep_registration_input = false;
};

/// What the filters did to one scan.
struct ScanFilterRecord {
  std::size_t index = 0;
  double timestamp = 0.0;
  std::size_t valid_pixels = 0;
  std::size_t removed_confidence = 0;
  std::size_t removed_jump_edges = 0;
  std::size_t removed_foreground_edges = 0;
  std::size_t removed_range = 0;
  std::size_t removed_crop = 0;
  std::size_t removed_plane = 0;
  bool plane_found = false;
  std::size_t object_points = 0;
};

struct ReconstructionTimes {
  double read_ms = 0.0;  ///< reading and unprojecting scans (all passes)
  double filter_ms = 0.0;
  double registration_ms = 0.0;
  double fusion_ms = 0.0;
  double normals_ms = 0.0;
  double raw_mesh_ms = 0.0;
  double smoothing_ms = 0.0;
  double filtered_mesh_ms = 0.0;
  double total_ms = 0.0;
};

struct ReconstructionResult {
  /// Final sensor poses (object frame, MRPT sensor axes, like the rawlog's
  /// sensorPose) and the scans' time stamps (seconds since 1970).
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Eigen::Isometry3d> reported_poses;
  std::vector<double> timestamps;
  /// Input poses that were not exactly rotations as read and were projected
  /// onto the nearest one (RangeScan::pose_orthonormalised).
  std::size_t poses_orthonormalised = 0;
  /// ScanReader::poseMatching(): "recorded", "order", "timestamp", "none".
  std::string pose_matching;
  /// A folder's camera (intrinsics, depth scale); empty for a rawlog.
  std::optional<DepthCamera> depth_camera;
  Eigen::AlignedBox3d crop_box;
  bool crop_box_automatic = false;
  /// The object frame's up direction the support-plane filter used, and
  /// whether it was estimated from the sensors' poses (else given).
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  bool up_automatic = false;
  double scan_spacing_m = 0.0;  ///< median point spacing of the first scan's object points
  std::vector<ScanFilterRecord> filters;
  SequenceRegistrationResult registration;  ///< empty when registration is off
  /// With `keep_registration_input`: per scan, its filtered object points in
  /// its own sensor frame (MRPT axes), as the registration saw them.
  std::vector<PointCloud> registration_input;
  /// Per scan, the checkerboard pose when `board` was given (else empty);
  /// `poses_from_board` of them were found and used; `board_pose_rejected`
  /// marks those found but too far from the reported pose.
  std::vector<LatticePose> board_poses;
  std::vector<std::uint8_t> board_pose_rejected;
  std::size_t poses_from_board = 0;
  /// The fused cloud with normals and the attributes `view`, `pixel`,
  /// `viewpoint_x/y/z`.
  PointCloud cloud;
  OctreeFusionReport fusion;
  ndt::NormalEstimationReport normals;
  TriangleMesh raw_mesh;
  BallPivotingReport raw_meshing;
  /// The filtered mesh: smoothed positions, v3 normals facing the views,
  /// and the attributes `cardinality`, `flatness`, `displacement`,
  /// `excluded`.
  TriangleMesh filtered_mesh;
  ndt::SmoothingReport smoothing;
  BallPivotingReport filtered_meshing;
  std::size_t dropped_excluded = 0;  ///< with mesh_kept_points_only
  ReconstructionTimes times;
};

/// Checks the values reconstructRawlog takes before the long run: throws
/// InputError naming the field (e.g. "OctreeFusionParameters::resolution",
/// "ReconstructionParameters::auto_crop_half_size") and what was expected.
void validateReconstructionParameters(const ReconstructionParameters& params);

/// Runs the pipeline on a rawlog, a TUM RGB-D folder or a ROS 2 bag
/// (ScanReader): its scans fed to a Reconstructor in order.
/// Throws InputError naming the file and the scan for unreadable input (the
/// readers' errors, a pose file with too few or unmatched poses, a scan
/// without object points) and for bad parameters.
/// Progress stages: "poses", "registration", "fusion", "normals", "raw mesh",
/// "smoothing", "filtered mesh".
ReconstructionResult reconstructRawlog(const std::string& rawlog, const ReconstructionParameters& params = {},
                                       const ProgressCallback& progress = {});

/// How the readers are to open the input of `params` (pose file, camera,
/// bag topics and tolerances).
ScanReaderOptions scanReaderOptions(const ReconstructionParameters& params);

/// The point closest (least squares) to the lines through each pose's
/// origin along its +x axis (MRPT's optical axis); nothing when the axes
/// are (nearly) parallel.
std::optional<Eigen::Vector3d> convergencePoint(const std::vector<Eigen::Isometry3d>& sensor_poses);

}  // namespace icrkit::reconstruction
