#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/reconstructor.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <string>
#include <utility>

namespace icrkit::reconstruction {

namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

ScanReaderOptions scanReaderOptions(const ReconstructionParameters& params) {
  ScanReaderOptions options;
  options.pose_file = params.pose_file;
  options.images_folder = params.images_folder;
  options.depth_camera = params.depth_camera;
  options.max_time_difference = params.max_time_difference;
  options.rotation_tolerance = params.rotation_tolerance;
  options.mcap = params.mcap;
  return options;
}

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
  if (params.up && (!params.up->allFinite() || !(params.up->norm() > 1e-9)))
    throw InputError("ReconstructionParameters::up", "", "expected a non-zero, finite direction");
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
  if (params.registration.incremental && !params.register_scans)
    throw InputError("SequenceRegistrationParameters::incremental", "",
                     "registration as the scans arrive needs registration on (register_scans)");
  if (params.register_scans) params.registration.validate();
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
  Reconstructor reconstructor(params, rawlog);
  ScanReader reader(rawlog, scanReaderOptions(params));
  double read_ms = 0.0;
  for (;;) {
    const auto start = Clock::now();
    std::optional<RangeScan> scan = reader.next();
    read_ms += millisecondsSince(start);
    if (!scan) break;
    reconstructor.add(std::move(*scan));
    reportProgress(progress, "poses", reconstructor.scanCount(), 0);
  }
  reconstructor.setInputDescription(reader.poseMatching(), reader.depthCamera());
  ReconstructionResult result = reconstructor.takeResult(progress);
  result.times.read_ms += read_ms;
  result.times.total_ms += read_ms;
  return result;
}

}  // namespace icrkit::reconstruction
