// The direct Gerstner sums of bakeshop/water/gerstner.py: eight sums per point over the waves,
// in the waves' order.
#pragma once

#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::water {

// out[i, 0:8] = (h, hx, hy, dx, dy, dxx, dyy, dxy) at point i; phase[j] = -w t + phi.
inline void gerstner_sums(const double* amp, const double* kx, const double* ky,
                          const double* phase, index_t waves, const double* x, const double* y,
                          index_t points, double* out) {
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < points; ++i) {
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;
    for (index_t j = 0; j < waves; ++j) {
      const double k = std::sqrt(kx[j] * kx[j] + ky[j] * ky[j]);
      const double th = kx[j] * x[i] + ky[j] * y[i] + phase[j];
      const double c = amp[j] * std::cos(th);
      const double s = amp[j] * std::sin(th);
      s0 += c;
      s1 -= kx[j] * s;
      s2 -= ky[j] * s;
      s3 -= kx[j] / k * s;
      s4 -= ky[j] / k * s;
      s5 -= kx[j] * kx[j] / k * c;
      s6 -= ky[j] * ky[j] / k * c;
      s7 -= kx[j] * ky[j] / k * c;
    }
    double* o = out + 8 * i;
    o[0] = s0, o[1] = s1, o[2] = s2, o[3] = s3, o[4] = s4, o[5] = s5, o[6] = s6, o[7] = s7;
  }
}

}  // namespace bakeshop::water
