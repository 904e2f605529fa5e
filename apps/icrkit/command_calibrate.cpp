// `icrkit calibrate`: camera intrinsics and lens distortion from
// checkerboard images (reconstruction::calibrateCamera), taken from a folder
// of image files or from a rawlog's colour/amplitude images, optionally
// written back into a copy of the rawlog.

#include "argument_parsing.hpp"
#include "commands.hpp"

#include <icrkit/core/atomic_file.hpp>
#include <icrkit/core/error.hpp>
#include <icrkit/reconstruction/calibration/camera_calibration.hpp>
#include <icrkit/reconstruction/calibration/calibration_images.hpp>
#include <icrkit/reconstruction/input/rawlog_intrinsics.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>

#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct CalibrateOptions {
  std::string images;
  std::string rawlog;
  std::string board = "9x6";
  double square = 0.025;
  bool estimate_k3 = false;
  std::string output;
  std::string write_rawlog;
};

reconstruction::Checkerboard parseBoard(const std::string& text, double square) {
  const std::vector<std::string> parts = split(text, 'x');
  double columns = 0, rows = 0;
  if (parts.size() != 2 || !parseNumber(parts[0], columns) || !parseNumber(parts[1], rows) || columns < 2 || rows < 2 ||
      columns != static_cast<int>(columns) || rows != static_cast<int>(rows))
    throw InputError("--board", "", "expected inner corners as COLUMNSxROWS (e.g. 9x6), got '" + text + "'");
  if (!(square > 0)) throw InputError("--square", "", "the square size must be > 0 m");
  return {static_cast<int>(columns), static_cast<int>(rows), square};
}

nlohmann::json calibrate(const CalibrateOptions& o, CommandContext& context) {
  if (o.images.empty() == o.rawlog.empty())
    throw InputError("--images/--rawlog", "", "give exactly one source of checkerboard images");
  if (!o.write_rawlog.empty() && o.rawlog.empty())
    throw InputError("--write-rawlog", "", "needs --rawlog (the recording to copy with the new camera)");
  reconstruction::CalibrationParameters params;
  params.board = parseBoard(o.board, o.square);
  params.estimate_k3 = o.estimate_k3;

  std::vector<reconstruction::GrayImage> images;
  std::vector<std::string> names;
  if (!o.images.empty()) {
    images = reconstruction::readGrayImages(o.images, &names);
  } else {
    reconstruction::RawlogReaderOptions reading;
    reading.unproject = false;  // only the images are needed
    reconstruction::RawlogReader reader(o.rawlog, reading);
    while (auto scan = reader.next()) {
      if (scan->intensity.empty()) continue;
      images.push_back(reconstruction::grayOf(scan->intensity));
      names.push_back("scan " + std::to_string(scan->index));
    }
    if (images.empty()) throw InputError(o.rawlog, "", "no scan carries a colour or amplitude image");
  }
  const reconstruction::CalibrationResult r =
      renamingInputErrors("images", o.images.empty() ? o.rawlog : o.images,
                          [&] { return reconstruction::calibrateCamera(images, params); });

  nlohmann::json used = nlohmann::json::array();
  for (std::size_t i : r.used_images) used.push_back(names[i]);
  const CameraIntrinsics& k = r.intrinsics;
  nlohmann::json summary{{"source", o.images.empty() ? o.rawlog : o.images},
                         {"images", images.size()},
                         {"boards_found", r.used_images.size()},
                         {"used_images", used},
                         {"board",
                          {{"inner_columns", params.board.inner_columns},
                           {"inner_rows", params.board.inner_rows},
                           {"square_m", params.board.square_size}}},
                         {"rms_reprojection_px", r.rms_reprojection_px},
                         {"camera",
                          {{"width", k.width},
                           {"height", k.height},
                           {"fx", k.fx},
                           {"fy", k.fy},
                           {"cx", k.cx},
                           {"cy", k.cy},
                           {"distortion_k1_k2_p1_p2_k3", k.distortion}}}};
  if (!o.write_rawlog.empty())
    summary["rawlog_written"] = {{"path", o.write_rawlog},
                                 {"scans", reconstruction::writeRawlogWithIntrinsics(o.rawlog, o.write_rawlog, k)}};
  if (!o.output.empty()) {
    summary["output"] = o.output;
    writeFileAtomically(
        o.output, [&](std::ostream& out) { out << summary.dump(2) << '\n'; }, false);
  }
  summary["time_ms"] = {{"total", context.elapsedMs()}};
  return summary;
}

}  // namespace

void addCalibrateCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "calibrate",
      "Camera intrinsics and lens distortion (OpenCV: findChessboardCorners, cornerSubPix, calibrateCamera) from "
      "checkerboard images in a folder or in a rawlog's colour/amplitude images; optionally writes a copy of the "
      "rawlog with the calibrated camera. See docs/calibration.md");
  auto o = std::make_shared<CalibrateOptions>();
  command->add_option("--images", o->images, "Folder of images (.png .jpg .pgm .ppm .bmp .tif), sorted by name");
  command->add_option("--rawlog", o->rawlog, "Rawlog whose scans' colour or amplitude images show the board");
  command->add_option("--board", o->board, "Inner corners COLUMNSxROWS")->capture_default_str();
  command->add_option("--square", o->square, "Square size in metres")->capture_default_str();
  command->add_flag("--estimate-k3", o->estimate_k3, "Also estimate k3 (held at 0 by default)");
  command->add_option("-o,--output", o->output, "Write the calibration (JSON) here, atomically");
  command->add_option("--write-rawlog", o->write_rawlog, "Write a copy of --rawlog with the calibrated camera");
  command->callback([&runner, o] { runner = [o](CommandContext& context) { context.mapFields({{"Checkerboard", "--board"}});
    context.emit(calibrate(*o, context)); }; });
}

}  // namespace icrkit::app
