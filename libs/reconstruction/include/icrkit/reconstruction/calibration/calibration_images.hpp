#pragma once
/// \file
/// Grey images for calibration: from a folder of image files (OpenCV's
/// codecs) or from a rawlog scan's colour or amplitude image.

#include <icrkit/reconstruction/calibration/camera_calibration.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <string>
#include <vector>

namespace icrkit::reconstruction {

/// Every .png, .jpg, .jpeg, .pgm, .ppm, .bmp, .tif and .tiff file of
/// `folder` (not recursive), sorted by file name, as grey images; their
/// names go to `names` when given. Throws InputError naming the folder when
/// it is missing or holds no image, and naming the file when one cannot be
/// decoded.
std::vector<GrayImage> readGrayImages(const std::string& folder, std::vector<std::string>* names = nullptr);

/// A colour (RGB) or grey 8-bit image as grey (ITU-R BT.601 luma for colour).
GrayImage grayOf(const Image8& image);

}  // namespace icrkit::reconstruction
