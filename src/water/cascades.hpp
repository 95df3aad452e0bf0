// The periodic bilinear lookup of bakeshop/water/cascades.py (sample_periodic, sum_cascades):
// a GPU's REPEAT sampler at world points.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/kernel.hpp"

namespace bakeshop::water {

// out[i, :] += weight * bilinear sample of the periodic field (n, n, channels) at world
// (x[i], y[i]); row 0 at the top (y = size). A point that is not finite samples NaN.
inline void sample_add(const double* field, index_t n, index_t channels, double size,
                       const double* x, const double* y, index_t points, double weight,
                       double* out) {
  const double texel = size / static_cast<double>(n);
  const double period = static_cast<double>(n);
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < points; ++i) {
    const double u = x[i] / texel - 0.5;
    const double v = (size - y[i]) / texel - 0.5;
    if (!(std::isfinite(u) && std::isfinite(v))) {
      for (index_t ch = 0; ch < channels; ++ch) out[i * channels + ch] += NAN;
      continue;
    }
    const double u0 = std::floor(u);
    const double v0 = std::floor(v);
    const double fu = u - u0;
    const double fv = v - v0;
    // Python's % (floor) of the integral texel index, exact in double at any distance
    double cu = std::fmod(u0, period), rv = std::fmod(v0, period);
    if (cu < 0) cu += period;
    if (rv < 0) rv += period;
    const index_t c0 = static_cast<index_t>(cu) % n;
    const index_t r0 = static_cast<index_t>(rv) % n;
    const index_t c1 = (c0 + 1) % n;
    const index_t r1 = (r0 + 1) % n;
    const double* f00 = field + (r0 * n + c0) * channels;
    const double* f01 = field + (r0 * n + c1) * channels;
    const double* f10 = field + (r1 * n + c0) * channels;
    const double* f11 = field + (r1 * n + c1) * channels;
    for (index_t ch = 0; ch < channels; ++ch)
      out[i * channels + ch] += weight * ((1 - fv) * ((1 - fu) * f00[ch] + fu * f01[ch]) +
                                          fv * ((1 - fu) * f10[ch] + fu * f11[ch]));
  }
}

}  // namespace bakeshop::water
