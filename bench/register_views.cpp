// icrkit's registration stage alone on prepared views: the icrkit side of
// bench/registration_sweep.py, on exactly the points Open3D gets.
//
//   bench_register_views VIEWS_DIR -o POSES.txt [--no-model-alignment]
//
// VIEWS_DIR is what `icrkit reconstruct --write-registration-input` writes
// (or the sweep prepares from other recordings): view_NNN.ply, each view's
// object points in its sensor frame, and start.txt, the starting poses
// (TUM, sensor -> object). The registration runs with the parameters
// `icrkit reconstruct` uses. Writes the registered poses (TUM, the starting
// stamps) and prints one JSON line: views, time_s (registration only, file
// reading excluded), pairs accepted and rejected.
#include <icrkit/core/error.hpp>
#include <icrkit/core/io/geometry_io.hpp>
#include <icrkit/core/pose.hpp>
#include <icrkit/reconstruction/reconstruction_pipeline.hpp>
#include <icrkit/reconstruction/registration/scan_sequence_registration.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace icrkit;

int main(int argc, char** argv) {
  if (argc < 4 || std::string(argv[2]) != "-o") {
    std::fprintf(stderr, "usage: %s VIEWS_DIR -o POSES.txt [--no-model-alignment] [--set NAME=VALUE]... (e.g. --set joint=0: without the joint refinement)\n", argv[0]);
    return 2;
  }
  try {
    const fs::path dir(argv[1]);
    const std::vector<StampedPose> starts = readTumTrajectory((dir / "start.txt").string());
    std::vector<PointCloud> views;
    for (std::size_t i = 0;; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "view_%03zu.ply", i);
      if (!fs::exists(dir / name)) break;
      views.push_back(io::readPointCloud((dir / name).string()));
    }
    if (views.size() != starts.size())
      throw InputError(dir.string(), "", std::to_string(views.size()) + " views but " + std::to_string(starts.size()) +
                                             " starting poses");
    std::vector<Eigen::Isometry3d> initial;
    for (const StampedPose& s : starts) initial.push_back(s.pose);
    reconstruction::ReconstructionParameters defaults;
    // Variants for the sweep: a few of the registration's parameters.
    auto& r = defaults.registration;
    for (int a = 4; a < argc; ++a) {
      const std::string arg = argv[a];
      if (arg == "--no-model-alignment") {
        r.model_alignment_resolutions.clear();
        continue;
      }
      if (arg.rfind("--set", 0) != 0 || a + 1 >= argc) throw InputError(arg, "", "unknown argument");
      const std::string kv = argv[++a];
      const std::string name = kv.substr(0, kv.find('='));
      const std::string text = kv.substr(kv.find('=') + 1);
      if (name == "model_levels") {
        r.model_alignment_resolutions.clear();
        for (std::size_t at = 0; at < text.size();) {
          const std::size_t comma = std::min(text.find(',', at), text.size());
          r.model_alignment_resolutions.push_back(std::stod(text.substr(at, comma - at)));
          at = comma + 1;
        }
        continue;
      }
      const double value = std::stod(text);
      if (name == "prior_sigma") r.prior_sigma_translation = r.prior_sigma_rotation = value;
      else if (name == "odometry_sigma") r.odometry_sigma_translation = r.odometry_sigma_rotation = value;
      else if (name == "max_partners") r.max_partners = int(value);
      else if (name == "refinement_rounds") r.refinement_rounds = int(value);
      else if (name == "min_pair_overlap") r.min_pair_overlap = value;
      else if (name == "estimate_robot_precision") r.estimate_robot_precision = value != 0;
      else if (name == "degeneracy_ratio") r.degeneracy_ratio = value;
      else if (name == "hessian_information") r.hessian_information = value != 0;
      else if (name == "variance_rounds") r.variance_rounds = int(value);
      else if (name == "retry_angle") r.model_alignment_retry_angle = value;
      else if (name == "reseat") r.reseat_unplaced_views = value != 0;
      else if (name == "reseat_min_shared") r.reseat_min_shared_cubes = value;
      else if (name == "reseat_min_pair") r.reseat_min_pair_cubes = value;
      else if (name == "reseat_search_step") r.reseat_search_step = value;
      else if (name == "reseat_search_steps") r.reseat_search_steps = int(value);
      else if (name == "pair_ndt") r.pair_ndt = value != 0;
      else if (name == "ndt_eps") r.ndt.translation_epsilon = r.ndt.rotation_epsilon = value;
      else if (name == "normals_index_order") r.normals_in_index_order = value != 0;
      else if (name == "pair_ndt_placed") r.pair_ndt_for_placed_views = value != 0;
      else if (name == "pair_retry") r.pair_ndt_retry_rejected = value != 0;
      else if (name == "reseat_passes") r.reseat_passes = int(value);
      else if (name == "unsettled_pair_move") r.unsettled_pair_move = value;
      else if (name == "max_unsettled_rounds") r.max_unsettled_rounds = int(value);
      else if (name == "max_icp_points") r.icp_max_source_points = static_cast<std::size_t>(value);
      else if (name == "min_normalized_score") r.min_normalized_score = value;
      else if (name == "model_max_translation") r.model_alignment_max_translation = value;
      else if (name == "incremental") r.incremental = value != 0;
      else if (name == "joint") r.joint_refinement = value != 0;
      else if (name == "joint_incidence") r.joint.target_max_incidence = value;
      else if (name == "joint_iterations") r.joint.iterations = int(value);
      else if (name == "joint_sources") r.joint.max_source_points = static_cast<std::size_t>(value);
      else if (name == "joint_normal_radius") r.joint_normal_radius = value;
      else if (name == "joint_min_linked_pair_ratio") r.joint_min_linked_pair_ratio = value;
      else if (name == "max_cell_to_spread") r.model_alignment_max_cell_to_spread = value;
      else throw InputError(name, "", "not a parameter this tool sets");
    }
    const auto start = std::chrono::steady_clock::now();
    const reconstruction::SequenceRegistrationResult result =
        reconstruction::registerScanSequence(views, initial, defaults.registration);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<StampedPose> out;
    for (std::size_t i = 0; i < starts.size(); ++i) out.push_back({starts[i].timestamp, result.poses[i]});
    writeTumTrajectory(argv[3], out);
    std::size_t accepted = 0;
    for (const auto& p : result.pairs) accepted += p.accepted;
    std::cout << nlohmann::json{{"views", views.size()},
                                {"time_s", seconds},
                                {"stage_ms",
                                 {{"prepare", result.stage_times.prepare_ms},
                                  {"model_alignment", result.stage_times.model_alignment_ms},
                                  {"pairs", result.stage_times.pairs_ms},
                                  {"graph", result.stage_times.graph_ms},
                                  {"joint", result.stage_times.joint_ms}}},
                                {"pairs_accepted", accepted},
                                {"joint_iterations", result.joint_iterations},
                                {"joint_pairs", result.joint_pairs},
                                {"joint_linked_view_pairs", result.joint_linked_view_pairs},
                                {"joint_graph_view_pairs", result.joint_graph_view_pairs},
                                {"joint_applied", result.joint_applied},
                                {"joint_rejection", result.joint_rejection},
                                {"pairs_rejected", result.pairs.size() - accepted},
                                {"model_alignment_accepted", result.model_alignment_accepted},
                                {"model_alignment_levels", result.model_alignment_resolutions},
                                {"model_spread_mm", result.model_spread_m * 1e3},
                                {"refinement_rounds", result.refinement_rounds},
                                {"unsettled_pairs_registered", result.unsettled_pairs_registered},
                                {"unsettled_pairs_accepted", result.unsettled_pairs_accepted},
                                {"pairs_retried_coarse", result.pairs_retried_coarse},
                                {"pairs_retried_accepted", result.pairs_retried_accepted},
                                {"reseat_tried", result.reseat_tried},
                                {"reseat_moved", result.reseat_moved},
                                {"reseat_searched", result.reseat_searched},
                                {"model_alignment_median_move_m", result.model_alignment_median_move_m},
                                {"model_alignment_max_move_m", result.model_alignment_max_move_m},
                                {"measured_odometry_sigma_mm", result.measured_odometry_sigma_translation_m * 1e3},
                                {"measured_odometry_sigma_deg", result.measured_odometry_sigma_rotation_rad * 180 / M_PI},
                                {"prior_sigma_mm", result.prior_sigma_translation_m * 1e3},
                                {"odometry_sigma_mm", result.odometry_sigma_translation_m * 1e3},
                                {"pair_variance_factor", result.pair_variance_factor}}
                     .dump()
              << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_register_views: %s\n", e.what());
    return 2;
  }
}
