/// \file
/// Renders a Kinect v1 frame: for each pixel, where the IR camera samples
/// the surface (lateral noise), whether the projector lights that point
/// (shadows), the depth it triangulates (axial noise, 1/8-pixel disparity
/// steps), and the registered colour and IR images.

#include "gaussian_random_field.hpp"
#include "kinect_model.hpp"
#include "lens_distortion.hpp"
#include "scan_rendering.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace icrkit::sim {
namespace {

// A surface point is in the projector's shadow when something lies on the
// segment between them. Hits within this distance of the point itself are
// the point's own surface (its face, or a neighbouring facet of a
// tessellated curved surface met at a shared edge), not an occluder.
constexpr double kShadowTolerance = 0.002;  // metres

// Per pixel, between the passes of one batch.
struct PixelState {
  Eigen::Vector3d nominal = Eigen::Vector3d::Zero();  // unit ray through the pixel centre, scene frame
  double depth = 0.0;                                  // noise-free depth of the surface sampled, 0: none
  double incidence = 0.0;                              // radians, of the pixel's ray on that surface
  bool candidate = false;                              // a surface was sampled, the shadow ray decides
};

std::uint8_t toByte(double value) { return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 1.0) * 255.0)); }

}  // namespace

void renderKinect(const RenderContext& context, SimulatedScan& scan) {
  const SensorModel& model = context.model;
  const CameraIntrinsics& in = model.intrinsics;
  const CameraFrame& camera = context.camera;
  const Eigen::Vector3d projector = camera.toScene(Eigen::Vector3d(model.baseline, 0.0, 0.0));
  const double fb = in.fx * model.baseline;  // depth = fb / disparity

  std::vector<Ray> rays;
  std::vector<RayHit> nominal_hits, sampled_hits, shadow_hits;
  std::vector<PixelState> state;
  std::vector<PixelRandom> random;
  // The pattern window a pixel is matched on overlaps its neighbours', so
  // part of the axial noise is one field over the whole frame, drawn once.
  const double correlated_share = model.axial_correlated_share;
  const std::vector<float> shared_noise =
      correlated_share > 0.0 ? gaussianRandomField(scan.width, scan.height, model.axial_correlation_px, context.seed)
                             : std::vector<float>{};
  const double own_weight = std::sqrt(1.0 - correlated_share), shared_weight = std::sqrt(correlated_share);
  for (int row0 = 0; row0 < scan.height; row0 += kRowsPerBatch) {
    const int rows = std::min(kRowsPerBatch, scan.height - row0);
    const std::size_t count = static_cast<std::size_t>(rows) * static_cast<std::size_t>(scan.width);
    const std::size_t first = static_cast<std::size_t>(row0) * static_cast<std::size_t>(scan.width);
    auto pixelOf = [&](std::size_t k) {
      return std::pair<int, int>{static_cast<int>(k % static_cast<std::size_t>(scan.width)),
                                 row0 + static_cast<int>(k / static_cast<std::size_t>(scan.width))};
    };
    rays.resize(count);
    state.assign(count, PixelState{});
    random.clear();
    random.reserve(count);
    for (std::size_t k = 0; k < count; ++k) random.emplace_back(context.seed, first + k);

    // Pass 1: the ray through each pixel centre: ground truth and colour.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const auto [u, v] = pixelOf(k);
        rays[k] = camera.ray(pixelDirection(in, u, v));
        state[k].nominal = rays[k].direction.normalized();
      }
    });
    nominal_hits = context.scene.closestHits(rays);

    // Pass 2: where the camera actually samples: the pixel centre moved by
    // the lateral noise, which grows towards grazing incidence.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const auto [u, v] = pixelOf(k);
        const std::size_t pixel = first + k;
        const RayHit& hit = nominal_hits[k];
        double theta = 0.0;
        if (hit.hit) {
          theta = incidenceAngle(state[k].nominal, hit.face_normal);
          scan.true_range[pixel] = static_cast<float>(camera.toCamera(hit.point).z());
          scan.true_face[pixel] = hit.face;
          const Colour albedo = context.colour(hit.face, hit.point);
          const double shade = model.ambient_light + (1.0 - model.ambient_light) * std::cos(theta);
          for (int c = 0; c < 3; ++c)
            scan.colour[pixel][c] = static_cast<std::uint8_t>(std::lround(std::clamp(albedo[c] * shade, 0.0, 255.0)));
        }
        const double sigma = kinectLateralSigmaPx(model, theta);
        const double du = sigma * random[k].normal();
        const double dv = sigma * random[k].normal();
        rays[k] = camera.ray(pixelDirection(in, u + du, v + dv));
      }
    });
    sampled_hits = context.scene.closestHits(rays);

    // Pass 3: the depth of the sampled surface along the pixel's own ray,
    // then a ray from the projector to the sampled point.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const RayHit& hit = sampled_hits[k];
        rays[k] = Ray{};
        rays[k].t_max = -1.0;  // no shadow ray unless a surface was sampled
        if (!hit.hit) continue;
        PixelState& s = state[k];
        // Lateral noise decides which surface a pixel sees (edges come out
        // ragged); on that surface the depth is read along the pixel's own
        // ray, through the plane of the face sampled, so that the noise on
        // a surface's inside is the axial model's alone.
        const double cosine = hit.face_normal.dot(s.nominal);
        Eigen::Vector3d point = hit.point;
        if (std::abs(cosine) > 1e-9) {
          const double t = hit.face_normal.dot(hit.point - camera.origin) / cosine;
          const Eigen::Vector3d on_plane = camera.origin + t * s.nominal;
          // A plane met far from the sampled point (near-parallel ray,
          // small face) is no estimate of that surface's depth.
          if (t > 0.0 && (on_plane - hit.point).norm() <= 0.05 * hit.distance) point = on_plane;
        }
        s.depth = camera.toCamera(point).z();
        s.incidence = incidenceAngle(s.nominal, hit.face_normal);
        s.candidate = s.depth > 0.0;
        const Eigen::Vector3d to_point = hit.point - projector;
        const double distance = to_point.norm();
        rays[k].origin = projector;
        rays[k].direction = to_point;
        rays[k].t_max = distance - kShadowTolerance;
      }
    });
    shadow_hits = context.scene.closestHits(rays);

    // Pass 4: the measured depth: noise added to the disparity, which the
    // sensor reports in 1/8-pixel steps.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const std::size_t pixel = first + k;
        const PixelState& s = state[k];
        const RayHit& hit = sampled_hits[k];
        if (!hit.hit || shadow_hits[k].hit) continue;  // no surface, or no pattern on it
        // IR image: the projected pattern's brightness, Lambertian, falling
        // with the square of the distance from the projector (1 at 1 m).
        const Eigen::Vector3d from_projector = hit.point - projector;
        const double d2 = std::max(from_projector.squaredNorm(), 1e-12);
        const double lit = std::abs(hit.face_normal.dot(from_projector)) / std::sqrt(d2);
        scan.intensity[pixel] = toByte(context.reflectivity(hit.face, hit.point) * lit / d2);
        if (!s.candidate || s.incidence > model.grazing_angle) continue;

        // Nguyen et al.'s sigma was measured on the sensor's quantised
        // output; the noise added before quantising is the part of it the
        // steps (uniform rounding error, variance step^2 / 12) do not
        // already account for.
        const double z = s.depth;
        const double sigma = kinectAxialSigma(model, z, s.incidence);
        const double step = kinectDepthStep(model, z);
        const double sigma_before = std::sqrt(std::max(sigma * sigma - step * step / 12.0, 0.0));
        const double standard = shared_noise.empty()
                                    ? random[k].normal()
                                    : own_weight * random[k].normal() + shared_weight * shared_noise[pixel];
        const double disparity = fb / z + sigma_before * fb / (z * z) * standard;
        const double measured = kinectQuantisedDepth(model, disparity);
        if (!(measured >= model.min_range && measured <= model.max_range)) continue;
        scan.range[pixel] = static_cast<float>(measured);
        scan.confidence[pixel] = 255;
      }
    });
  }
}

}  // namespace icrkit::sim
