// `icrkit convert IN OUT`: between PLY, OBJ, PCD and XYZ, chosen by extension.

#include "commands.hpp"

#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>

#include <memory>
#include <string>

namespace icrkit::app {
namespace {

struct ConvertOptions {
  std::string input;
  std::string output;
  bool ascii = false;
  bool single_precision = false;
  bool big_endian = false;
};

nlohmann::json convert(const ConvertOptions& options, CommandContext& context) {
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
  auto* command = app.add_subcommand("convert", "Convert between .ply, .obj, .pcd and .xyz (by extension)");
  auto options = std::make_shared<ConvertOptions>();
  command->add_option("input", options->input, "Input mesh or cloud")->required()->check(CLI::ExistingFile);
  command->add_option("output", options->output, "Output file, written atomically")->required();
  command->add_flag("--ascii", options->ascii, "ASCII PLY/PCD instead of binary");
  command->add_flag("--float", options->single_precision, "Single-precision positions and normals (PLY/PCD)");
  command->add_flag("--big-endian", options->big_endian, "Binary big-endian PLY");
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) { context.emit(convert(*options, context)); };
  });
}

}  // namespace icrkit::app
