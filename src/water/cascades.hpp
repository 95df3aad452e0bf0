// The periodic bilinear lookup of bakeshop/water/cascades.py (sample_periodic, sum_cascades):
// a GPU's REPEAT sampler at world points.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/kernel.hpp"

namespace bakeshop::water {

// Python's `int(t) % n` (floor) of an integral texel index t: in integers where it fits (the
// usual case), else exactly in double.
inline index_t wrap(double t, index_t n, double period) {
  if (std::fabs(t) < 0x1p62) {
    const index_t m = static_cast<index_t>(t) % n;
    return m < 0 ? m + n : m;
  }
  double m = std::fmod(t, period);
  if (m < 0) m += period;
  return static_cast<index_t>(m) % n;
}

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
    const index_t c0 = wrap(u0, n, period);
    const index_t r0 = wrap(v0, n, period);
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
