/// \file
/// TUM RGB-D folders: the list, the camera, the poses, and each 16-bit PNG
/// turned into an MRPT observation so that the rawlog reader's conversion
/// (and MRPT's unprojection) handles it exactly as a recorded scan.

#include <icrkit/reconstruction/input/tum_folder_reader.hpp>

#include <icrkit/reconstruction/input/depth_image_scan.hpp>

#include <icrkit/core/error.hpp>
#include <icrkit/core/pose.hpp>


#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace icrkit::reconstruction {
namespace {

namespace fs = std::filesystem;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

std::string scanLocation(std::size_t index) {
  return "scan " + std::to_string(index);
}

bool parseDouble(std::string_view text, double& value) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// A number under `key` of `object`; `present` says whether it was there.
double jsonNumber(const nlohmann::json& object, const char* key, const std::string& file, bool& present) {
  present = false;
  const auto it = object.find(key);
  if (it == object.end()) return 0.0;
  if (!it->is_number() || !std::isfinite(it->get<double>()))
    throw InputError(file, std::string("key ") + key, "expected a finite number, found " + it->dump());
  present = true;
  return it->get<double>();
}

void checkLens(const CameraIntrinsics& k, const std::string& source, const std::string& location) {
  if (!(k.fx > 0 && k.fy > 0 && std::isfinite(k.fx) && std::isfinite(k.fy)))
    throw InputError(source, location, "expected positive focal lengths fx, fy (pixels)");
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw InputError(source, location, "expected a finite principal point cx, cy (pixels)");
  for (double d : k.distortion)
    if (!std::isfinite(d)) throw InputError(source, location, "expected finite distortion coefficients");
}

// A 16-bit, one-channel depth image, or InputError naming the file.
cv::Mat readDepthImage(const DepthFrame& frame, std::size_t index) {
  // ANYDEPTH keeps 16 bits, ANYCOLOR keeps the channels, so that an 8-bit
  // or colour image is recognised instead of being converted silently.
  cv::Mat image = cv::imread(frame.path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (image.empty()) throw InputError(frame.path, scanLocation(index), "cannot be decoded as an image");
  if (image.depth() != CV_16U) {
    const int d = image.depth();
    const char* depth = d == CV_8U || d == CV_8S     ? "8-bit"
                        : d == CV_16S                ? "signed 16-bit"
                        : d == CV_32F || d == CV_64F ? "floating-point"
                                                     : "32-bit integer";
    throw InputError(
        frame.path, scanLocation(index),
        std::string("expected a 16-bit depth image (one channel of depth counts), found ") + depth + " pixels");
  }
  if (image.channels() != 1)
    throw InputError(
        frame.path, scanLocation(index),
        "expected a 16-bit depth image with one channel, found " + std::to_string(image.channels()) + " channels");
  return image;
}

}  // namespace

const char* poseMatchingName(PoseMatching matching) {
  switch (matching) {
    case PoseMatching::None:
      return "none";
    case PoseMatching::ByOrder:
      return "order";
    case PoseMatching::ByTimestamp:
      return "timestamp";
  }
  return "none";
}

std::vector<DepthFrame> readDepthList(const std::string& list_file) {
  std::ifstream in(list_file, std::ios::binary);
  if (!in) throw InputError(list_file, "", "cannot be read");
  const fs::path folder = fs::path(list_file).parent_path();
  std::vector<DepthFrame> frames;
  std::string text;
  std::size_t line_number = 0;
  while (std::getline(in, text)) {
    ++line_number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    const std::vector<std::string_view> f = fields(text);
    if (f.empty() || f[0].front() == '#') continue;
    const std::string where = "line " + std::to_string(line_number);
    if (f.size() != 2)
      throw InputError(list_file, where,
                       "expected 'timestamp filename', found " + std::to_string(f.size()) + " fields");
    DepthFrame frame;
    if (!parseDouble(f[0], frame.timestamp))
      throw InputError(list_file, where, "expected a time stamp in seconds, found '" + std::string(f[0]) + "'");
    frame.file = std::string(f[1]);
    const fs::path file(frame.file);
    frame.path = (file.is_absolute() ? file : folder / file).string();
    frame.line = line_number;
    frames.push_back(std::move(frame));
  }
  if (frames.empty()) throw InputError(list_file, "", "lists no depth image ('timestamp filename' lines)");
  return frames;
}

DepthCamera readDepthCameraFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot read the camera file");
  nlohmann::json root;
  try {
    in >> root;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "", std::string("expected a JSON object: ") + e.what());
  }
  if (!root.is_object()) throw InputError(path, "", "expected a JSON object with fx, fy, cx, cy");
  // `icrkit calibrate -o` nests the lens under "camera".
  const auto nested = root.find("camera");
  if (nested != root.end() && !nested->is_object()) throw InputError(path, "key camera", "expected an object");
  const nlohmann::json& lens = nested != root.end() ? *nested : root;

  DepthCamera camera;
  camera.camera_file = path;
  bool present = false;
  CameraIntrinsics& k = camera.intrinsics;
  k.fx = jsonNumber(lens, "fx", path, present);
  const bool has_fx = present;
  k.fy = jsonNumber(lens, "fy", path, present);
  const bool has_fy = present;
  k.cx = jsonNumber(lens, "cx", path, present);
  const bool has_cx = present;
  k.cy = jsonNumber(lens, "cy", path, present);
  const bool has_cy = present;
  if (has_fx || has_fy || has_cx || has_cy) {
    if (!(has_fx && has_fy && has_cx && has_cy))
      throw InputError(path, "", "expected all of fx, fy, cx, cy (pixels) or none");
    checkLens(k, path, "key fx");
  }
  const auto distortion = lens.find("distortion_k1_k2_p1_p2_k3");
  if (distortion != lens.end()) {
    if (!distortion->is_array() || distortion->size() != 5)
      throw InputError(path, "key distortion_k1_k2_p1_p2_k3", "expected 5 numbers k1, k2, p1, p2, k3");
    for (std::size_t i = 0; i < 5; ++i) {
      const auto& v = (*distortion)[i];
      if (!v.is_number() || !std::isfinite(v.get<double>()))
        throw InputError(path, "key distortion_k1_k2_p1_p2_k3", "expected 5 finite numbers k1, k2, p1, p2, k3");
      k.distortion[i] = v.get<double>();
    }
  }
  for (const char* key : {"width", "height"}) {
    const double v = jsonNumber(lens, key, path, present);
    if (present && !(v >= 1 && v == std::floor(v) && v < 1e6))
      throw InputError(path, std::string("key ") + key, "expected a positive whole number of pixels");
    (key[0] == 'w' ? k.width : k.height) = present ? static_cast<int>(v) : 0;
  }
  camera.depth_scale = jsonNumber(root, "depth_scale", path, present);
  if (present && !(camera.depth_scale > 0))
    throw InputError(path, "key depth_scale", "expected the depth counts per metre (> 0; 1000 for millimetres)");
  if (present) camera.depth_scale_source = "camera file";
  camera.max_range = jsonNumber(root, "max_range_m", path, present);
  if (present && !(camera.max_range >= 0)) throw InputError(path, "key max_range_m", "expected metres >= 0");
  return camera;
}

MatchedPoses matchOpticalPoses(const std::string& pose_file, const std::vector<double>& frame_timestamps,
                               double max_time_difference) {
  if (!(max_time_difference >= 0) || !std::isfinite(max_time_difference))
    throw InputError("max time difference", "", "expected seconds >= 0");
  std::error_code error;
  if (!fs::is_regular_file(pose_file, error)) throw InputError(pose_file, "", "no such pose file");
  std::vector<std::uint8_t> normalised;
  const std::vector<StampedPose> poses = readTumTrajectory(pose_file, &normalised);
  if (poses.empty()) throw InputError(pose_file, "", "holds no pose ('timestamp tx ty tz qx qy qz qw' lines)");
  const std::size_t n = frame_timestamps.size();
  MatchedPoses out;
  std::vector<std::size_t> chosen(n);
  if (poses.size() == n) {
    out.matching = PoseMatching::ByOrder;
    for (std::size_t i = 0; i < n; ++i) chosen[i] = i;
  } else {
    out.matching = PoseMatching::ByTimestamp;
    for (std::size_t k = 1; k < poses.size(); ++k)
      if (poses[k].timestamp < poses[k - 1].timestamp)
        throw InputError(pose_file, "pose " + std::to_string(k),
                         "time stamps go backwards (" + number(poses[k].timestamp) + " after " +
                             number(poses[k - 1].timestamp) + "); with " + std::to_string(poses.size()) +
                             " poses for " + std::to_string(n) +
                             " depth frames the poses are matched by time stamp and must be in time order");
    for (std::size_t i = 0; i < n; ++i) {
      const double t = frame_timestamps[i];
      const auto after = std::lower_bound(poses.begin(), poses.end(), t,
                                          [](const StampedPose& p, double time) { return p.timestamp < time; });
      std::size_t best = after == poses.end() ? poses.size() - 1 : static_cast<std::size_t>(after - poses.begin());
      // The earlier of two equally near poses, so that the choice does not
      // depend on the search.
      if (best > 0 && std::abs(poses[best - 1].timestamp - t) <= std::abs(poses[best].timestamp - t)) --best;
      if (!(std::abs(poses[best].timestamp - t) <= max_time_difference))
        throw InputError(pose_file, scanLocation(i),
                         "has " + std::to_string(poses.size()) + " poses for " + std::to_string(n) +
                             " depth frames, so they are matched by time stamp, and none lies within " +
                             number(max_time_difference) + " s of the frame at " + number(t) +
                             " (nearest: " + number(poses[best].timestamp) + ")");
      chosen[i] = best;
    }
  }
  const Eigen::Matrix3d axes = mrptSensorAxesInOptical();
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Isometry3d sensor = poses[chosen[i]].pose;
    sensor.linear() = sensor.linear() * axes;
    out.sensor_poses.push_back(sensor);
    out.normalised.push_back(normalised[chosen[i]]);
  }
  return out;
}

struct TumFolderReader::Impl {
  std::string folder;
  TumFolderOptions options;
  std::vector<DepthFrame> frames;
  DepthCamera camera;
  MatchedPoses poses;
  cv::Mat first_image;  // decoded for the image size; used by the first next()
  std::size_t scans = 0;

  void resolveCamera() {
    std::string file = options.camera.camera_file;
    std::error_code error;
    if (file.empty()) {
      const fs::path automatic = fs::path(folder) / "camera.json";
      if (fs::is_regular_file(automatic, error)) file = automatic.string();
    } else if (!fs::is_regular_file(file, error)) {
      throw InputError(file, "", "no such camera file");
    }
    if (!file.empty()) camera = readDepthCameraFile(file);
    if (options.camera.intrinsics) {
      const int width = camera.intrinsics.width, height = camera.intrinsics.height;
      camera.intrinsics = *options.camera.intrinsics;
      camera.intrinsics.width = width;
      camera.intrinsics.height = height;
      camera.intrinsics_from_options = true;
      checkLens(camera.intrinsics, "intrinsics", "");
    }
    if (!(camera.intrinsics.fx > 0))
      throw InputError(
          folder, "",
          "no camera intrinsics: give fx, fy, cx, cy (DepthCameraOptions::intrinsics) or a camera.json in the folder");
    if (options.camera.depth_scale) {
      if (!(std::isfinite(*options.camera.depth_scale) && *options.camera.depth_scale > 0))
        throw InputError("DepthCameraOptions::depth_scale", "", "expected the depth counts per metre (> 0)");
      camera.depth_scale = *options.camera.depth_scale;
      camera.depth_scale_source = "options";
    } else if (!(camera.depth_scale > 0)) {
      camera.depth_scale = kTumDepthScale;
      camera.depth_scale_source = "default";
    }

    first_image = readDepthImage(frames.front(), 0);
    const int width = first_image.cols, height = first_image.rows;
    if ((camera.intrinsics.width != 0 && camera.intrinsics.width != width) ||
        (camera.intrinsics.height != 0 && camera.intrinsics.height != height))
      throw InputError(camera.camera_file, "key width",
                       "the camera is " + std::to_string(camera.intrinsics.width) + "x" +
                           std::to_string(camera.intrinsics.height) + " but " + frames.front().file + " is " +
                           std::to_string(width) + "x" + std::to_string(height));
    camera.intrinsics.width = width;
    camera.intrinsics.height = height;
  }

  RangeScan convert(std::size_t index) {
    const DepthFrame& frame = frames[index];
    cv::Mat image = index == 0 && !first_image.empty() ? first_image : readDepthImage(frame, index);
    if (index == 0) first_image.release();
    if (image.cols != camera.intrinsics.width || image.rows != camera.intrinsics.height)
      throw InputError(frame.path, scanLocation(index),
                       "expected a " + std::to_string(camera.intrinsics.width) + "x" +
                           std::to_string(camera.intrinsics.height) + " depth image like the first frame, found " +
                           std::to_string(image.cols) + "x" + std::to_string(image.rows));

    DepthImageView view;
    view.width = image.cols;
    view.height = image.rows;
    view.counts = image.ptr<std::uint16_t>(0);
    view.depth_scale = camera.depth_scale;
    view.row_stride = image.step1();
    DepthImageMeta meta;
    meta.intrinsics = camera.intrinsics;
    meta.sensor_pose = poses.sensor_poses[index];
    meta.pose_normalised = poses.normalised[index] != 0;
    meta.timestamp = frame.timestamp;
    meta.max_range = camera.max_range;
    meta.sensor_label = "TUM_DEPTH";
    meta.unproject = options.unproject;
    RangeScan scan = scanFromDepthImage(view, meta, index, frame.path);
    return scan;
  }
};

TumFolderReader::TumFolderReader(const std::string& folder, TumFolderOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->folder = folder;
  impl_->options = std::move(options);
  std::error_code error;
  if (!fs::is_directory(folder, error)) throw InputError(folder, "", "not a folder");
  const std::string list = (fs::path(folder) / "depth.txt").string();
  if (!fs::is_regular_file(list, error))
    throw InputError(list, "",
                     "no such file: a TUM RGB-D folder lists its depth images in depth.txt ('timestamp filename' "
                     "lines)");
  impl_->frames = readDepthList(list);
  for (const DepthFrame& frame : impl_->frames)
    if (!fs::is_regular_file(frame.path, error))
      throw InputError(list, "line " + std::to_string(frame.line),
                       "lists the depth image '" + frame.file + "', which does not exist");
  impl_->resolveCamera();

  std::vector<double> times;
  for (const DepthFrame& frame : impl_->frames) times.push_back(frame.timestamp);
  if (!impl_->options.pose_file.empty()) {
    impl_->poses = matchOpticalPoses(impl_->options.pose_file, times, impl_->options.max_time_difference);
  } else {
    // No poses: each optical frame is the object frame.
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.linear() = mrptSensorAxesInOptical();
    impl_->poses.sensor_poses.assign(times.size(), sensor);
    impl_->poses.normalised.assign(times.size(), 0);
    impl_->poses.matching = PoseMatching::None;
  }
}

TumFolderReader::~TumFolderReader() = default;

std::optional<RangeScan> TumFolderReader::next() {
  if (impl_->scans >= impl_->frames.size()) return std::nullopt;
  RangeScan scan = impl_->convert(impl_->scans);
  ++impl_->scans;
  return scan;
}

std::size_t TumFolderReader::scansRead() const {
  return impl_->scans;
}
const std::string& TumFolderReader::path() const {
  return impl_->folder;
}
const std::vector<DepthFrame>& TumFolderReader::frames() const {
  return impl_->frames;
}
const DepthCamera& TumFolderReader::camera() const {
  return impl_->camera;
}
PoseMatching TumFolderReader::poseMatching() const {
  return impl_->poses.matching;
}

std::string depthCameraRecordJson(const DepthCamera& camera) {
  const CameraIntrinsics& k = camera.intrinsics;
  const nlohmann::json record{
      {"width", k.width},
      {"height", k.height},
      {"fx", k.fx},
      {"fy", k.fy},
      {"cx", k.cx},
      {"cy", k.cy},
      {"distortion_k1_k2_p1_p2_k3", k.distortion},
      {"intrinsics_source", camera.intrinsics_from_options ? std::string("options") : camera.camera_file},
      {"depth_scale", camera.depth_scale},
      {"depth_scale_source", camera.depth_scale_source == "camera file" ? camera.camera_file
                             : camera.depth_scale_source == "default"   ? std::string("default (TUM)")
                                                                        : camera.depth_scale_source},
      {"max_range_m", camera.max_range}};
  return record.dump();
}

}  // namespace icrkit::reconstruction
