#pragma once
/// \file
/// The reconstruction of Section II-A fed one scan at a time, from memory:
/// a camera driver's depth images, a ROS callback's frames, NumPy arrays, or
/// the readers of recordings (reconstructRawlog() is a reader feeding one).
///
///     Reconstructor reconstructor(params);
///     for (each frame) reconstructor.addDepthImage(view, meta);
///     const ReconstructionResult& r = reconstructor.update();  // cloud, meshes, report
///
/// What each scan needs alone is done as it arrives: the range correction,
/// the sensor filters (confidence, jump edges, range gate) and the board
/// pose. update() does the rest for the scans so far: the crop box (placed
/// from all the views' optical axes unless given), cropping and
/// support-plane removal (cheap: a few ms a scan), the multiway
/// registration and pose graph, the fusion at the registered poses, normals
/// and both meshes; it keeps the result until the next add(). The
/// registration is solved afresh each time: pairs chosen from the poses an
/// earlier update() reached would make the result depend on when update()
/// was called, not on the scans alone.
///
/// With `params.registration.incremental` the registration runs as the
/// scans arrive instead: once the crop box is known (given, or placed where
/// the optical axes meet once at least 3 views' axes spread by 0.5 rad), add() also
/// crops the scan, removes the support plane, aligns the view to the views
/// before it and registers it with its best-overlapping earlier views;
/// update() is left with the loop closure, the pose graph, the later
/// refinement rounds, the fusion and the meshes (an update() before the box
/// could be placed registers the scans so far the same way from scratch and
/// keeps nothing). Still a function of the scans alone, whenever update() is
/// called, but not the same as registering all views together: a view is
/// aligned to the views before it, not to those after it.
///
/// Fed the scans of a recording in order, update() gives the bytes
/// `icrkit reconstruct` writes for that recording: the file paths are this
/// class behind a reader.
///
/// One call at a time: a driver thread adding while another thread calls
/// update() needs a lock around both (Python's icrkit.Reconstructor holds
/// one). The work inside update() is parallel and deterministic.
///
/// Memory: each scan is kept as its filtered points (single precision where
/// that is exact, which MRPT's unprojection always is), their pixels, and
/// its range image; colour and confidence images are dropped once filtered.
/// It grows with the scans (1.4 MB a view of the real bunny recording, up to
/// 6 MB a full 640 x 480 frame): a 30 Hz stream wants its frames chosen
/// (every n-th, or by camera motion) before add(), as the recordings are.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/reconstruction/input/depth_image_scan.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// Points without an image grid (a lidar, a stereo matcher's output, an
/// organised cloud with its invalid points dropped): no jump-edge filter
/// (it needs neighbouring pixels), everything else as for an image.
struct PointScanMeta {
  /// The camera's pose in the object frame, optical axes (x right, y down,
  /// z forward; ROS, TUM): the points are given in this frame.
  Eigen::Isometry3d optical_pose = Eigen::Isometry3d::Identity();
  double timestamp = 0.0;  ///< seconds
  double max_range = 0.0;  ///< metres; 0: not given
};

class Reconstructor {
 public:
  /// `source` names the input in errors ("scans" for frames from memory,
  /// the path for a reader). Throws InputError for bad parameters.
  explicit Reconstructor(ReconstructionParameters params = {}, std::string source = "scans");
  ~Reconstructor();
  Reconstructor(Reconstructor&&) noexcept;
  Reconstructor& operator=(Reconstructor&&) noexcept;
  Reconstructor(const Reconstructor&) = delete;
  Reconstructor& operator=(const Reconstructor&) = delete;

  /// A scan as the readers give it (range image, points unprojected in the
  /// object frame at `sensor_pose`). Its index becomes scanCount().
  void add(RangeScan scan);
  /// A depth image (16-bit counts with a depth scale, or float metres).
  void addDepthImage(const DepthImageView& image, const DepthImageMeta& meta);
  /// Unorganised points in the camera's optical frame (finite; NaN rows
  /// are dropped as no return).
  void addPoints(const std::vector<Eigen::Vector3d>& points, const PointScanMeta& meta);

  std::size_t scanCount() const;

  /// How the input assigned its poses and, for a depth folder or bag, its
  /// camera: recorded in the result (reconstruction.json).
  void setInputDescription(std::string pose_matching, std::optional<DepthCamera> camera);

  /// Registration, fusion and (with `make_meshes`) meshes of the scans so
  /// far; the same result until the next add(). Throws InputError when
  /// there is nothing to reconstruct: no scans, a crop box that cannot be
  /// placed, a scan left without object points, a fusion of fewer than 3
  /// points. Progress stages: "registration", "fusion", "normals", "raw
  /// mesh", "smoothing", "filtered mesh".
  const ReconstructionResult& update(const ProgressCallback& progress = {});
  /// The last update()'s result, if any and still current.
  bool upToDate() const;

  /// Takes the result of update() out (no copy), for the last call.
  ReconstructionResult takeResult(const ProgressCallback& progress = {});

  /// Bytes held for the scans (points, pixels, range images, registration
  /// input; registering as the scans arrive, also the registration's point
  /// copies, SequenceRegistration::pointBytes): the memory a stream of scans
  /// costs before update().
  std::size_t storedBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace icrkit::reconstruction
