/// \file
/// Streamed rawlog reading: the archive is read object by object so that
/// only the sensory frame at hand is in memory.

#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include "observation_scan.hpp"
#include "rawlog_size_guard.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/core/pose_mrpt.hpp>

#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <deque>
#include <filesystem>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

std::string scanLocation(std::size_t index) { return "scan " + std::to_string(index); }

CameraIntrinsics cameraOf(const mrpt::img::TCamera& c) {
  CameraIntrinsics m;
  m.width = static_cast<int>(c.ncols);
  m.height = static_cast<int>(c.nrows);
  m.fx = c.fx();
  m.fy = c.fy();
  m.cx = c.cx();
  m.cy = c.cy();
  for (std::size_t i = 0; i < 5; ++i) m.distortion[i] = c.dist[i];
  return m;
}

Image8 imageOf(const mrpt::img::CImage& image) {
  Image8 out;
  out.width = static_cast<int>(image.getWidth());
  out.height = static_cast<int>(image.getHeight());
  out.channels = image.isColor() ? 3 : 1;
  out.data.resize(static_cast<std::size_t>(out.width) * out.height * out.channels);
  for (int r = 0; r < out.height; ++r) {
    const auto* row = image.ptrLine<std::uint8_t>(static_cast<unsigned>(r));
    std::uint8_t* dst = out.data.data() + static_cast<std::size_t>(r) * out.width * out.channels;
    if (out.channels == 1) {
      std::copy(row, row + out.width, dst);
    } else {
      // CImage keeps colour in OpenCV's BGR order.
      for (int c = 0; c < out.width; ++c) {
        dst[3 * c + 0] = row[3 * c + 2];
        dst[3 * c + 1] = row[3 * c + 1];
        dst[3 * c + 2] = row[3 * c + 0];
      }
    }
  }
  return out;
}

}  // namespace

std::size_t RangeScan::validPixels() const {
  std::size_t n = 0;
  for (float r : range) n += r > 0.0f;
  return n;
}

std::size_t RangeScan::dropInvalidPoints() {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (range[pixels[i]] <= 0.0f) continue;
    points[kept] = points[i];
    pixels[kept] = pixels[i];
    ++kept;
  }
  const std::size_t dropped = points.size() - kept;
  points.resize(kept);
  pixels.resize(kept);
  return dropped;
}

Eigen::Matrix3d mrptSensorAxesInOptical() {
  Eigen::Matrix3d r;
  r << 0, -1, 0,  //
      0, 0, -1,   //
      1, 0, 0;
  return r;
}

Eigen::Vector3d opticalPoint(const RangeScan& scan, int row, int col, double range) {
  const Eigen::Vector3d ray((col - scan.camera.cx) / scan.camera.fx, (row - scan.camera.cy) / scan.camera.fy, 1.0);
  return scan.range_is_depth ? Eigen::Vector3d(ray * range) : Eigen::Vector3d(ray.normalized() * range);
}

namespace detail {

mrpt::img::TCamera toMrptCamera(const CameraIntrinsics& k) {
  mrpt::img::TCamera camera;
  camera.ncols = static_cast<std::uint32_t>(k.width);
  camera.nrows = static_cast<std::uint32_t>(k.height);
  camera.setIntrinsicParamsFromValues(k.fx, k.fy, k.cx, k.cy);
  camera.setDistortionPlumbBob(k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3], k.distortion[4]);
  return camera;
}

RangeScan scanFromObservation(CObservation3DRangeScan& obs, std::size_t index, const std::string& path,
                              const ObservationConversion& conversion) {
  const std::string where = scanLocation(index);
  if (!obs.hasRangeImage || obs.rangeImage.cols() == 0 || obs.rangeImage.rows() == 0)
    throw InputError(path, where, "the 3D scan has no range image");

  RangeScan scan;
  scan.index = index;
  scan.timestamp = mrpt::Clock::toDouble(obs.timestamp);
  scan.sensor_label = obs.sensorLabel;
  scan.range_is_depth = obs.range_is_depth;
  scan.max_range = obs.maxRange;
  scan.width = static_cast<int>(obs.rangeImage.cols());
  scan.height = static_cast<int>(obs.rangeImage.rows());
  scan.camera = cameraOf(obs.cameraParams);
  scan.camera_intensity = cameraOf(obs.cameraParamsIntensity);
  if (scan.camera.width != scan.width || scan.camera.height != scan.height)
    throw InputError(path, where,
                     "range image is " + std::to_string(scan.width) + "x" + std::to_string(scan.height) +
                         " but cameraParams say " + std::to_string(scan.camera.width) + "x" +
                         std::to_string(scan.camera.height));
  if (!(scan.camera.fx > 0 && scan.camera.fy > 0))
    throw InputError(path, where, "cameraParams have a non-positive focal length");
  if (!(obs.rangeUnits > 0)) throw InputError(path, where, "rangeUnits is not positive");

  scan.range.resize(static_cast<std::size_t>(scan.width) * scan.height);
  for (int r = 0; r < scan.height; ++r)
    for (int c = 0; c < scan.width; ++c)
      scan.range[static_cast<std::size_t>(r) * scan.width + c] = obs.rangeImage(r, c) * obs.rangeUnits;

  if (obs.hasIntensityImage && !obs.intensityImage.isEmpty()) {
    scan.intensity = imageOf(obs.intensityImage);
    scan.intensity_is_ir = obs.intensityImageChannel == CObservation3DRangeScan::CH_IR;
    if (scan.intensity.width != scan.camera_intensity.width || scan.intensity.height != scan.camera_intensity.height)
      throw InputError(path, where,
                       "intensity image is " + std::to_string(scan.intensity.width) + "x" +
                           std::to_string(scan.intensity.height) + " but cameraParamsIntensity say " +
                           std::to_string(scan.camera_intensity.width) + "x" +
                           std::to_string(scan.camera_intensity.height));
  }
  if (obs.hasConfidenceImage && !obs.confidenceImage.isEmpty()) {
    scan.confidence = imageOf(obs.confidenceImage);
    if (scan.confidence.width != scan.width || scan.confidence.height != scan.height)
      throw InputError(path, where,
                       "confidence image is " + std::to_string(scan.confidence.width) + "x" +
                           std::to_string(scan.confidence.height) + ", the range image " + std::to_string(scan.width) +
                           "x" + std::to_string(scan.height));
  }

  if (conversion.pose) {
    scan.sensor_pose = *conversion.pose;
    scan.pose_orthonormalised = conversion.pose_normalised;
    obs.sensorPose = toCPose3D(scan.sensor_pose);
  } else {
    scan.sensor_pose = toIsometry(obs.sensorPose);
    // MRPT unprojects with the observation's own pose: it must be the
    // repaired one, or the points would carry the scale or shear.
    scan.pose_orthonormalised = orthonormaliseReadPose(scan.sensor_pose, path, where, conversion.rotation_tolerance);
    if (scan.pose_orthonormalised) obs.sensorPose = toCPose3D(scan.sensor_pose);
  }

  if (conversion.unproject) {
    mrpt::maps::CSimplePointsMap cloud;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    obs.unprojectInto(cloud, pp);
    // MRPT records each point's pixel next to the points it unprojects.
    if (obs.points3D_idxs_x.size() < cloud.size() || obs.points3D_idxs_y.size() < cloud.size())
      throw InputError(path, where, "internal: MRPT did not report the pixels of its points");
    scan.points.reserve(cloud.size());
    scan.pixels.reserve(cloud.size());
    for (std::size_t k = 0; k < cloud.size(); ++k) {
      const std::uint32_t pixel =
          static_cast<std::uint32_t>(obs.points3D_idxs_y[k]) * scan.width + obs.points3D_idxs_x[k];
      if (pixel >= scan.range.size() || !(scan.range[pixel] > 0.0f)) continue;
      float x, y, z;
      cloud.getPoint(k, x, y, z);
      scan.points.emplace_back(x, y, z);
      scan.pixels.push_back(pixel);
    }
  }
  return scan;
}

}  // namespace detail

struct RawlogReader::Impl {
  std::string path;
  RawlogReaderOptions options;
  mrpt::io::CFileGZInputStream stream;
  // Between the file and MRPT: refuses absurd image and matrix sizes before
  // MRPT allocates them. 2^26 elements: an 8192 x 8192 range image.
  RawlogSizeGuard guard{stream, std::uint64_t{1} << 26};
  std::vector<StampedPose> poses;
  std::vector<std::uint8_t> pose_normalised;         // per pose: its quaternion was off unit length
  std::deque<CObservation3DRangeScan::Ptr> pending;  // the rest of the current sensory frame
  std::size_t scans = 0;
  bool finished = false;

  // Reads objects until a 3D scan is pending or the file ends.
  void fill() {
    auto archive = mrpt::serialization::archiveFrom(guard);
    while (pending.empty() && !finished) {
      const std::uint64_t before = stream.getPosition();
      mrpt::serialization::CSerializable::Ptr object;
      try {
        object = archive.ReadObject();
      } catch (const std::exception& e) {
        if (!guard.refusal().empty()) throw InputError(path, scanLocation(scans), guard.refusal());
        // Nothing consumed: a clean end between objects. Anything else is
        // an object cut short (a truncated copy, an interrupted recording).
        if (stream.getPosition() == before && stream.checkEOF()) {
          finished = true;
          break;
        }
        throw InputError(path, scanLocation(scans),
                         "the file ends inside an object (truncated or corrupt) after " + std::to_string(scans) +
                             " complete 3D scans at byte " + std::to_string(before) + " (uncompressed)");
      }
      if (!object) continue;
      if (auto obs = std::dynamic_pointer_cast<CObservation3DRangeScan>(object)) {
        pending.push_back(obs);
      } else if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
        for (const auto& o : *frame)
          if (auto scan = std::dynamic_pointer_cast<CObservation3DRangeScan>(o)) pending.push_back(scan);
      }
      // Actions and other observations carry nothing the reconstruction uses.
    }
  }

  RangeScan convert(CObservation3DRangeScan& obs, std::size_t index) {
    const std::string where = scanLocation(index);
    // External images and range files are loaded lazily relative to the images folder.
    try {
      obs.load();
      if (obs.hasIntensityImage) obs.intensityImage.forceLoad();
      if (obs.hasConfidenceImage) obs.confidenceImage.forceLoad();
    } catch (const std::exception& e) {
      throw InputError(path, where,
                       "an externally stored image could not be loaded (images folder " +
                           mrpt::img::CImage::getImagesPathBase() + "): " + e.what());
    }
    detail::ObservationConversion conversion;
    conversion.rotation_tolerance = options.rotation_tolerance;
    conversion.unproject = options.unproject;
    if (!options.pose_file.empty()) {
      if (index >= poses.size())
        throw InputError(options.pose_file, where,
                         "only " + std::to_string(poses.size()) + " poses for the scans of " + path);
      conversion.pose = &poses[index].pose;
      conversion.pose_normalised = pose_normalised[index] != 0;
    }
    RangeScan scan = detail::scanFromObservation(obs, index, path, conversion);
    obs.unload();
    return scan;
  }
};

RawlogReader::RawlogReader(const std::string& path, RawlogReaderOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->options = std::move(options);
  std::error_code error;
  if (!fs::is_regular_file(path, error)) throw InputError(path, "", "no such rawlog file");
  if (!impl_->options.pose_file.empty())
    impl_->poses = readTumTrajectory(impl_->options.pose_file, &impl_->pose_normalised);
  std::string images = impl_->options.images_folder;
  if (images.empty()) {
    const fs::path p(path);
    images = (p.parent_path() / (p.stem().string() + "_Images")).string();
  }
  // MRPT resolves external images against a process-wide folder; it must
  // be set before the first observation is read.
  mrpt::img::CImage::setImagesPathBase(images);
  if (!impl_->stream.open(path)) throw InputError(path, "", "cannot open the rawlog");
  impl_->fill();
  if (impl_->pending.empty())
    throw InputError(path, "", "no 3D range scans (CObservation3DRangeScan) in the rawlog");
}

RawlogReader::~RawlogReader() = default;

std::optional<RangeScan> RawlogReader::next() {
  impl_->fill();
  if (impl_->pending.empty()) return std::nullopt;
  auto obs = impl_->pending.front();
  impl_->pending.pop_front();
  RangeScan scan = impl_->convert(*obs, impl_->scans);
  ++impl_->scans;
  return scan;
}

std::size_t RawlogReader::scansRead() const { return impl_->scans; }
const std::string& RawlogReader::path() const { return impl_->path; }

std::vector<RangeScan> readAllScans(const std::string& path, const RawlogReaderOptions& options) {
  RawlogReader reader(path, options);
  std::vector<RangeScan> scans;
  while (auto scan = reader.next()) scans.push_back(std::move(*scan));
  return scans;
}

}  // namespace icrkit::reconstruction
