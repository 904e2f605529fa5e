#include <icrkit/reconstruction/input/scan_source.hpp>

#include <filesystem>
#include <system_error>

namespace icrkit::reconstruction {

bool isDepthImageFolder(const std::string& path) {
  std::error_code error;
  return std::filesystem::is_directory(path, error);
}

ScanReader::ScanReader(const std::string& path, const ScanReaderOptions& options)
    : pose_file_(!options.pose_file.empty()) {
  if (isDepthImageFolder(path)) {
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
  return folder_ ? folder_->next() : rawlog_->next();
}
std::size_t ScanReader::scansRead() const {
  return folder_ ? folder_->scansRead() : rawlog_->scansRead();
}
const std::string& ScanReader::path() const {
  return folder_ ? folder_->path() : rawlog_->path();
}
bool ScanReader::isFolder() const {
  return folder_ != nullptr;
}

std::optional<DepthCamera> ScanReader::depthCamera() const {
  if (!folder_) return std::nullopt;
  return folder_->camera();
}

std::string ScanReader::poseMatching() const {
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
