// `icrkit mesh IN -o OUT`: ball pivoting (reconstruction::ballPivoting) of
// an oriented point cloud. Points without normals get estimated ones
// (ndt::estimateNormals). Writes the mesh, whose vertices are exactly the
// input points, and the JSON summary next to it.

#include "argument_parsing.hpp"
#include "commands.hpp"
#include "mesh_options.hpp"

#include <icrkit/core/error.hpp>
#include <icrkit/core/io/file_format.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/ndt/normal_estimation.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting.hpp>
#include <icrkit/reconstruction/meshing/ball_pivoting_record.hpp>
#include <icrkit/reconstruction/fusion/octree_fusion.hpp>

#include <memory>
#include <string>
#include <vector>

namespace icrkit::app {
namespace {

nlohmann::json mesh(const MeshOptions& options, CommandContext& context) {
  // Arguments are checked before a large file is read.
  const reconstruction::BallPivotingParameters params = ballPivotingParameters(options);
  ndt::NormalEstimationParameters normal_params = normalEstimationParameters(options);
  io::formatFromPath(options.input);
  io::formatFromPath(options.output);
  const std::string summary_path = summaryPathFor(options.output);
  if (summary_path == options.output)
    throw InputError(options.output, "", "the output needs an extension other than .json (the summary goes there)");

  const double read_start = context.elapsedMs();
  PointCloud cloud = io::readPointCloud(options.input);
  const double read_ms = context.elapsedMs() - read_start;

  std::string normals_source = "input";
  double normals_ms = 0.0;
  if (options.estimate_normals || !cloud.hasNormals()) {
    if (!options.estimate_normals)
      context.note(options.input + " has no normals: estimating them (see --normal-radius, --viewpoint)");
    const double start = context.elapsedMs();
    // A fused cloud carries each point's sensor position (viewpoint_x/y/z,
    // from the reconstruction's fusion): each normal then faces its own.
    if (options.viewpoint.empty()) normal_params.viewpoints = reconstruction::fusionViewpoints(cloud);
    if (!normal_params.viewpoints.empty()) normals_source = "estimated, facing each point's viewpoint attribute";
    renamingInputErrors("point cloud", options.input, [&] { return ndt::estimateNormals(cloud, normal_params); });
    normals_ms = context.elapsedMs() - start;
    if (normals_source == "input") normals_source = "estimated";
  }

  const double mesh_start = context.elapsedMs();
  const reconstruction::BallPivotingResult result =
      renamingInputErrors("point cloud", options.input, [&] { return reconstruction::ballPivoting(cloud, params); });
  const double mesh_ms = context.elapsedMs() - mesh_start;

  const double write_start = context.elapsedMs();
  io::writeTriangleMesh(options.output, result.mesh);
  const double write_ms = context.elapsedMs() - write_start;

  nlohmann::json summary = nlohmann::json::parse(reconstruction::ballPivotingRecordJson(result.report));
  summary["input"] = options.input;
  summary["output"] = options.output;
  summary["summary"] = summary_path;
  summary["normals"] = normals_source;
  summary["time_ms"] = {{"read", read_ms},
                        {"normals", normals_ms},
                        {"mesh", mesh_ms},
                        {"write", write_ms},
                        {"total", context.elapsedMs()}};
  writeSummaryFile(summary_path, summary);
  return summary;
}

}  // namespace

void addMeshCommand(CLI::App& app, CommandRunner& runner) {
  auto* command = app.add_subcommand(
      "mesh",
      "Ball pivoting surface reconstruction (Bernardini et al. 1999) of an oriented point cloud, with several "
      "increasing radii. The mesh's vertices are exactly the input points in input order, with their normals and "
      "attributes (points no triangle uses stay, unreferenced). Writes OUT and the JSON summary next to it (OUT "
      "with .json)");
  auto options = std::make_shared<MeshOptions>();
  command->add_option("input", options->input, "Point cloud or mesh (.ply, .obj, .pcd, .xyz); meshes give their vertices")
      ->required();
  command->add_option("-o,--output", options->output, "Output mesh, written atomically (.ply keeps the attributes)")
      ->required();
  command->add_option("--radii", options->radii,
                      "Ball radii, increasing: metres (0.001,0.002) or multiples of the median nearest-neighbour "
                      "spacing (1.5x,2x). Default: 1.5x,2.5x, plus 2.2 times the 90th percentile of the "
                      "nearest-neighbour distances when that is over 3x (unevenly sampled clouds)");
  command
      ->add_option("--thinning", options->thinning,
                   "A noise layer thicker than its spacing (a cloud fused from many views) is thinned to one point "
                   "per cube of this factor x its measured thickness before pivoting, the others are put back "
                   "into the faces afterwards; 0 = off (docs/meshing.md)")
      ->capture_default_str();
  command->add_flag("--no-reinsert", options->no_reinsert,
                    "Leave the points the thinning left out unused instead of putting them back into the faces");
  command
      ->add_option("--fill-holes", options->fill_holes,
                   "Fill holes of up to this many boundary edges (and a perimeter of up to 8 x the largest radius) "
                   "over their own points; 0 = off")
      ->capture_default_str();
  command->add_flag("--keep-folded-holes", options->keep_folded_holes,
                    "Leave open the holes whose rim is folded over (no fill can face the point normals "
                    "everywhere); by default they are filled where the fill lies on seen surface (docs/meshing.md)");
  command
      ->add_option("--min-component-faces", options->min_component_faces,
                   "Take out components with fewer faces than this (flakes beside the surface); 0 = keep all")
      ->capture_default_str();
  command->add_flag("--estimate-normals", options->estimate_normals,
                    "Estimate normals even when the input has some (done anyway when it has none)");
  command
      ->add_option("--normal-radius", options->normal_radius,
                   "Window radius of the normal estimate: metres or a multiple of the spacing")
      ->capture_default_str();
  command->add_option("--viewpoint", options->viewpoint,
                      "Sensor position x,y,z (metres) that estimated normals face (default: outwards, made "
                      "consistent over neighbours)");
  command->callback([&runner, options] {
    runner = [options](CommandContext& context) {
      context.mapFields({{"BallPivotingParameters::radii", "--radii"},
                         {"BallPivotingParameters::thinning_factor", "--thinning"},
                         {"NormalEstimationParameters::radius", "--normal-radius"}});
      context.emit(mesh(*options, context));
    };
  });
}

}  // namespace icrkit::app
