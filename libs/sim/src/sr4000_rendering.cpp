/// \file
/// Renders an SR4000 frame: each pixel integrates the modulated light from
/// its whole footprint (a grid of sub-rays), so the phase it measures is that
/// of the sum of the returns' phasors; then the wiggling error and the
/// amplitude-dependent noise are added.

#include "lens_distortion.hpp"
#include "scan_rendering.hpp"
#include "sr4000_model.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace icrkit::sim {
namespace {
std::uint8_t toByte(double value) { return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 1.0) * 255.0)); }
}  // namespace

void renderSr4000(const RenderContext& context, SimulatedScan& scan) {
  const SensorModel& model = context.model;
  const CameraIntrinsics& in = model.intrinsics;
  const CameraFrame& camera = context.camera;
  const int side = model.mixed_pixel_samples;
  const std::size_t per_pixel = static_cast<std::size_t>(side * side);
  const std::size_t centre = (per_pixel - 1) / 2;  // the sub-ray through the pixel centre (side is odd)
  const double radians_per_metre = sr4000Phase(model, 1.0);

  std::vector<Ray> rays;
  std::vector<RayHit> hits;
  for (int row0 = 0; row0 < scan.height; row0 += kRowsPerBatch) {
    const int rows = std::min(kRowsPerBatch, scan.height - row0);
    const std::size_t count = static_cast<std::size_t>(rows) * static_cast<std::size_t>(scan.width);
    const std::size_t first = static_cast<std::size_t>(row0) * static_cast<std::size_t>(scan.width);
    rays.resize(count * per_pixel);

    // Sub-rays on a regular grid over the pixel (stratified, no jitter: a
    // random pattern would add noise that the real pixel, which integrates
    // continuously, does not have).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const double u = static_cast<double>(k % static_cast<std::size_t>(scan.width));
        const double v = static_cast<double>(row0) + static_cast<double>(k / static_cast<std::size_t>(scan.width));
        for (int j = 0; j < side; ++j)
          for (int i = 0; i < side; ++i) {
            const double du = (i - (side - 1) / 2) / static_cast<double>(side);
            const double dv = (j - (side - 1) / 2) / static_cast<double>(side);
            rays[k * per_pixel + static_cast<std::size_t>(j * side + i)] = camera.ray(pixelDirection(in, u + du, v + dv));
          }
      }
    });
    hits = context.scene.closestHits(rays);

    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const std::size_t pixel = first + k;
        const RayHit* sub = &hits[k * per_pixel];
        const Ray* sub_rays = &rays[k * per_pixel];
        if (sub[centre].hit) {
          scan.true_range[pixel] = static_cast<float>(sub[centre].distance);
          scan.true_face[pixel] = sub[centre].face;
        }
        // Phases are taken relative to one sub-ray's so that the sum does
        // not wrap around where ranges straddle a multiple of c / 2f.
        std::size_t reference = per_pixel;
        if (sub[centre].hit) reference = centre;
        for (std::size_t s = 0; s < per_pixel && reference == per_pixel; ++s)
          if (sub[s].hit) reference = s;
        if (reference == per_pixel) continue;  // nothing returns any light
        const double reference_range = sub[reference].distance;
        double re = 0.0, im = 0.0, total = 0.0;
        for (std::size_t s = 0; s < per_pixel; ++s) {
          if (!sub[s].hit) continue;
          const Eigen::Vector3d direction = sub_rays[s].direction.normalized();
          const double theta = incidenceAngle(direction, sub[s].face_normal);
          const double amplitude = sr4000Amplitude(model, context.reflectivity(sub[s].face, sub[s].point), theta,
                                                   sub[s].distance);
          const double phase = radians_per_metre * (sub[s].distance - reference_range);
          re += amplitude * std::cos(phase);
          im += amplitude * std::sin(phase);
          total += amplitude;
        }
        const double amplitude = std::hypot(re, im) / static_cast<double>(per_pixel);
        scan.intensity[pixel] = toByte(amplitude / model.amplitude_full_scale);
        if (!(amplitude >= model.min_amplitude) || amplitude <= 0.0) continue;
        if (sub[centre].hit &&
            incidenceAngle(sub_rays[centre].direction.normalized(), sub[centre].face_normal) > model.grazing_angle)
          continue;

        const double mixed = reference_range + std::atan2(im, re) / radians_per_metre;
        PixelRandom random(context.seed, pixel);
        const double measured =
            mixed + sr4000Wiggling(model, mixed) + sr4000RangeSigma(model, amplitude) * random.normal();
        if (!(measured >= model.min_range && measured <= model.max_range)) continue;
        scan.range[pixel] = static_cast<float>(measured);
        // Coherence |sum of phasors| / sum of amplitudes is 1 on a single
        // surface and drops where the pixel mixes ranges.
        const double coherence = total > 0.0 ? amplitude * static_cast<double>(per_pixel) / total : 0.0;
        scan.confidence[pixel] = toByte(coherence * std::min(amplitude, 1.0));
      }
    });
  }
}

}  // namespace icrkit::sim
