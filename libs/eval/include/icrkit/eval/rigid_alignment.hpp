#pragma once
/// \file
/// Rigid alignment of a reconstructed mesh to the CAD surface: the stand-in
/// for the paper's manual registration when a reconstruction's frame is not
/// the CAD model's (real recordings; simulated ones are already aligned).
///
/// Point-to-plane ICP: each iteration pairs sampled vertices of the moving
/// mesh with their closest points on the CAD surface (Embree, exact in double
/// precision), drops pairs farther than the current distance limit, weights
/// the rest with Huber's function of the point-to-plane residual, and solves
/// the linearised 6-DoF least-squares problem (Chen & Medioni; small-angle
/// rotation, re-orthonormalised). The distance limit shrinks from
/// `max_distance` to `min_distance` as the fit converges, so gross outliers
/// (table remnants, flying pixels) never pull the fit.

#include <icrkit/core/triangle_mesh.hpp>

#include <Eigen/Geometry>

#include <cstddef>

namespace icrkit::eval {

struct AlignmentParameters {
  /// Moving vertices used (evenly strided over those some face uses, or over
  /// all of a mesh without faces), 0 = all.
  std::size_t max_samples = 20000;
  double max_distance = 0.01;       ///< metres: pairs farther apart are ignored at the start
  double min_distance = 0.002;      ///< metres: the limit never shrinks below this
  double huber = 0.001;             ///< metres: residuals above it get weight huber / |r|
  int max_iterations = 50;
  /// Converged when an iteration moves no sample point farther than this
  /// (metres): the step's translation plus its rotation angle times the
  /// samples' largest distance from the origin.
  double tolerance = 1e-6;
};

struct AlignmentResult {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  ///< moving -> CAD frame
  int iterations = 0;
  bool converged = false;
  std::size_t pairs = 0;            ///< pairs used in the last iteration
  double rms_before_m = 0.0;        ///< point-to-surface RMS of the pairs within max_distance, before
  double rms_after_m = 0.0;         ///< the same after (same limit)
};

/// Aligns `moving` to `cad`. Throws InputError for meshes without faces or
/// vertices, invalid parameters, or fewer than 6 pairs within max_distance.
AlignmentResult alignToCad(const TriangleMesh& moving, const TriangleMesh& cad, const AlignmentParameters& params = {});

/// Moves the vertices and rotates the normals of `mesh` in place.
void transformMesh(TriangleMesh& mesh, const Eigen::Isometry3d& transform);

}  // namespace icrkit::eval
