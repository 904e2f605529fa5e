#pragma once
/// \file
/// Joint refinement of all views at once: point-to-plane residuals between
/// every pair of overlapping views, all poses solved together (Gauss-Newton
/// on one dense system), the final step of the scan sequence registration.
///
/// Why after the pose graph: the graph holds each pair as a relative pose
/// with an information matrix, measured on the pair alone; a joint solve
/// weighs every correspondence of every pair against all the others, so a
/// group of views can move together (the back of an object against its
/// front), which neither a pair nor one view against the others can do.
///
/// Why face-on targets: a depth camera's points on a surface it sees at a
/// slant spread along the line of sight and their fitted normals tilt, so
/// a tangent plane there misplaces every point matched to it. On the real
/// PrimeSense views of the issue-35 sweep, matching to every target point
/// leaves the views where the pose graph leaves them, 0.87 mm from the
/// reference surface; matching only to points seen within 18 deg of their
/// normal brings them to 0.71 mm. On the same recording's reconstruction
/// from its own crop it does the opposite (0.69 -> 0.81 mm), so the scan
/// sequence registration runs it only when asked (docs/reconstruction.md,
/// "Joint refinement").
///
/// Conventions: views' points and normals in their sensor frames (the
/// sensor at the origin); poses map sensor to world.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace icrkit::reconstruction {

struct JointRefinementParameters {
  /// Gauss-Newton iterations, each with fresh correspondences.
  int iterations = 12;
  /// Pairing distance (metres), coarse to fine over the iterations (equal
  /// shares): a depth camera's at arm's length.
  std::vector<double> max_distances{0.004, 0.003, 0.002};
  /// Geman-McClure scale of the point-to-plane residual (metres).
  double kernel_width = 0.001;
  /// A target point counts only when its sensor saw it within this angle
  /// of its normal (radians; 18.2 deg, cos = 0.95). >= pi/2: every point.
  double target_max_incidence = 0.3176;
  /// A correspondence counts only when the two points' normals agree to
  /// within this cosine (the two sides of a thin part stay apart).
  double min_normal_cosine = 0.8;
  /// Sources: each view's points reduced to centroids of cubes of this
  /// edge (metres), at most `max_source_points` of them (an even stride).
  double source_voxel_size = 0.002;
  std::size_t max_source_points = 3000;
  /// A pair of views enters an iteration with at least this many
  /// correspondences.
  std::size_t min_pair_correspondences = 50;
  /// Each view is held to its incoming pose by a prior of these standard
  /// deviations (metres, radians): it fixes the gauge and is weak against
  /// thousands of correspondences.
  double prior_sigma_translation = 0.005;
  double prior_sigma_rotation = 0.01;
  /// Stops when no view moves more than these in an iteration.
  double translation_epsilon = 1e-6;
  double rotation_epsilon = 1e-6;
};

struct JointRefinementResult {
  std::vector<Eigen::Isometry3d> poses;
  int iterations = 0;
  /// Pairs of views with correspondences in the last iteration: ordered
  /// (view i's sources against view j's targets), and unordered.
  std::size_t pairs = 0;
  std::size_t linked_view_pairs = 0;
  /// Weighted RMS point-to-plane residual of the last iteration (metres).
  double rms_m = 0.0;
};

/// Refines `poses` of `views` (points and unit normals per view, sensor
/// frame; normals of either sign). Views with fewer than 3 points keep
/// their pose. Throws InputError on mismatched sizes or bad parameters.
/// Deterministic for any thread count.
JointRefinementResult refineJointly(const std::vector<std::vector<Eigen::Vector3d>>& points,
                                    const std::vector<std::vector<Eigen::Vector3d>>& normals,
                                    const std::vector<Eigen::Isometry3d>& poses,
                                    const JointRefinementParameters& params = {});

}  // namespace icrkit::reconstruction
