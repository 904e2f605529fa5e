#pragma once
/// \file
/// Free-space fusion of registered scans with an OctoMap occupancy octree.
///
/// Every scan is inserted from its sensor origin (rays mark the voxels they
/// cross as free, their end points as occupied); a point is then kept when
/// its voxel is occupied after all scans. Points that other views see
/// through (flying pixels, a double layer from a misregistered view,
/// outliers in front of the surface) land in free voxels and are dropped.
/// The octree only decides; the kept points are the measured ones at full
/// resolution, each with the view it came from, so that normals can be
/// oriented towards the sensor later.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

struct OctreeFusionParameters {
  /// Voxel edge (metres). A few times the sensor's noise: finer voxels let
  /// neighbouring rays of another view carve real, noisy surface.
  double resolution = 0.004;
  /// Rays are cut at this length (metres, > 0); unset: each scan's max_range.
  std::optional<double> max_range;
  /// Only this region is updated (object frame); an empty box: no limit.
  /// Rays are clipped to it, so points outside still carve the space their
  /// rays cross inside it: pass whole scans, not cropped ones. Points
  /// outside it are dropped (their voxels are unknown).
  Eigen::AlignedBox3d bounds;
  /// OctoMap's sensor model (its defaults): hit and miss probabilities,
  /// clamping, and the occupancy threshold applied at the end.
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamping_min = 0.1192;
  double clamping_max = 0.971;
  double occupancy_threshold = 0.5;
};

struct OctreeFusionReport {
  std::size_t scans = 0;
  std::size_t points_in = 0;
  std::size_t kept = 0;
  std::size_t dropped_free = 0;     ///< their voxel ended up free
  std::size_t dropped_outside = 0;  ///< outside `bounds` or the ray length
  std::vector<std::size_t> kept_per_scan;
  std::size_t occupied_leaves = 0;
  std::size_t leaves = 0;
  double time_ms = 0.0;
};

struct OctreeFusionResult {
  /// The kept points in scan order with the attributes `view` (Int32, the
  /// scan index), `pixel` (UInt32, row * width + col) and `viewpoint_x`,
  /// `viewpoint_y`, `viewpoint_z` (Float64, the sensor origin, metres,
  /// object frame).
  PointCloud points;
  OctreeFusionReport report;
};

/// Incremental fusion, one registered scan at a time, so that a recording
/// never has to sit in memory: only the candidate points (the fused model)
/// are kept between scans.
///
///     OctreeFusion fusion(params);
///     for (each scan) fusion.insert(scan, object_mask);
///     OctreeFusionResult result = fusion.finish();
class OctreeFusion {
public:
  /// Throws InputError for a non-positive resolution or probabilities
  /// outside (0, 1).
  explicit OctreeFusion(const OctreeFusionParameters& params = {});
  ~OctreeFusion();
  OctreeFusion(const OctreeFusion&) = delete;
  OctreeFusion& operator=(const OctreeFusion&) = delete;

  /// Carves and marks the octree with every point of `scan` (already in
  /// the common frame, from `scan.sensor_pose`'s origin). `candidate`, when
  /// not empty, has one flag per point of `scan.points`: only flagged points
  /// may appear in the output (e.g. the object's points after cropping and
  /// support-plane removal), while every point's ray still carves. Throws
  /// InputError (naming the scan) when `candidate` has the wrong size.
  void insert(const RangeScan& scan, const std::vector<std::uint8_t>& candidate = {});
  /// Several scans, in order: the same tree and model as insert() called
  /// for each in turn. Tracing their rays, the costly part that reads
  /// nothing of the tree, runs in parallel; the updates follow in order,
  /// each as soon as its scan is traced. `candidates`: empty, or one mask
  /// per scan. An insertion that fails part-way (out of memory) leaves the
  /// fusion refusing every later call (std::logic_error): some of its scans
  /// may be in the tree.
  void insert(const std::vector<RangeScan>& scans, const std::vector<std::vector<std::uint8_t>>& candidates);

  /// Decides which candidates survive; the fusion cannot be used afterwards.
  OctreeFusionResult finish();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Fuses scans already in a common frame (their `points` and
/// `sensor_pose`); every point is a candidate. Deterministic: the octree
/// does not depend on thread timing, and points are emitted in input order.
/// Throws InputError for a non-positive resolution or probabilities outside
/// (0, 1).
OctreeFusionResult fuseScans(const std::vector<RangeScan>& scans, const OctreeFusionParameters& params = {});

/// Each point's sensor position from the fusion's `viewpoint_x/y/z`
/// attributes (for orienting normals); empty when the cloud lacks them.
std::vector<Eigen::Vector3d> fusionViewpoints(const PointCloud& cloud);

}  // namespace icrkit::reconstruction
