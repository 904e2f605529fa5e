#include <icrkit/reconstruction/input/rawlog_intrinsics.hpp>

#include "observation_scan.hpp"

#include <icrkit/core/error.hpp>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <system_error>

namespace icrkit::reconstruction {
namespace {

void apply(mrpt::obs::CObservation3DRangeScan& obs, const CameraIntrinsics& k, const std::string& input,
           std::size_t index) {
  if (obs.hasRangeImage && (obs.rangeImage.cols() != k.width || obs.rangeImage.rows() != k.height))
    throw InputError(input, "scan " + std::to_string(index),
                     "the range image is " + std::to_string(obs.rangeImage.cols()) + " x " +
                         std::to_string(obs.rangeImage.rows()) + ", the calibrated camera " + std::to_string(k.width) +
                         " x " + std::to_string(k.height));
  obs.cameraParams = detail::toMrptCamera(k);
  obs.cameraParamsIntensity = obs.cameraParams;
}

}  // namespace

std::size_t writeRawlogWithIntrinsics(const std::string& input, const std::string& output,
                                      const CameraIntrinsics& intrinsics) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(input)) throw InputError(input, "", "cannot be opened");
  const std::filesystem::path target(output);
  std::filesystem::path temporary = target;
  temporary += ".tmp";
  std::size_t scans = 0;
  try {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(temporary.string(), 1)) throw InputError(output, "", "cannot be written");
    auto reader = mrpt::serialization::archiveFrom(in);
    auto writer = mrpt::serialization::archiveFrom(out);
    for (;;) {
      const std::uint64_t before = in.getPosition();
      mrpt::serialization::CSerializable::Ptr object;
      try {
        object = reader.ReadObject();
      } catch (const std::exception&) {
        if (in.getPosition() == before && in.checkEOF()) break;  // a clean end between objects
        throw InputError(input, "scan " + std::to_string(scans), "the file ends inside an object (truncated or corrupt)");
      }
      if (!object) continue;
      if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(object)) {
        apply(*obs, intrinsics, input, scans++);
      } else if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
        for (auto& o : *frame)
          if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
            apply(*scan, intrinsics, input, scans++);
      }
      writer << *object;
    }
    out.close();
    if (scans == 0) throw InputError(input, "", "holds no 3D range scan (CObservation3DRangeScan)");
    std::error_code error;
    std::filesystem::rename(temporary, target, error);
    if (error) throw InputError(output, "", "cannot move the finished rawlog into place");
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  return scans;
}

}  // namespace icrkit::reconstruction
