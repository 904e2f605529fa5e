#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/meshing/raw_and_filtered_meshes.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <string>
#include <utility>

namespace icrkit::reconstruction {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

ScanReaderOptions readerOptions(const ReconstructionParameters& params, bool unproject) {
  ScanReaderOptions options;
  options.pose_file = params.pose_file;
  options.images_folder = params.images_folder;
  options.depth_camera = params.depth_camera;
  options.max_time_difference = params.max_time_difference;
  options.rotation_tolerance = params.rotation_tolerance;
  options.unproject = unproject;
  return options;
}

// The filters of one scan: the sensor filters change `scan` (every point
// left still carves free space in the fusion); cropping and support-plane
// removal only decide which of its points belong to the object (`object`,
// one flag per point of `scan.points`).
ScanFilterRecord filterScan(RangeScan& scan, const ReconstructionParameters& params, const Eigen::AlignedBox3d& box,
                            std::vector<std::uint8_t>& object) {
  ScanFilterRecord record;
  record.index = scan.index;
  record.timestamp = scan.timestamp;
  correctRange(scan, params.range_correction);
  record.valid_pixels = scan.validPixels();
  record.removed_confidence = filterConfidence(scan, params.confidence).removed;
  if (params.jump_edge_filter) record.removed_jump_edges = filterJumpEdges(scan, params.jump_edges).removed;
  record.removed_range = filterRange(scan, params.range).removed;

  RangeScan cropped = scan;
  record.removed_crop = filterCropBox(cropped, box).removed;
  if (params.remove_support_plane) {
    PlaneRemovalParameters plane = params.support_plane;
    // The table or plate lies somewhere in the box's lower half.
    plane.band = 0.5 * box.sizes().z();
    const PlaneRemovalReport report = removeSupportPlane(cropped, box, plane);
    record.removed_plane = report.removed;
    record.plane_found = report.found;
  }
  const std::size_t pixel_count = static_cast<std::size_t>(scan.width) * static_cast<std::size_t>(scan.height);
  std::vector<std::uint8_t> kept_pixel(pixel_count, 0);
  for (std::uint32_t pixel : cropped.pixels) kept_pixel[pixel] = 1;
  object.assign(scan.points.size(), 0);
  for (std::size_t k = 0; k < scan.points.size(); ++k) object[k] = kept_pixel[scan.pixels[k]];
  record.object_points = cropped.points.size();
  return record;
}

// The object's points in the sensor's own frame (the registration's input).
PointCloud objectPointsInSensorFrame(const RangeScan& scan, const std::vector<std::uint8_t>& object) {
  PointCloud cloud;
  const Eigen::Isometry3d to_sensor = scan.sensor_pose.inverse();
  for (std::size_t k = 0; k < scan.points.size(); ++k)
    if (object[k]) cloud.positions.push_back(to_sensor * scan.points[k]);
  return cloud;
}

// Scan i of a pass over the recording, filtered (see filterScan), with the
// reading and filtering times added to `times`.
// With `board_pose`, the checkerboard pose is taken from the scan as read
// (before any filter touches its range image).
RangeScan nextFilteredScan(ScanReader& reader, const std::string& rawlog, std::size_t i,
                           const ReconstructionParameters& params, const Eigen::AlignedBox3d& box,
                           std::vector<std::uint8_t>& object, ScanFilterRecord& record, ReconstructionTimes& times,
                           LatticePose* board_pose = nullptr) {
  auto start = Clock::now();
  std::optional<RangeScan> scan = reader.next();
  if (!scan) throw InputError(rawlog, "scan " + std::to_string(i), "the file changed while it was being read");
  times.read_ms += msSince(start);
  if (board_pose && params.board) {
    start = Clock::now();
    *board_pose = latticeCameraPose(*scan, *params.board, params.board_detection);
    times.registration_ms += msSince(start);
  }
  start = Clock::now();
  record = filterScan(*scan, params, box, object);
  times.filter_ms += msSince(start);
  return std::move(*scan);
}

void report(const ProgressCallback& progress, const char* stage, std::size_t done, std::size_t total) {
  if (progress) progress(stage, done, total);
}

}  // namespace

std::optional<Eigen::Vector3d> convergencePoint(const std::vector<Eigen::Isometry3d>& sensor_poses) {
  // Minimises the summed squared distances to the lines o + s d:
  // sum (I - d d^T) x = sum (I - d d^T) o.
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& pose : sensor_poses) {
    const Eigen::Vector3d d = pose.rotation().col(0).normalized();
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p;
    b += p * pose.translation();
  }
  if (sensor_poses.size() < 2) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(a);
  // Parallel axes leave the point free along them.
  if (!(eigen.eigenvalues()(0) > 1e-3 * eigen.eigenvalues()(2))) return std::nullopt;
  const Eigen::Vector3d x = a.ldlt().solve(b);
  if (!x.allFinite()) return std::nullopt;
  return x;
}

void validateReconstructionParameters(const ReconstructionParameters& params) {
  if (!(params.rotation_tolerance >= 0) || !std::isfinite(params.rotation_tolerance))
    throw InputError("ReconstructionParameters::rotation_tolerance", "", "expected max |R^T R - I| >= 0");
  if (!(params.auto_crop_half_size > 0) || !std::isfinite(params.auto_crop_half_size))
    throw InputError("ReconstructionParameters::auto_crop_half_size", "", "expected a positive half-size in metres");
  if (params.crop_box && (params.crop_box->isEmpty() || !params.crop_box->min().allFinite() ||
                          !params.crop_box->max().allFinite()))
    throw InputError("ReconstructionParameters::crop_box", "", "expected finite corners with min < max");
  if (params.board && (!(params.board->square_size > 0) || !std::isfinite(params.board->square_size)))
    throw InputError("BoardLattice::square_size", "", "expected the checkerboard's square size in metres (> 0)");
  if (params.board && !params.register_scans)
    throw InputError("ReconstructionParameters::board", "",
                     "the checkerboard poses enter the registration's pose graph; registration is off");
  if (params.confidence.min_confidence < 0 || params.confidence.min_confidence > 255)
    throw InputError("ConfidenceFilterParameters::min_confidence", "", "expected 0..255");
  if (params.confidence.min_amplitude < 0 || params.confidence.min_amplitude > 255)
    throw InputError("ConfidenceFilterParameters::min_amplitude", "", "expected 0..255");
  if (!(params.range.max_range >= 0) || !std::isfinite(params.range.max_range))
    throw InputError("RangeGateParameters::max_range", "", "expected 0 (none) or metres");
  if (!(params.fusion.resolution > 0) || !std::isfinite(params.fusion.resolution))
    throw InputError("OctreeFusionParameters::resolution", "", "expected metres > 0");
  params.smoothing.validate();
  params.meshing.validate();
}

ReconstructionResult reconstructRawlog(const std::string& rawlog, const ReconstructionParameters& params,
                                       const ProgressCallback& progress) {
  const auto total_start = Clock::now();
  validateReconstructionParameters(params);
  ReconstructionResult result;
  ReconstructionTimes& times = result.times;

  // Pass 0: the poses only, for the automatic crop box and the scan count.
  {
    const auto start = Clock::now();
    ScanReader reader(rawlog, readerOptions(params, false));
    while (auto scan = reader.next()) {
      result.reported_poses.push_back(scan->sensor_pose);
      result.timestamps.push_back(scan->timestamp);
      result.poses_orthonormalised += scan->pose_orthonormalised;
      report(progress, "poses", result.reported_poses.size(), 0);
    }
    result.pose_matching = reader.poseMatching();
    result.depth_camera = reader.depthCamera();
    times.read_ms += msSince(start);
  }
  const std::size_t n = result.reported_poses.size();
  if (params.crop_box) {
    result.crop_box = *params.crop_box;
  } else {
    const std::optional<Eigen::Vector3d> centre = convergencePoint(result.reported_poses);
    const bool one_pose = n > 1 && std::all_of(result.reported_poses.begin(), result.reported_poses.end(),
                                               [&](const Eigen::Isometry3d& p) {
                                                 return p.isApprox(result.reported_poses.front(), 1e-12);
                                               });
    if (!centre && one_pose)
      throw InputError(rawlog, "",
                       "every view has the same pose (a depth folder read without a pose file has none): "
                       "give the camera poses (ReconstructionParameters::pose_file, a TUM file) or the "
                       "object's region (ReconstructionParameters::crop_box)");
    if (!centre)
      throw InputError(rawlog, "", "cannot place the crop box: the views' optical axes do not converge on an object "
                                   "(give the object's region explicitly)");
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(params.auto_crop_half_size);
    result.crop_box = Eigen::AlignedBox3d(*centre - half, *centre + half);
    result.crop_box_automatic = true;
  }

  // Pass 1: filters and scan-to-model registration.
  std::optional<SequenceRegistration> registration;
  if (params.register_scans) registration.emplace(params.registration);
  {
    ScanReader reader(rawlog, readerOptions(params, true));
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<std::uint8_t> object;
      ScanFilterRecord& record = result.filters.emplace_back();
      LatticePose board_pose;
      const RangeScan scan =
          nextFilteredScan(reader, rawlog, i, params, result.crop_box, object, record, times, &board_pose);
      std::optional<PosePrior> board_prior;
      if (params.board) {
        bool rejected = false;
        if (board_pose.found) {
          const Eigen::Isometry3d change = scan.sensor_pose.inverse() * board_pose.sensor_pose;
          rejected = change.translation().norm() > 0.5 * params.board->square_size ||
                     Eigen::AngleAxisd(change.rotation()).angle() > params.board_max_rotation;
        }
        if (board_pose.found && !rejected) {
          board_prior = PosePrior{board_pose.sensor_pose, params.board_prior_sigma_translation,
                                  params.board_prior_sigma_rotation};
          ++result.poses_from_board;
        }
        result.board_poses.push_back(board_pose);
        result.board_pose_rejected.push_back(rejected ? 1 : 0);
      }
      if (record.object_points == 0)
        throw InputError(rawlog, "scan " + std::to_string(i),
                         "no points left inside the crop box after filtering (check the crop box and the poses)");
      if (i == 0) {
        std::vector<Eigen::Vector3d> object_points;
        for (std::size_t k = 0; k < scan.points.size(); ++k)
          if (object[k]) object_points.push_back(scan.points[k]);
        result.scan_spacing_m = nearestNeighbourSpacing(object_points).median;
      }
      if (registration) {
        const auto start = Clock::now();
        PointCloud points = objectPointsInSensorFrame(scan, object);
        registration->add(points, scan.sensor_pose, board_prior);
        if (params.keep_registration_input) result.registration_input.push_back(std::move(points));
        times.registration_ms += msSince(start);
      }
      report(progress, "registration", i + 1, n);
    }
  }
  if (registration) {
    const auto start = Clock::now();
    result.registration = registration->finish();
    registration.reset();
    result.poses = result.registration.poses;
    times.registration_ms += msSince(start);
  } else {
    result.poses = result.reported_poses;
  }

  // Pass 2: fusion of the whole scans at their registered poses.
  OctreeFusionParameters fusion_params = params.fusion;
  fusion_params.bounds = result.crop_box;
  {
    OctreeFusion fusion(fusion_params);
    ScanReader reader(rawlog, readerOptions(params, true));
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<std::uint8_t> object;
      ScanFilterRecord record;
      RangeScan scan = nextFilteredScan(reader, rawlog, i, params, result.crop_box, object, record, times);
      const auto start = Clock::now();
      const Eigen::Isometry3d correction = result.poses[i] * scan.sensor_pose.inverse();
      for (Eigen::Vector3d& p : scan.points) p = correction * p;
      scan.sensor_pose = result.poses[i];
      fusion.insert(scan, object);
      times.fusion_ms += msSince(start);
      report(progress, "fusion", i + 1, n);
    }
    const auto start = Clock::now();
    OctreeFusionResult fused = fusion.finish();
    times.fusion_ms += msSince(start);
    result.cloud = std::move(fused.points);
    result.fusion = fused.report;
  }
  if (result.cloud.positions.size() < 3)
    throw InputError(rawlog, "", "only " + std::to_string(result.cloud.positions.size()) +
                                     " points survived the fusion: nothing to reconstruct");

  // Each point's sensor, for the raw normals and the smoothed ones (the
  // smoothing keeps the point order).
  const std::vector<Eigen::Vector3d> viewpoints = fusionViewpoints(result.cloud);
  {
    const auto start = Clock::now();
    report(progress, "normals", 0, 1);
    ndt::NormalEstimationParameters normals = params.normals;
    // Like the smoothing window: a multiple of one scan's spacing. The fused
    // cloud's own spacing is many times finer (every view adds points) while
    // its noise layer is as thick as one scan's noise, so a window scaled to
    // it sees noise, not the surface (raw normals 40-45 deg off the CAD
    // normals on the Kinect datasets).
    if (normals.radius.relative && result.scan_spacing_m > 0)
      normals.radius = Length::metres(normals.radius.metresFor(result.scan_spacing_m));
    normals.viewpoints = viewpoints;
    result.normals = ndt::estimateNormals(result.cloud, normals);
    times.normals_ms = msSince(start);
  }
  if (params.make_meshes) {
    RawAndFilteredParameters meshing;
    meshing.smoothing = params.smoothing;
    // The smoothing window, like the normals', is a multiple of one scan's
    // spacing (see ReconstructionParameters::smoothing).
    meshing.reference_spacing = result.scan_spacing_m;
    meshing.meshing = params.meshing;
    meshing.thin_raw_cloud = params.thin_raw_cloud;
    meshing.mesh_kept_points_only = params.mesh_kept_points_only;
    RawAndFilteredMeshes meshes = meshRawAndFiltered(result.cloud, meshing, viewpoints, progress);
    result.raw_mesh = std::move(meshes.raw);
    result.raw_meshing = meshes.raw_meshing;
    result.filtered_mesh = std::move(meshes.filtered);
    result.filtered_meshing = meshes.filtered_meshing;
    result.smoothing = meshes.smoothing;
    result.dropped_excluded = meshes.dropped_excluded;
    times.raw_mesh_ms = meshes.times.raw_mesh_ms;
    times.smoothing_ms = meshes.times.smoothing_ms;
    times.filtered_mesh_ms = meshes.times.filtered_mesh_ms;
  }
  times.total_ms = msSince(total_start);
  return result;
}

}  // namespace icrkit::reconstruction
