// `icrkit convert IN OUT`: between PLY, OBJ, PCD and XYZ, chosen by
// extension; and a TUM RGB-D folder of depth images into an MRPT rawlog
// (`icrkit convert FOLDER OUT.rawlog`), written by the simulator's rawlog
// writer so that both kinds of recording are stored alike.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "depth_folder_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/reconstruction/input/rawlog_reader.hpp>
#include <icrkit/reconstruction/input/scan_source.hpp>
#include <icrkit/reconstruction/input/tum_folder_reader.hpp>
#include <icrkit/sim/rawlog_writer.hpp>

#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

struct ConvertOptions {
  std::string input;
  std::string output;
  bool ascii = false, single_precision = false, big_endian = false;  // binary, double, little-endian
  std::string poses;
  DepthFolderFlags folder;
  const CLI::App* command = nullptr;
};

// Folder -> rawlog. The simulator's writer takes the whole recording at
// once, so the folder's range images are all held in memory (4 bytes a
// pixel) while it writes.
nlohmann::json convertFolder(const ConvertOptions& options, CommandContext& context) {
  if (lowercaseExtension(options.output) != ".rawlog")
    throw InputError(options.output, "", "a TUM RGB-D folder converts to an MRPT rawlog: expected a .rawlog output");
  reconstruction::TumFolderOptions reading;
  reading.pose_file = options.poses;
  reading.camera = depthCameraOptions(options.folder);
  reading.max_time_difference = options.folder.max_time_difference;
  reading.unproject = false;
  reconstruction::TumFolderReader reader(options.input, reading);
  const reconstruction::DepthCamera& camera = reader.camera();
  context.note(depthScaleNote(camera));

  sim::SensorModel model = sim::kinectV1();
  model.name = "TUM RGB-D folder " + options.input;
  model.intrinsics = camera.intrinsics;
  model.range_is_depth = true;
  // The single-precision values the folder reader uses, so that the rawlog
  // stores the very same counts, units and range limit.
  model.range_units = static_cast<float>(1.0 / camera.depth_scale);
  model.max_range = static_cast<float>(camera.max_range);
  std::vector<sim::SimulatedScan> scans;
  std::vector<sim::View> views;
  std::size_t orthonormalised = 0;
  const Eigen::Matrix3d optical_from_mrpt = reconstruction::mrptSensorAxesInOptical().transpose();
  while (auto scan = reader.next()) {
    sim::SimulatedScan& s = scans.emplace_back();
    s.width = scan->width;
    s.height = scan->height;
    s.range = std::move(scan->range);
    sim::View& view = views.emplace_back();
    // The writer takes optical poses and turns them into MRPT's axes again
    // (a signed permutation both ways: exact).
    view.reported_camera = scan->sensor_pose;
    view.reported_camera.linear() = scan->sensor_pose.linear() * optical_from_mrpt;
    view.true_camera = view.reported_camera;
    view.timestamp = scan->timestamp - sim::kRawlogEpoch;
    orthonormalised += scan->pose_orthonormalised;
  }
  sim::writeRawlog(options.output, model, scans, views);
  return {{"input", options.input},
          {"input_format", "tum_folder"},
          {"output", options.output},
          {"format", "rawlog"},
          {"scans", scans.size()},
          {"poses", options.poses.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.poses)},
          {"pose_matching", reconstruction::poseMatchingName(reader.poseMatching())},
          {"poses_orthonormalised", orthonormalised},
          {"depth_camera", depthCameraJson(camera)},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

nlohmann::json convert(const ConvertOptions& options, CommandContext& context) {
  if (reconstruction::isDepthImageFolder(options.input)) return convertFolder(options, context);
  if (lowercaseExtension(options.output) == ".rawlog")
    throw InputError(options.input, "", "only a TUM RGB-D folder (depth.txt, depth/*.png) converts to a rawlog");
  refuseDepthFolderOptions(*options.command, options.folder);
  if (!options.poses.empty()) throw InputError("--poses", "", "applies to a TUM RGB-D folder input");
  const auto output_format = io::formatFromPath(options.output);
  io::formatFromPath(options.input);
  const TriangleMesh mesh = io::readTriangleMesh(options.input);
  io::WriteOptions write;
  write.encoding = options.ascii ? io::Encoding::Ascii : io::Encoding::Binary;
  write.real_type = options.single_precision ? ScalarType::Float32 : ScalarType::Float64;
  write.big_endian = options.big_endian;

  std::size_t dropped_faces = 0;
  if (io::formatHoldsFaces(output_format)) {
    io::writeTriangleMesh(options.output, mesh, write);
  } else {
    dropped_faces = mesh.faces.size();
    if (dropped_faces > 0)
      context.note("icrkit: " + options.output + " holds points only; " + std::to_string(dropped_faces) +
                   " faces not written");
    io::writePointCloud(options.output, mesh.vertices, write);
  }
  return {{"input", options.input},
          {"output", options.output},
          {"format", io::formatName(output_format)},
          {"vertices", mesh.vertices.size()},
          {"faces_written", mesh.faces.size() - dropped_faces},
          {"faces_dropped", dropped_faces},
          {"time_ms", {{"total", context.elapsedMs()}}}};
}

}  // namespace

void addConvertCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "convert",
      "Convert between .ply, .obj, .pcd and .xyz (by extension), or a TUM RGB-D folder (depth.txt, 16-bit depth "
      "PNGs, optional camera.json) into an MRPT rawlog (OUT.rawlog) that `icrkit reconstruct` reads like the folder");
  auto options = std::make_shared<ConvertOptions>();
  options->command = command;
  command->add_option("input", options->input, "Input mesh or cloud, or a TUM RGB-D folder")
      ->required()
      ->check(CLI::ExistingPath);
  command->add_option("output", options->output, "Output file, written atomically")->required();
  command->add_option("--poses", options->poses,
                      "TUM folder input: TUM file of the camera's OPTICAL-frame poses (x right, y down, z forward; "
                      "camera to object), written into the rawlog as sensorPose in MRPT's axes");
  addDepthFolderOptions(*command, options->folder);
  command->add_flag("--ascii", options->ascii, "ASCII PLY/PCD instead of binary");
  command->add_flag("--float", options->single_precision, "Single-precision positions and normals (PLY/PCD)");
  command->add_flag("--big-endian", options->big_endian, "Binary big-endian PLY");
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      context.mapFields(
          {{"DepthCameraOptions::depth_scale", "--depth-scale"}, {"DepthCameraOptions::intrinsics", "--intrinsics"}});
      context.emit(convert(*options, context));
    };
  });
}

}  // namespace icrkit::app
