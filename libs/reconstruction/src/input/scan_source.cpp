#include <icrkit/reconstruction/input/scan_source.hpp>

#include <icrkit/core/error.hpp>

#include <filesystem>
#include <system_error>

namespace icrkit::reconstruction {

bool isDepthImageFolder(const std::string& path) {
  std::error_code error;
  return std::filesystem::is_directory(path, error);
}

bool isBag(const std::string& path) {
  return isMcapFile(path);
}

ScanReader::ScanReader(const std::string& path, const ScanReaderOptions& options)
    : pose_file_(!options.pose_file.empty()) {
  if (reconstruction::isBag(path)) {
    // A bag's poses are its own messages; a TUM file would need a frame
    // convention and a matching rule of its own.
    if (!options.pose_file.empty())
      throw InputError("ScanReaderOptions::pose_file", "",
                       "a ROS 2 bag takes its poses from a PoseStamped topic (McapReaderOptions::pose_topic) or tf "
                       "(McapReaderOptions::parent_frame), not from a TUM file");
    if (!options.depth_camera.camera_file.empty())
      throw InputError("DepthCameraOptions::camera_file", "",
                       "a ROS 2 bag takes its camera from its CameraInfo (or McapReaderOptions::intrinsics)");
    McapReaderOptions bag = options.mcap;
    if (!bag.intrinsics) bag.intrinsics = options.depth_camera.intrinsics;
    if (!bag.depth_scale) bag.depth_scale = options.depth_camera.depth_scale;
    if (options.max_time_difference != kTumMaxTimeDifference) bag.max_time_difference = options.max_time_difference;
    bag.unproject = options.unproject;
    bag_ = std::make_unique<McapReader>(path, std::move(bag));
  } else if (isDepthImageFolder(path)) {
    TumFolderOptions folder;
    folder.pose_file = options.pose_file;
    folder.camera = options.depth_camera;
    folder.max_time_difference = options.max_time_difference;
    folder.unproject = options.unproject;
    folder_ = std::make_unique<TumFolderReader>(path, std::move(folder));
  } else {
    RawlogReaderOptions rawlog;
    rawlog.pose_file = options.pose_file;
    rawlog.images_folder = options.images_folder;
    rawlog.unproject = options.unproject;
    rawlog.rotation_tolerance = options.rotation_tolerance;
    rawlog_ = std::make_unique<RawlogReader>(path, std::move(rawlog));
  }
}

ScanReader::~ScanReader() = default;

std::optional<RangeScan> ScanReader::next() {
  if (bag_) return bag_->next();
  return folder_ ? folder_->next() : rawlog_->next();
}
std::size_t ScanReader::scansRead() const {
  if (bag_) return bag_->scansRead();
  return folder_ ? folder_->scansRead() : rawlog_->scansRead();
}
const std::string& ScanReader::path() const {
  if (bag_) return bag_->path();
  return folder_ ? folder_->path() : rawlog_->path();
}
bool ScanReader::isFolder() const {
  return folder_ != nullptr;
}
bool ScanReader::isBag() const {
  return bag_ != nullptr;
}
const McapReader* ScanReader::bag() const {
  return bag_.get();
}

std::optional<DepthCamera> ScanReader::depthCamera() const {
  if (bag_) return bag_->camera();
  if (!folder_) return std::nullopt;
  return folder_->camera();
}

std::string ScanReader::poseMatching() const {
  if (bag_) return bag_->poseMatching();
  if (folder_) return poseMatchingName(folder_->poseMatching());
  return pose_file_ ? "order" : "recorded";
}

std::vector<RangeScan> readScans(const std::string& path, const ScanReaderOptions& options) {
  ScanReader reader(path, options);
  std::vector<RangeScan> scans;
  while (auto scan = reader.next()) scans.push_back(std::move(*scan));
  return scans;
}

}  // namespace icrkit::reconstruction
