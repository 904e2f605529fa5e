#include <icrkit/reconstruction/meshing/ball_pivoting_record.hpp>

#include <nlohmann/json.hpp>

#include <vector>

namespace icrkit::reconstruction {

std::string ballPivotingRecordJson(const BallPivotingReport& r) {
  nlohmann::json passes = nlohmann::json::array();
  std::vector<double> radii_m;
  for (const auto& pass : r.passes) {
    passes.push_back(
        {{"radius_m", pass.radius}, {"seeds", pass.seeds}, {"triangles", pass.triangles}, {"time_ms", pass.time_ms}});
    radii_m.push_back(pass.radius);
  }
  const nlohmann::json record{{"points", r.points},
                              {"median_spacing_m", r.median_spacing},
                              {"radii_m", radii_m},
                              {"passes", passes},
                              {"triangles", r.triangles},
                              {"used_points", r.used_points},
                              {"unused_points", r.unused_points},
                              {"duplicate_points", r.duplicate_points},
                              {"unoriented_points", r.unoriented_points},
                              {"layer_thickness_m", r.layer_thickness},
                              {"thinning_cell_m", r.thinning_cell},
                              {"thinned_points", r.thinned_points},
                              {"reinserted_points", r.reinserted_points},
                              {"mesh_spacing_m", r.mesh_spacing},
                              {"removed_faces", r.removed_faces},
                              {"boundary_edges", r.boundary_edges},
                              {"closed_holes", r.closed_holes},
                              {"folded_holes", r.folded_holes},
                              {"boundary_loops", r.boundary_loops},
                              {"non_manifold_edges", r.non_manifold_edges},
                              {"components", r.components},
                              {"euler_characteristic", r.euler_characteristic}};
  return record.dump();
}

}  // namespace icrkit::reconstruction
