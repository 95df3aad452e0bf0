// The blend methods' formulas of bakeshop/normals/blend.py as one fused loop over the texels:
// read both normals, scale the detail's height, blend in float64, renormalise, write.
#pragma once

#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::normals {

constexpr double blend_tiny = 1e-30;

inline double overlay1(double a, double b) {
  a = (a + 1) * 0.5;
  b = (b + 1) * 0.5;
  const double r = a < 0.5 ? 2 * a * b : 1 - 2 * (1 - a) * (1 - b);
  return r * 2 - 1;
}

// The method's formula (its index in blend.METHODS) on macro (x1, y1, z1) and detail (x2, y2,
// z2), unnormalised.
inline void blend_formula(int method, double x1, double y1, double z1, double x2, double y2,
                          double z2, double& x, double& y, double& z) {
  switch (method) {
    case 0: {  // exact
      const double k = z2 - x2 * x1 - y2 * y1;
      x = k * x1 + x2, y = k * y1 + y2, z = k * z1;
      return;
    }
    case 1: {  // rnm; n1 = (0, 0, -1) has no rotation
      const double up = z1 + 1;
      const double tz = 1e-12 > up ? 1e-12 : up;  // Python's max(up, 1e-12): NaN stays
      const double k = (-x1 * x2 - y1 * y2 + tz * z2) / tz;
      x = x1 * k + x2, y = y1 * k + y2, z = tz * k - z2;
      return;
    }
    case 2: {  // sg: Mikkelsen's surface gradients of both, resolved against the vertex frame
      const double k1 = std::fabs(z1) > blend_tiny ? z1 : blend_tiny;
      const double k2 = std::fabs(z2) > blend_tiny ? z2 : blend_tiny;
      x = x1 / k1 + x2 / k2, y = y1 / k1 + y2 / k2, z = 1.0;
      return;
    }
    case 3:  // pd
      x = x1 * z2 + x2 * z1, y = y1 * z2 + y2 * z1, z = z1 * z2;
      return;
    case 4:  // whiteout
      x = x1 + x2, y = y1 + y2, z = z1 * z2;
      return;
    case 5:  // udn
      x = x1 + x2, y = y1 + y2, z = z1;
      return;
    case 6:  // overlay on packed R and G, multiply on packed B
      x = overlay1(x1, x2), y = overlay1(y1, y2), z = (z1 + 1) * (z2 + 1) * 0.5 - 1;
      return;
    default:  // linear
      x = x1 + x2, y = y1 + y2, z = z1 + z2 - 1;
  }
}

// out[i] = normalize(formula(m[i], normalize(s x, s y, z of d[i]))), (0, 0, 1) where the
// result has no direction; strength is one value (`per_texel` false) or one per texel.
template <class M, class D, class S, class O>
void blend_texels(int method, const M* m, const D* d, const S* strength, bool per_texel,
                  index_t n, O* out) {
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < n; ++i) {
    const double s = static_cast<double>(per_texel ? strength[i] : strength[0]);
    double x2 = s * static_cast<double>(d[3 * i]);
    double y2 = s * static_cast<double>(d[3 * i + 1]);
    double z2 = static_cast<double>(d[3 * i + 2]);
    double length = std::sqrt(x2 * x2 + y2 * y2 + z2 * z2);
    if (length > 0) {
      x2 /= length;
      y2 /= length;
      z2 /= length;
    }
    double x, y, z;
    blend_formula(method, static_cast<double>(m[3 * i]), static_cast<double>(m[3 * i + 1]),
                  static_cast<double>(m[3 * i + 2]), x2, y2, z2, x, y, z);
    length = std::sqrt(x * x + y * y + z * z);
    if (length > 0 && std::isfinite(length)) {
      out[3 * i] = static_cast<O>(x / length);
      out[3 * i + 1] = static_cast<O>(y / length);
      out[3 * i + 2] = static_cast<O>(z / length);
    } else {
      out[3 * i] = 0;
      out[3 * i + 1] = 0;
      out[3 * i + 2] = 1;
    }
  }
}

}  // namespace bakeshop::normals
