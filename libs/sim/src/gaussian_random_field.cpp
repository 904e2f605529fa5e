#include "gaussian_random_field.hpp"

#include "scan_rendering.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace icrkit::sim {
namespace {

std::vector<double> gaussianKernel(double sigma_px) {
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_px)));
  std::vector<double> kernel(static_cast<std::size_t>(2 * radius + 1));
  for (int i = -radius; i <= radius; ++i)
    kernel[static_cast<std::size_t>(i + radius)] = std::exp(-0.5 * (i * i) / (sigma_px * sigma_px));
  return kernel;
}

// One 1-D pass along lines of `length` samples, `stride` apart, starting at
// `line_start(line)`: unit-variance input with independent lines stays unit
// variance (the taps that fall outside the image are left out of the norm).
template <class LineStart>
void blurLines(const std::vector<double>& in, std::vector<double>& out, int lines, int length, std::size_t stride,
               const std::vector<double>& kernel, LineStart line_start) {
  const int radius = static_cast<int>(kernel.size() / 2);
  tbb::parallel_for(0, lines, [&](int line) {
    const std::size_t start = line_start(line);
    for (int i = 0; i < length; ++i) {
      double sum = 0.0, norm = 0.0;
      for (int t = std::max(-radius, -i); t <= std::min(radius, length - 1 - i); ++t) {
        const double w = kernel[static_cast<std::size_t>(t + radius)];
        sum += w * in[start + static_cast<std::size_t>(i + t) * stride];
        norm += w * w;
      }
      out[start + static_cast<std::size_t>(i) * stride] = sum / std::sqrt(norm);
    }
  });
}

}  // namespace

std::vector<float> gaussianRandomField(int width, int height, double sigma_px, std::uint64_t seed) {
  const std::size_t w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  std::vector<double> white(w * h), rows(w * h), field(w * h);
  // A stream of its own: the per-pixel noise of the renderer uses
  // PixelRandom(seed, pixel) and must stay what it was.
  const std::uint64_t field_seed = mix64(seed ^ 0x6a09e667f3bcc909ULL);
  tbb::parallel_for(std::size_t{0}, w * h, [&](std::size_t p) { white[p] = PixelRandom(field_seed, p).normal(); });
  const std::vector<double> kernel = gaussianKernel(sigma_px);
  blurLines(white, rows, height, width, 1, kernel, [w](int row) { return static_cast<std::size_t>(row) * w; });
  blurLines(rows, field, width, height, w, kernel, [](int column) { return static_cast<std::size_t>(column); });
  return std::vector<float>(field.begin(), field.end());
}

}  // namespace icrkit::sim
