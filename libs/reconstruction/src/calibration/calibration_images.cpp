#include <icrkit/reconstruction/calibration/calibration_images.hpp>

#include <icrkit/core/error.hpp>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace icrkit::reconstruction {

std::vector<GrayImage> readGrayImages(const std::string& folder, std::vector<std::string>* names) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(folder, error)) throw InputError(folder, "", "not a folder of images");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    if (!entry.is_regular_file()) continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pgm" || ext == ".ppm" || ext == ".bmp" ||
        ext == ".tif" || ext == ".tiff")
      files.push_back(entry.path());
  }
  if (error) throw InputError(folder, "", "cannot list the folder: " + error.message());
  if (files.empty()) throw InputError(folder, "", "holds no image (.png, .jpg, .pgm, .ppm, .bmp, .tif)");
  std::sort(files.begin(), files.end());
  std::vector<GrayImage> images;
  for (const fs::path& file : files) {
    const cv::Mat m = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (m.empty() || m.type() != CV_8UC1) throw InputError(file.string(), "", "cannot be decoded as an image");
    GrayImage image;
    image.width = m.cols;
    image.height = m.rows;
    image.pixels.resize(static_cast<std::size_t>(m.cols) * static_cast<std::size_t>(m.rows));
    for (int r = 0; r < m.rows; ++r)
      std::copy(m.ptr<std::uint8_t>(r), m.ptr<std::uint8_t>(r) + m.cols,
                image.pixels.begin() + static_cast<std::ptrdiff_t>(r) * m.cols);
    images.push_back(std::move(image));
    if (names) names->push_back(file.filename().string());
  }
  return images;
}

GrayImage grayOf(const Image8& image) {
  GrayImage gray;
  gray.width = image.width;
  gray.height = image.height;
  const std::size_t n = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  gray.pixels.resize(n);
  if (image.channels == 1) {
    std::copy(image.data.begin(), image.data.begin() + static_cast<std::ptrdiff_t>(n), gray.pixels.begin());
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const double y = 0.299 * image.data[3 * i] + 0.587 * image.data[3 * i + 1] + 0.114 * image.data[3 * i + 2];
      gray.pixels[i] = static_cast<std::uint8_t>(std::lround(std::min(255.0, y)));
    }
  }
  return gray;
}

}  // namespace icrkit::reconstruction
