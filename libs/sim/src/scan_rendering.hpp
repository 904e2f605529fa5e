#pragma once
/// \file
/// What the per-sensor renderers share: the camera pose, the scene's
/// appearance with its defaults filled in, counter-based per-pixel random
/// numbers, and row batches cast with the core RayCaster.

#include <icrkit/sim/range_sensor.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

namespace icrkit::sim {

/// The optical frame in the scene.
struct CameraFrame {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< optical frame axes in scene coordinates
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();        ///< optical centre, scene frame

  explicit CameraFrame(const Eigen::Isometry3d& camera_in_scene)
      : rotation(camera_in_scene.rotation()), origin(camera_in_scene.translation()) {}

  /// Ray from the optical centre along a direction given in the optical frame.
  Ray ray(const Eigen::Vector3d& direction_in_camera) const {
    Ray r;
    r.origin = origin;
    r.direction = rotation * direction_in_camera;
    return r;
  }
  Eigen::Vector3d toCamera(const Eigen::Vector3d& scene_point) const {
    return rotation.transpose() * (scene_point - origin);
  }
  Eigen::Vector3d toScene(const Eigen::Vector3d& camera_point) const { return origin + rotation * camera_point; }
};

/// Everything a renderer needs for one frame.
struct RenderContext {
  const RayCaster& scene;
  const SensorModel& model;
  CameraFrame camera;
  std::function<Colour(int, const Eigen::Vector3d&)> colour;           // never empty
  std::function<double(int, const Eigen::Vector3d&)> reflectivity;   // never empty, clamped to [0, 1] by the caller
  std::uint64_t seed;
};

/// The splitmix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mix.
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Random numbers of one pixel: a splitmix64 stream whose start is a hash of
/// (seed, pixel). Each pixel draws its own numbers in a fixed order, so a
/// frame does not depend on how TBB splits it over threads; hashing the
/// pixel (rather than offsetting one stream) keeps neighbouring pixels'
/// streams from overlapping.
class PixelRandom {
public:
  PixelRandom(std::uint64_t seed, std::uint64_t pixel) : state_(mix64(seed ^ mix64(pixel ^ 0x5851f42d4c957f2dULL))) {}

  std::uint64_t next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return mix64(state_);
  }
  /// Uniform in (0, 1]: never 0, so its logarithm is finite.
  double uniform() { return (static_cast<double>(next() >> 11) + 1.0) * 0x1.0p-53; }
  /// Standard normal (Box-Muller; the second value is not kept, so each
  /// call consumes exactly two draws).
  double normal() {
    const double radius = std::sqrt(-2.0 * std::log(uniform()));
    return radius * std::cos(6.283185307179586 * uniform());
  }

private:
  std::uint64_t state_;
};

/// Rows rendered per batch: enough rays per closestHits call to keep every
/// thread busy, few enough that the batch's rays and hits stay in cache-sized
/// buffers instead of a whole frame's.
constexpr int kRowsPerBatch = 32;

/// Angle (radians, 0..pi/2) between a ray direction and a surface normal,
/// whichever side of the surface the ray comes from.
inline double incidenceAngle(const Eigen::Vector3d& unit_direction, const Eigen::Vector3d& unit_normal) {
  return std::acos(std::min(1.0, std::abs(unit_direction.dot(unit_normal))));
}

/// Throws InputError("sensor model", <field>, ...) for a model that cannot
/// be rendered or unprojected.
void checkSensorModel(const SensorModel& model);

void renderKinect(const RenderContext& context, SimulatedScan& scan);
void renderSr4000(const RenderContext& context, SimulatedScan& scan);

}  // namespace icrkit::sim
