// `icrkit calibrate-range RAWLOG --scene MESH --poses TUM -o model.json`:
// the systematic range error of a ToF camera (reconstruction::
// calibrateRangeError) from a recording of a known scene at known poses;
// `icrkit reconstruct --range-correction model.json` removes it.

#include "argument_parsing.hpp"
#include "commands.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/reconstruction/calibration/range_calibration.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace icrkit::app {
namespace {

struct CalibrateRangeOptions {
  std::string input;
  std::string scene;
  std::string poses;
  std::string images;
  std::string output;
  double wavelength = 1.249;
  double max_residual = 0.02;
};

nlohmann::json calibrateRange(const CalibrateRangeOptions& o, CommandContext& context) {
  if (!(o.wavelength >= 0) || !std::isfinite(o.wavelength))
    throw InputError("--wavelength", "", "expected 0 (no periodic term) or metres");
  if (!(o.max_residual > 0) || !std::isfinite(o.max_residual))
    throw InputError("--max-residual", "", "expected a positive length in metres");
  if (o.output.size() < 5 || o.output.compare(o.output.size() - 5, 5, ".json") != 0)
    throw InputError(o.output, "", "expected a .json output");
  const TriangleMesh scene = io::readTriangleMesh(o.scene);
  reconstruction::RawlogReaderOptions reader;
  reader.pose_file = o.poses;
  reader.images_folder = o.images;
  reconstruction::RangeCalibrationParameters params;
  params.wavelength = o.wavelength;
  params.max_residual = o.max_residual;
  const reconstruction::RangeCalibrationResult r = renamingInputErrors(
      "scene mesh", o.scene, [&] { return reconstruction::calibrateRangeError(o.input, reader, scene, params); });
  reconstruction::writeRangeErrorModel(o.output, r.model, r.report);
  const double amplitude = std::hypot(r.model.sine, r.model.cosine);
  return {{"input", o.input},
          {"scene", o.scene},
          {"output", o.output},
          {"wavelength_m", r.model.wavelength},
          {"offset_mm", r.model.offset * 1e3},
          {"slope", r.model.slope},
          {"periodic_amplitude_mm", amplitude * 1e3},
          {"scans", r.report.scans},
          {"samples", r.report.samples},
          {"rejected", r.report.rejected},
          {"range_m", {r.report.min_range_m, r.report.max_range_m}},
          {"rms_before_mm", r.report.rms_before_m * 1e3},
          {"rms_after_mm", r.report.rms_after_m * 1e3},
          {"time_ms", context.elapsedMs()}};
}

}  // namespace

void addCalibrateRangeCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "calibrate-range",
      "Systematic range error of a time-of-flight camera (offset, slope and the periodic 'wiggling' term) from a "
      "recording of a known scene at known poses: every pixel's ray is cast at the scene mesh and the measured "
      "ranges are fitted against the cast ones. Writes a JSON model for `icrkit reconstruct --range-correction`");
  auto options = std::make_shared<CalibrateRangeOptions>();
  command->add_option("input", options->input, "Rawlog of the reference recording")->required();
  command->add_option("--scene", options->scene, "Mesh of the recorded scene (metres, the poses' frame)")->required();
  command->add_option("--poses", options->poses,
                      "TUM file of the scans' true sensor poses (default: the rawlog's own, which must be exact)");
  command->add_option("--images", options->images, "Folder of externally stored images");
  command->add_option("--wavelength", options->wavelength,
                      "Period of the wiggling term in metres, c / (8 f): 1.249 for an SR4000 at 30 MHz; 0: none")
      ->capture_default_str();
  command->add_option("--max-residual", options->max_residual,
                      "Pixels further than this from the scene (metres) are left out")
      ->capture_default_str();
  command->add_option("-o,--output", options->output, "Model file (.json), written atomically")->required();
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) { context.emit(calibrateRange(*options, context)); };
  });
}

}  // namespace icrkit::app
