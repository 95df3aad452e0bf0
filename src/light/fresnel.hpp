// The Fresnel reflectance kernels of bakeshop/light/fresnel.py.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::light {

// The exact unpolarised reflectance of fresnel_dielectric for one cosine (clipped to [0, 1]
// here; NaN stays NaN), relative index n.
inline double reflectance(double c, double n) {
  if (c != c) return c;  // NaN
  c = std::min(std::max(c, 0.0), 1.0);
  const double g2 = n * n - 1.0 + c * c;
  if (g2 <= 0.0) return 1.0;  // total internal reflection (only possible for n < 1)
  const double g = std::sqrt(g2);
  const double a = (g - c) / (g + c);
  const double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

inline void reflectance_array(const double* c, index_t size, double n, double* out) {
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < size; ++i) out[i] = reflectance(c[i], n);
}

// out = image * R(cos) where cos >= 0, 0 below the plane; alpha (channels from `colour` on)
// kept; a NaN cos: all 0. image and out are (P, channels), the product in float64.
template <class T>
void apply_reflectance(const double* cos, index_t size, double n, const T* image,
                       index_t channels, T* out, index_t colour) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < size; ++p) {
    const double c = cos[p];
    const double r = c >= 0.0 ? reflectance(c, n) : 0.0;
    const T* in = image + p * channels;
    T* o = out + p * channels;
    for (index_t k = 0; k < colour; ++k) o[k] = static_cast<T>(static_cast<double>(in[k]) * r);
    for (index_t k = colour; k < channels; ++k) o[k] = c == c ? in[k] : T(0);
  }
}

}  // namespace bakeshop::light
