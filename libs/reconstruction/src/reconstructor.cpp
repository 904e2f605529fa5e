#include <icrkit/reconstruction/reconstructor.hpp>

#include <icrkit/core/elapsed.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/core/kd_tree.hpp>
#include <icrkit/core/morton_order.hpp>
#include <icrkit/core/progress.hpp>
#include <icrkit/reconstruction/input/up_axis.hpp>
#include <icrkit/reconstruction/meshing/raw_and_filtered_meshes.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <string>
#include <utility>

namespace icrkit::reconstruction {

namespace {

using Clock = std::chrono::steady_clock;

// One scan as kept between add() and update(): its filtered range image and
// points. MRPT unprojects in single precision, so the points are kept as
// floats whenever that loses nothing (everything but a range-corrected ToF
// scan), which halves the largest part of the memory a stream costs.
struct StoredScan {
  RangeScan scan;  // `points` moved to `float_points` when exact
  std::vector<Eigen::Vector3f> float_points;
  bool points_as_float = false;
  bool organised = true;
  LatticePose board_pose;
  ScanFilterRecord sensor_filters;  // what the filters of add() did

  std::size_t bytes() const {
    return scan.range.size() * sizeof(float) + scan.pixels.size() * sizeof(std::uint32_t) +
           scan.points.size() * sizeof(Eigen::Vector3d) + float_points.size() * sizeof(Eigen::Vector3f);
  }

  RangeScan restore() const {
    RangeScan copy = scan;
    if (points_as_float) {
      copy.points.resize(float_points.size());
      for (std::size_t k = 0; k < float_points.size(); ++k) copy.points[k] = float_points[k].cast<double>();
    }
    return copy;
  }
};

bool exactInFloat(const std::vector<Eigen::Vector3d>& points) {
  for (const Eigen::Vector3d& p : points)
    for (int k = 0; k < 3; ++k)
      if (static_cast<double>(static_cast<float>(p[k])) != p[k]) return false;
  return true;
}

// Cropping and support-plane removal only decide which of a scan's points
// belong to the object (`object`, one flag per point): every point left by
// the sensor filters still carves free space in the fusion.
void selectObjectPoints(const RangeScan& scan, const ReconstructionParameters& params, const Eigen::AlignedBox3d& box,
                        const Eigen::Vector3d& up, std::vector<std::uint8_t>& object, ScanFilterRecord& record) {
  RangeScan cropped = scan;
  record.removed_crop = filterCropBox(cropped, box).removed;
  if (params.remove_support_plane) {
    PlaneRemovalParameters plane = params.support_plane;
    plane.up = up;
    // The table or plate lies somewhere in the box's lower half.
    plane.band = 0.5 * box.sizes().dot(up.cwiseAbs());
    const PlaneRemovalReport removal = removeSupportPlane(cropped, box, plane);
    record.removed_plane = removal.removed;
    record.plane_found = removal.found;
  }
  const std::size_t pixel_count = static_cast<std::size_t>(scan.width) * static_cast<std::size_t>(scan.height);
  std::vector<std::uint8_t> kept_pixel(pixel_count, 0);
  for (std::uint32_t pixel : cropped.pixels) kept_pixel[pixel] = 1;
  object.assign(scan.points.size(), 0);
  for (std::size_t k = 0; k < scan.points.size(); ++k) object[k] = kept_pixel[scan.pixels[k]];
  record.object_points = cropped.points.size();
}

// The object's points in the sensor's own frame (the registration's input).
PointCloud objectPointsInSensorFrame(const RangeScan& scan, const std::vector<std::uint8_t>& object) {
  PointCloud cloud;
  const Eigen::Isometry3d to_sensor = scan.sensor_pose.inverse();
  for (std::size_t k = 0; k < scan.points.size(); ++k)
    if (object[k]) cloud.positions.push_back(to_sensor * scan.points[k]);
  return cloud;
}

// The views' optical axes must spread this far (radians, from the first
// view's) before an automatic crop box is placed from them as the scans
// arrive: nearly parallel axes meet far from the object.
constexpr double kAutoCropSpread = 0.5;

// Whether the optical axes (MRPT sensor x) of `poses` spread enough to
// place the automatic crop box where they meet.
bool axesSpread(const std::vector<Eigen::Isometry3d>& poses) {
  if (poses.size() < 3) return false;
  const Eigen::Vector3d first = poses.front().rotation().col(0).normalized();
  for (const Eigen::Isometry3d& pose : poses)
    if (std::acos(std::clamp(first.dot(pose.rotation().col(0).normalized()), -1.0, 1.0)) >= kAutoCropSpread)
      return true;
  return false;
}

// What the crop box and the board make of one scan: its object points,
// the filter record, and the board's pose prior.
struct SelectedScan {
  std::vector<std::uint8_t> object;
  ScanFilterRecord record;
  LatticePose board_pose;
  bool board_rejected = false;
  std::optional<PosePrior> board_prior;
};

}  // namespace

struct Reconstructor::Impl {
  ReconstructionParameters params;
  std::string source;
  std::vector<StoredScan> scans;
  std::string pose_matching = "recorded";
  std::optional<DepthCamera> camera;
  std::size_t poses_orthonormalised = 0;
  double add_filter_ms = 0.0;
  double add_read_ms = 0.0;
  double add_board_ms = 0.0;
  std::optional<ReconstructionResult> result;

  std::string where(std::size_t i) const { return "scan " + std::to_string(i); }

  void store(RangeScan scan, bool organised, double convert_ms) {
    result.reset();
    add_read_ms += convert_ms;
    StoredScan stored;
    stored.organised = organised;
    scan.index = scans.size();
    // The board is found in the scan as read, before any filter touches it.
    if (params.board) {
      const auto start = Clock::now();
      stored.board_pose = latticeCameraPose(scan, *params.board, params.board_detection);
      add_board_ms += millisecondsSince(start);
    }
    const auto start = Clock::now();
    ScanFilterRecord& record = stored.sensor_filters;
    record.index = scan.index;
    record.timestamp = scan.timestamp;
    correctRange(scan, params.range_correction);
    record.valid_pixels = scan.validPixels();
    record.removed_confidence = filterConfidence(scan, params.confidence).removed;
    if (params.jump_edge_filter && organised) record.removed_jump_edges = filterJumpEdges(scan, params.jump_edges).removed;
    if (organised) record.removed_foreground_edges = filterForegroundEdges(scan, params.foreground_edges).removed;
    record.removed_range = filterRange(scan, params.range).removed;
    add_filter_ms += millisecondsSince(start);
    poses_orthonormalised += scan.pose_orthonormalised;
    // Only the range image, the points and their pixels are used from here on.
    scan.intensity = Image8{};
    scan.confidence = Image8{};
    if (exactInFloat(scan.points)) {
      stored.float_points.reserve(scan.points.size());
      for (const Eigen::Vector3d& p : scan.points) stored.float_points.push_back(p.cast<float>());
      stored.points_as_float = true;
      std::vector<Eigen::Vector3d>().swap(scan.points);
    }
    stored.scan = std::move(scan);
    scans.push_back(std::move(stored));
    if (params.registration.incremental) {
      placeBox();
      advance();
    }
  }

  SelectedScan select(const StoredScan& stored, const RangeScan& scan, const Eigen::AlignedBox3d& box,
                      const Eigen::Vector3d& up) const;

  // The given up direction, else the one the poses suggest.
  Eigen::Vector3d upFrom(const std::vector<Eigen::Isometry3d>& poses) const {
    return params.up ? params.up->normalized() : estimateUpAxis(poses);
  }

  // Registration as the scans arrive (params.registration.incremental):
  // once the crop box is known, every scan is selected and registered by
  // add(); update() solves the graph from there.
  std::optional<Eigen::AlignedBox3d> live_box;
  bool live_box_automatic = false;
  Eigen::Vector3d live_up = Eigen::Vector3d::UnitZ();
  std::optional<SequenceRegistration> live;
  std::vector<SelectedScan> live_scans;  // per scan handed to `live`
  std::optional<InputError> live_error;  // a scan that cannot be registered: thrown by update()
  double live_filter_ms = 0.0;
  double live_registration_ms = 0.0;
  double live_spacing_m = 0.0;
  void placeBox();
  void advance();

  ReconstructionResult compute(const ProgressCallback& progress);
};

SelectedScan Reconstructor::Impl::select(const StoredScan& stored, const RangeScan& scan,
                                         const Eigen::AlignedBox3d& box, const Eigen::Vector3d& up) const {
  SelectedScan out;
  out.record = stored.sensor_filters;
  selectObjectPoints(scan, params, box, up, out.object, out.record);
  if (params.board) {
    const LatticePose& board_pose = stored.board_pose;
    if (board_pose.found) {
      const Eigen::Isometry3d change = scan.sensor_pose.inverse() * board_pose.sensor_pose;
      out.board_rejected = change.translation().norm() > 0.5 * params.board->square_size ||
                           Eigen::AngleAxisd(change.rotation()).angle() > params.board_max_rotation;
    }
    if (board_pose.found && !out.board_rejected)
      out.board_prior =
          PosePrior{board_pose.sensor_pose, params.board_prior_sigma_translation, params.board_prior_sigma_rotation};
    out.board_pose = board_pose;
  }
  return out;
}

void Reconstructor::Impl::placeBox() {
  if (live_box) return;
  std::vector<Eigen::Isometry3d> poses;
  for (const StoredScan& s : scans) poses.push_back(s.scan.sensor_pose);
  // Decided with the box, from the same views, and kept with it.
  live_up = upFrom(poses);
  if (params.crop_box) {
    live_box = *params.crop_box;
    return;
  }
  if (!axesSpread(poses)) return;
  if (const std::optional<Eigen::Vector3d> centre = convergencePoint(poses)) {
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(params.auto_crop_half_size);
    live_box = Eigen::AlignedBox3d(*centre - half, *centre + half);
    live_box_automatic = true;
  }
}

void Reconstructor::Impl::advance() {
  if (!live_box || live_error) return;
  if (!live && params.register_scans) live.emplace(params.registration);
  while (live_scans.size() < scans.size()) {
    const std::size_t i = live_scans.size();
    auto start = Clock::now();
    const RangeScan scan = scans[i].restore();
    SelectedScan selected = select(scans[i], scan, *live_box, live_up);
    live_filter_ms += millisecondsSince(start);
    if (selected.record.object_points == 0) {
      live_error = InputError(source, where(i),
                              "no points left inside the crop box after filtering (check the crop box and the poses)");
      return;
    }
    if (i == 0) {
      std::vector<Eigen::Vector3d> object_points;
      for (std::size_t k = 0; k < scan.points.size(); ++k)
        if (selected.object[k]) object_points.push_back(scan.points[k]);
      live_spacing_m = nearestNeighbourSpacing(object_points).median;
    }
    if (live) {
      start = Clock::now();
      try {
        live->add(objectPointsInSensorFrame(scan, selected.object), scan.sensor_pose, selected.board_prior);
      } catch (const InputError& e) {
        live_error = e;
        return;
      }
      live_registration_ms += millisecondsSince(start);
    }
    live_scans.push_back(std::move(selected));
  }
}

Reconstructor::Reconstructor(ReconstructionParameters params, std::string source) : impl_(std::make_unique<Impl>()) {
  validateReconstructionParameters(params);
  impl_->params = std::move(params);
  impl_->source = std::move(source);
}

Reconstructor::~Reconstructor() = default;
Reconstructor::Reconstructor(Reconstructor&&) noexcept = default;
Reconstructor& Reconstructor::operator=(Reconstructor&&) noexcept = default;

void Reconstructor::add(RangeScan scan) {
  const std::size_t i = impl_->scans.size();
  if (scan.width <= 0 || scan.height <= 0 ||
      scan.range.size() != static_cast<std::size_t>(scan.width) * static_cast<std::size_t>(scan.height))
    throw InputError(impl_->source, impl_->where(i), "expected a range image of width x height values");
  if (scan.points.size() != scan.pixels.size())
    throw InputError(impl_->source, impl_->where(i), "expected one pixel per point");
  for (std::size_t k = 0; k < scan.points.size(); ++k) {
    if (!scan.points[k].allFinite())
      throw InputError(impl_->source, impl_->where(i) + " point " + std::to_string(k), "non-finite coordinate");
    if (scan.pixels[k] >= scan.range.size())
      throw InputError(impl_->source, impl_->where(i) + " point " + std::to_string(k),
                       "its pixel lies outside the range image");
  }
  if (!scan.sensor_pose.matrix().allFinite())
    throw InputError(impl_->source, impl_->where(i), "non-finite sensor pose");
  impl_->store(std::move(scan), true, 0.0);
}

void Reconstructor::addDepthImage(const DepthImageView& image, const DepthImageMeta& meta) {
  const auto start = Clock::now();
  if (!meta.sensor_pose.matrix().allFinite())
    throw InputError(impl_->source, impl_->where(impl_->scans.size()), "non-finite camera pose");
  DepthImageMeta unprojected = meta;
  unprojected.unproject = true;
  RangeScan scan = scanFromDepthImage(image, unprojected, impl_->scans.size(), impl_->source);
  impl_->store(std::move(scan), true, millisecondsSince(start));
}

void Reconstructor::addPoints(const std::vector<Eigen::Vector3d>& points, const PointScanMeta& meta) {
  const auto start = Clock::now();
  const std::size_t i = impl_->scans.size();
  if (!meta.optical_pose.matrix().allFinite())
    throw InputError(impl_->source, impl_->where(i), "non-finite camera pose");
  RangeScan scan;
  scan.timestamp = meta.timestamp;
  scan.sensor_label = "POINTS";
  scan.sensor_pose = opticalToSensorPose(meta.optical_pose);
  // One row of "pixels", one per point, each holding the point's distance
  // along its ray: the range gate and the fusion's rays read it so.
  scan.range_is_depth = false;
  scan.max_range = meta.max_range;
  scan.camera.fx = scan.camera.fy = 1.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d& p = points[k];
    if (std::isinf(p.x()) || std::isinf(p.y()) || std::isinf(p.z()))
      throw InputError(impl_->source, impl_->where(i) + " point " + std::to_string(k),
                       "infinite coordinate (NaN marks no return)");
    if (!p.allFinite()) continue;
    const double distance = p.norm();
    if (!(distance > 0)) continue;
    scan.range.push_back(static_cast<float>(distance));
    scan.pixels.push_back(static_cast<std::uint32_t>(scan.points.size()));
    scan.points.push_back(meta.optical_pose * p);
  }
  scan.width = static_cast<int>(scan.range.size());
  scan.height = 1;
  if (scan.width == 0) throw InputError(impl_->source, impl_->where(i), "no finite point");
  scan.camera.width = scan.width;
  scan.camera.height = 1;
  scan.camera_intensity = scan.camera;
  impl_->store(std::move(scan), false, millisecondsSince(start));
}

std::size_t Reconstructor::scanCount() const { return impl_->scans.size(); }

void Reconstructor::setInputDescription(std::string pose_matching, std::optional<DepthCamera> camera) {
  impl_->pose_matching = std::move(pose_matching);
  impl_->camera = std::move(camera);
  if (impl_->result) {
    impl_->result->pose_matching = impl_->pose_matching;
    impl_->result->depth_camera = impl_->camera;
  }
}

const ReconstructionResult& Reconstructor::update(const ProgressCallback& progress) {
  if (!impl_->result) impl_->result = impl_->compute(progress);
  return *impl_->result;
}

bool Reconstructor::upToDate() const { return impl_->result.has_value(); }

ReconstructionResult Reconstructor::takeResult(const ProgressCallback& progress) {
  update(progress);
  ReconstructionResult out = std::move(*impl_->result);
  impl_->result.reset();
  return out;
}

std::size_t Reconstructor::storedBytes() const {
  std::size_t bytes = 0;
  for (const StoredScan& s : impl_->scans) bytes += s.bytes();
  if (impl_->live) bytes += impl_->live->pointBytes();
  return bytes;
}

ReconstructionResult Reconstructor::Impl::compute(const ProgressCallback& progress) {
  const auto total_start = Clock::now();
  ReconstructionResult result;
  ReconstructionTimes& times = result.times;
  times.read_ms = add_read_ms;
  times.filter_ms = add_filter_ms;
  times.registration_ms = add_board_ms;
  result.pose_matching = pose_matching;
  result.depth_camera = camera;
  result.poses_orthonormalised = poses_orthonormalised;
  const std::size_t n = scans.size();
  if (n == 0) throw InputError(source, "", "no scans to reconstruct");
  for (const StoredScan& s : scans) {
    result.reported_poses.push_back(s.scan.sensor_pose);
    result.timestamps.push_back(s.scan.timestamp);
  }

  // Registered as the scans arrived: once the crop box could be placed.
  // Before that (views not yet spread) the scans so far are registered
  // here the same way, from scratch, and nothing is kept: the box a later
  // scan places must not depend on when update() was called.
  const bool incremental = params.registration.incremental && live_box.has_value();
  result.up = incremental ? live_up : upFrom(result.reported_poses);
  result.up_automatic = !params.up.has_value();
  if (params.crop_box) {
    result.crop_box = *params.crop_box;
  } else if (incremental) {
    // Placed as the scans arrived, from the first views that spread enough.
    result.crop_box = *live_box;
    result.crop_box_automatic = live_box_automatic;
  } else {
    const std::optional<Eigen::Vector3d> centre = convergencePoint(result.reported_poses);
    const bool one_pose = n > 1 && std::all_of(result.reported_poses.begin(), result.reported_poses.end(),
                                               [&](const Eigen::Isometry3d& p) {
                                                 return p.isApprox(result.reported_poses.front(), 1e-12);
                                               });
    if (!centre && one_pose)
      throw InputError(source, "",
                       "every view has the same pose (a depth folder read without a pose file has none): "
                       "give the camera poses (ReconstructionParameters::pose_file, a TUM file) or the "
                       "object's region (ReconstructionParameters::crop_box)");
    if (!centre)
      throw InputError(source, "", "cannot place the crop box: the views' optical axes do not converge on an object "
                                   "(give the object's region explicitly)");
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(params.auto_crop_half_size);
    result.crop_box = Eigen::AlignedBox3d(*centre - half, *centre + half);
    result.crop_box_automatic = true;
  }

  // The object's points of every scan, and their registration.
  std::vector<std::vector<std::uint8_t>> objects(n);
  auto record = [&](SelectedScan& selected) {
    result.filters.push_back(selected.record);
    if (params.board) {
      if (selected.board_prior) ++result.poses_from_board;
      result.board_poses.push_back(selected.board_pose);
      result.board_pose_rejected.push_back(selected.board_rejected ? 1 : 0);
    }
  };
  if (incremental) {
    advance();
    if (live_error) throw *live_error;
    times.filter_ms += live_filter_ms;
    times.registration_ms += live_registration_ms;
    result.scan_spacing_m = live_spacing_m;
    for (std::size_t i = 0; i < n; ++i) {
      SelectedScan& selected = live_scans[i];
      record(selected);
      // Kept for the next update(): more scans may come.
      objects[i] = selected.object;
      if (params.keep_registration_input)
        result.registration_input.push_back(objectPointsInSensorFrame(scans[i].restore(), selected.object));
    }
    reportProgress(progress, "registration", n, n);
    if (live) {
      const auto start = Clock::now();
      result.registration = live->finish();
      result.poses = result.registration.poses;
      times.registration_ms += millisecondsSince(start);
    } else {
      result.poses = result.reported_poses;
    }
  } else {
    std::optional<SequenceRegistration> registration;
    if (params.register_scans) registration.emplace(params.registration);
    for (std::size_t i = 0; i < n; ++i) {
      const StoredScan& stored = scans[i];
      auto start = Clock::now();
      const RangeScan scan = stored.restore();
      SelectedScan selected = select(stored, scan, result.crop_box, result.up);
      record(selected);
      objects[i] = std::move(selected.object);
      times.filter_ms += millisecondsSince(start);
      if (result.filters.back().object_points == 0)
        throw InputError(source, where(i),
                         "no points left inside the crop box after filtering (check the crop box and the poses)");
      if (i == 0) {
        std::vector<Eigen::Vector3d> object_points;
        for (std::size_t k = 0; k < scan.points.size(); ++k)
          if (objects[i][k]) object_points.push_back(scan.points[k]);
        result.scan_spacing_m = nearestNeighbourSpacing(object_points).median;
      }
      if (registration) {
        start = Clock::now();
        PointCloud points = objectPointsInSensorFrame(scan, objects[i]);
        registration->add(points, scan.sensor_pose, selected.board_prior);
        if (params.keep_registration_input) result.registration_input.push_back(std::move(points));
        times.registration_ms += millisecondsSince(start);
      }
      reportProgress(progress, "registration", i + 1, n);
    }
    if (registration) {
      const auto start = Clock::now();
      result.registration = registration->finish();
      registration.reset();
      result.poses = result.registration.poses;
      times.registration_ms += millisecondsSince(start);
    } else {
      result.poses = result.reported_poses;
    }
  }

  // Fusion of the whole scans at their registered poses.
  {
    OctreeFusionParameters fusion_params = params.fusion;
    fusion_params.bounds = result.crop_box;
    OctreeFusion fusion(fusion_params);
    // A few scans at a time, restored and traced in parallel (the octree
    // is updated in scan order all the same): all of them at once would
    // hold every scan in double precision.
    const std::size_t chunk = 2 * static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
    for (std::size_t first = 0; first < n; first += chunk) {
      const auto start = Clock::now();
      const std::size_t last = std::min(n, first + chunk);
      std::vector<RangeScan> placed(last - first);
      // The object masks are read by nothing after the fusion.
      std::vector<std::vector<std::uint8_t>> masks(std::make_move_iterator(objects.begin() + static_cast<std::ptrdiff_t>(first)),
                                                   std::make_move_iterator(objects.begin() + static_cast<std::ptrdiff_t>(last)));
      tbb::parallel_for(first, last, [&](std::size_t i) {
        RangeScan scan = scans[i].restore();
        const Eigen::Isometry3d correction = result.poses[i] * scan.sensor_pose.inverse();
        for (Eigen::Vector3d& p : scan.points) p = correction * p;
        scan.sensor_pose = result.poses[i];
        placed[i - first] = std::move(scan);
      });
      fusion.insert(placed, masks);
      times.fusion_ms += millisecondsSince(start);
      reportProgress(progress, "fusion", last, n);
    }
    const auto start = Clock::now();
    OctreeFusionResult fused = fusion.finish();
    // In Z-order: every later stage walks the cloud point by point and asks
    // for each point's neighbours, which are then near it in memory too (the
    // fusion's own order revisits each place once per view): a quarter off
    // each radius query on 36 views (docs/performance.md, stop 45).
    const std::vector<std::uint32_t> order = mortonOrder(fused.points.positions);
    fused.points.select(std::vector<std::size_t>(order.begin(), order.end()));
    times.fusion_ms += millisecondsSince(start);
    result.cloud = std::move(fused.points);
    result.fusion = fused.report;
  }
  if (result.cloud.positions.size() < 3)
    throw InputError(source, "", "only " + std::to_string(result.cloud.positions.size()) +
                                     " points survived the fusion: nothing to reconstruct");

  // Each point's sensor, for the raw normals and the smoothed ones (the
  // smoothing keeps the point order).
  const std::vector<Eigen::Vector3d> viewpoints = fusionViewpoints(result.cloud);
  {
    const auto start = Clock::now();
    reportProgress(progress, "normals", 0, 1);
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
    times.normals_ms = millisecondsSince(start);
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
    meshing.make_raw = params.make_raw_mesh;
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
  times.total_ms = add_read_ms + add_filter_ms + add_board_ms + millisecondsSince(total_start);
  return result;
}

}  // namespace icrkit::reconstruction
