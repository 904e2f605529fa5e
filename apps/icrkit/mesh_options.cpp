#include "mesh_options.hpp"

#include "argument_parsing.hpp"

#include <vector>

namespace icrkit::app {

reconstruction::BallPivotingParameters ballPivotingParameters(const MeshOptions& options) {
  reconstruction::BallPivotingParameters params;
  if (!options.radii.empty()) {
    params.radii = parseLengths("--radii", options.radii);
    params.gap_radius_factor = 0.0;  // the radii given are all there is
  }
  params.thinning_factor = options.thinning;
  params.reinsert_thinned = !options.no_reinsert;
  params.fill_folded_holes = !options.keep_folded_holes;
  params.close_holes_up_to = options.fill_holes;
  params.min_component_faces = options.min_component_faces;
  params.validate();
  return params;
}

ndt::NormalEstimationParameters normalEstimationParameters(const MeshOptions& options) {
  ndt::NormalEstimationParameters normal_params;
  normal_params.radius = parseLength("--normal-radius", options.normal_radius);
  if (!options.viewpoint.empty()) normal_params.viewpoint = parsePoint("--viewpoint", options.viewpoint);
  return normal_params;
}

void addMeshOptions(CLI::App& command, MeshOptions& options) {
  command
      .add_option("input", options.input, "Point cloud or mesh (.ply, .obj, .pcd, .xyz); meshes give their vertices")
      ->required();
  command.add_option("-o,--output", options.output, "Output mesh, written atomically (.ply keeps the attributes)")
      ->required();
  command.add_option("--radii", options.radii,
                     "Ball radii, increasing: metres (0.001,0.002) or multiples of the median nearest-neighbour "
                     "spacing (1.5x,2x). Default: 1.5x,2.5x, plus 2.2 times the 90th percentile of the "
                     "nearest-neighbour distances when that is over 3x (unevenly sampled clouds)");
  command
      .add_option("--thinning", options.thinning,
                  "A noise layer thicker than its spacing (a cloud fused from many views) is thinned to one point "
                  "per cube of this factor x its measured thickness before pivoting, the others are put back "
                  "into the faces afterwards; 0 = off (docs/meshing.md)")
      ->capture_default_str();
  command.add_flag("--no-reinsert", options.no_reinsert,
                   "Leave the points the thinning left out unused instead of putting them back into the faces");
  command
      .add_option("--fill-holes", options.fill_holes,
                  "Fill holes of up to this many boundary edges (and a perimeter of up to 8 x the largest radius) "
                  "over their own points; 0 = off")
      ->capture_default_str();
  command.add_flag("--keep-folded-holes", options.keep_folded_holes,
                   "Leave open the holes whose rim is folded over (no fill can face the point normals "
                   "everywhere); by default they are filled where the fill lies on seen surface (docs/meshing.md)");
  command
      .add_option("--min-component-faces", options.min_component_faces,
                  "Take out components with fewer faces than this (flakes beside the surface); 0 = keep all")
      ->capture_default_str();
  command.add_flag("--estimate-normals", options.estimate_normals,
                   "Estimate normals even when the input has some (done anyway when it has none)");
  command
      .add_option("--normal-radius", options.normal_radius,
                  "Window radius of the normal estimate: metres or a multiple of the spacing")
      ->capture_default_str();
  command.add_option("--viewpoint", options.viewpoint,
                     "Sensor position x,y,z (metres) that estimated normals face (default: outwards, made "
                     "consistent over neighbours)");
}

}  // namespace icrkit::app
