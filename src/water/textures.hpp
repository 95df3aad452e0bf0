// The preview shading of bakeshop/water/textures.py (shade): a normal map seen obliquely,
// fresnel-weighted sky, a sun's glint. Float32 dot products as the old JIT typed them, the rest in
// double; powers by squaring as the old JIT unrolls `x ** 5` and `x ** 600`.
#pragma once

#include <algorithm>

#include "common/kernel.hpp"

namespace bakeshop::water {

// x ** n for a constant integer n >= 0, by the old JIT's square-and-multiply.
inline double powi(double x, unsigned n) {
  double r = 1.0;
  while (n != 0) {
    if (n & 1u) r *= x;
    n >>= 1;
    x *= x;
  }
  return r;
}

inline void shade(const float* normals, index_t h, index_t w, const float* view, const float* sun,
                  float* out) {
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < h; ++r) {
    for (index_t c = 0; c < w; ++c) {
      const index_t i = (r * w + c) * 3;
      const float nx = normals[i], ny = normals[i + 1], nz = normals[i + 2];
      const float dot_v = nx * view[0] + ny * view[1] + nz * view[2];
      const double cos_v = std::max(static_cast<double>(dot_v), 0.0);
      // mirror direction m = 2 (n.v) n - v and Schlick's fresnel for water (R0 = 0.02)
      const double mx = 2.0 * cos_v * nx - view[0];
      const double my = 2.0 * cos_v * ny - view[1];
      const double mz = 2.0 * cos_v * nz - view[2];
      const double f = 0.02 + 0.98 * powi(1.0 - cos_v, 5);
      const double e = std::min(std::max(mz, 0.0), 1.0);  // deep blue overhead, pale low
      const double sky_r = 0.75 - 0.60 * e;
      const double sky_g = 0.85 - 0.55 * e;
      const double sky_b = 0.95 - 0.35 * e;
      const double glint = powi(std::max(mx * sun[0] + my * sun[1] + mz * sun[2], 0.0), 600) * 30.0;
      out[i] = static_cast<float>(0.003 + (1.0 - f) * 0.010 + f * (sky_r + glint));
      out[i + 1] = static_cast<float>(0.015 + (1.0 - f) * 0.035 + f * (sky_g + glint));
      out[i + 2] = static_cast<float>(0.030 + (1.0 - f) * 0.060 + f * (sky_b + glint));
    }
  }
}

}  // namespace bakeshop::water
