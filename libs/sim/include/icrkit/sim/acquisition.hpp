#pragma once
/// \file
/// The paper's two acquisition setups (Krug et al., Section II-A) as camera
/// trajectories in the object frame, the static scene each one shows, and
/// the errors of the camera poses a robot reports.
///
/// - Setup A: a SwissRanger SR4000 on an industrial arm moves around the
///   object on a partial sphere; the object stands fixed on a table at the
///   workspace centre.
/// - Setup B: a fixed Kinect looks at the object, which sits on a
///   checkerboard-textured support on the arm's flange and is turned about
///   the flange's (vertical) axis. In the object frame this is a camera on a
///   circle around the z axis, the support turning with the object.
///
/// Poses are those of the camera's optical frame (x right, y down, z
/// forward) in the object frame (z up, object standing on z = 0).

#include <icrkit/core/triangle_mesh.hpp>
#include <icrkit/sim/range_sensor.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <optional>
#include <vector>

namespace icrkit::sim {

enum class Setup { A, B };

/// "A" or "B" (either case). Throws InputError("--setup", ...) otherwise.
Setup parseSetup(const std::string& name);
std::string setupName(Setup setup);

/// Errors of the camera pose the robot reports, relative to the true one:
/// reported = true x hand-eye x drift(k) x noise(k), all right-multiplied in
/// the camera's frame (docs/rawlog.md, "Reported-pose errors"). The defaults
/// are the industrial arm's (armPoseErrors()): its pose repeatability and a
/// careful hand-eye calibration. mobilePoseErrors() is the mobile
/// manipulator's: per-view noise only, ten times the arm's and more.
struct PoseErrorModel {
  /// Recorded in manifest.json: "arm", "mobile", "none" or "custom".
  std::string name = "arm";
  double noise_translation = 0.0003;   ///< m, sigma per axis, independent per view (arm repeatability and backlash)
  double noise_rotation = 0.0005;      ///< rad, sigma per axis, independent per view
  double hand_eye_translation = 0.002; ///< m, length of the fixed camera-mount offset (direction from the seed)
  double hand_eye_rotation = 0.003;    ///< rad, angle of the fixed camera-mount rotation error (axis from the seed)
  double drift_translation = 0.00005;  ///< m per view, along a fixed direction (thermal drift of the arm)
  double drift_rotation = 0.00005;     ///< rad per view, about a fixed axis
};

/// The industrial arm (the defaults above).
PoseErrorModel armPoseErrors();
/// A mobile manipulator: independent Gaussian errors per view, 3 mm per
/// translation axis and 0.5 deg (8.73 mrad) per rotation axis, nothing fixed
/// or drifting.
PoseErrorModel mobilePoseErrors();
/// Independent Gaussian errors per view only, with these sigmas per axis
/// (m, rad); named "custom". Throws InputError("--pose-error", ...) for a
/// negative or non-finite sigma.
PoseErrorModel independentPoseErrors(double sigma_translation, double sigma_rotation);
/// No error at all: the reported poses are the true ones ("none").
PoseErrorModel perfectPoses();

/// "arm", "mobile", "none" (any case), or explicit per-view sigmas
/// "T,R" with units, T in mm, cm or m and R in deg, mrad or rad
/// ("5mm,1deg"; see independentPoseErrors). Throws InputError(source, ...)
/// otherwise.
PoseErrorModel parsePoseErrorModel(const std::string& text, const std::string& source = "pose error model");

struct AcquisitionParameters {
  Setup setup = Setup::B;
  int views = 36;
  /// Distance from the camera to the object's bounding-box centre (m,
  /// finite and > 0); unset: the setup's default (A: 0.6 m, B: 0.7 m, inside
  /// both sensors' ranges with the object filling a good part of the image).
  std::optional<double> distance;
  /// Setup A: the partial sphere spans these elevations (radians above the
  /// horizontal plane through the object's centre), views on a spiral.
  double min_elevation = 0.15, max_elevation = 0.9;
  /// Setup B: the camera's fixed elevation (radians).
  double elevation = 0.45;
  PoseErrorModel errors;
  std::uint64_t seed = 1;
};

struct View {
  Eigen::Isometry3d true_camera = Eigen::Isometry3d::Identity();      ///< optical frame in the object frame
  Eigen::Isometry3d reported_camera = Eigen::Isometry3d::Identity();  ///< what the robot reports
  double timestamp = 0.0;  ///< seconds since the first view
};

/// The views of a setup around an object with the given bounds
/// (object frame), deterministic for the seed. Throws InputError for
/// views <= 0, a non-finite or negative distance or pose error.
std::vector<View> planViews(const AcquisitionParameters& params, const Eigen::AlignedBox3d& object_bounds);

/// The scene a setup's sensor sees: the object plus the setup's fixtures
/// (A: a table top under the object; B: the support plate with its
/// checkerboard and the post to the flange), all in the object frame, and
/// the appearance of each face (colour, near-infrared reflectivity).
struct Scene {
  TriangleMesh mesh;
  std::size_t object_faces = 0;  ///< faces [0, object_faces) are the object's
  SceneAppearance appearance;
};
Scene buildScene(const TriangleMesh& object, Setup setup);

}  // namespace icrkit::sim
