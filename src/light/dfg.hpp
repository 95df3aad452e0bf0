// The split-sum environment BRDF (DFG) kernels of bakeshop/light/dfg.py, and the GGX half
// vector they share with bakeshop/light/specular.py.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::light {

struct Vec3 {
  double x, y, z;
};

// Half vector h (tangent frame, n = +z) distributed as D(h) (n.h) for GGX's alpha:
// cos^2(theta) = (1 - v) / (1 + (alpha^2 - 1) v), phi = 2 pi u (Walter et al. 2007).
inline Vec3 ggx_half_vector(double u, double v, double alpha) {
  const double pi = 3.141592653589793;
  const double a2 = alpha * alpha;
  const double cos2 = (1.0 - v) / (1.0 + (a2 - 1.0) * v);
  const double cos_t = std::sqrt(cos2);
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos2));
  const double phi = 2.0 * pi * u;
  return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

// x ** 5 as the old JIT unrolls a constant integer power: x * ((x * x) * (x * x)).
inline double pow5(double x) {
  const double x2 = x * x;
  return x * (x2 * x2);
}

// Smith visibility V = G / (4 n.l n.v) for GGX: Schlick's separable form (k = alpha / 2) or
// the height-correlated one (Heitz 2014).
inline double visibility(double n_dot_l, double n_dot_v, double alpha, bool schlick) {
  if (schlick) {
    const double k = 0.5 * alpha;
    const double g_v = n_dot_v / (n_dot_v * (1.0 - k) + k);
    const double g_l = n_dot_l / (n_dot_l * (1.0 - k) + k);
    return g_v * g_l / (4.0 * n_dot_l * n_dot_v);
  }
  const double a2 = alpha * alpha;
  const double lam_v = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
  const double lam_l = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
  return 0.5 / (lam_v + lam_l);
}

// The (A, B) sums of one n.v over the half vectors h (count, 3), divided by count.
inline void dfg_point(double n_dot_v, double alpha, const double* h, index_t count, bool schlick,
                      double* out) {
  const double nv = std::min(std::max(n_dot_v, 1e-6), 1.0);
  const double vx = std::sqrt(std::max(0.0, 1.0 - nv * nv));
  const double vz = nv;
  double a = 0.0, b = 0.0;
  for (index_t s = 0; s < count; ++s) {
    const double hx = h[3 * s], hz = h[3 * s + 2];
    const double v_dot_h = vx * hx + vz * hz;
    const double lz = 2.0 * v_dot_h * hz - vz;
    if (lz <= 0.0 || v_dot_h <= 0.0) continue;
    // pdf(l) = D(h) (n.h) / (4 v.h), so f (n.l) / pdf = V (n.l) 4 (v.h) / (n.h) * F.
    const double weight = visibility(lz, nv, alpha, schlick) * 4.0 * lz * v_dot_h / hz;
    const double fc = pow5(1.0 - v_dot_h);
    a += (1.0 - fc) * weight;
    b += fc * weight;
  }
  out[0] = a / static_cast<double>(count);
  out[1] = b / static_cast<double>(count);
}

// out[p] = (A, B) at n_dot_v[p], roughness[p], over the Hammersley points xi (count, 2).
inline void dfg_terms(const double* n_dot_v, const double* roughness, index_t n, const double* xi,
                      index_t count, bool schlick, double* out) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    const double alpha = roughness[p] * roughness[p];
    std::vector<double> h(static_cast<size_t>(3 * count));
    for (index_t s = 0; s < count; ++s) {
      const Vec3 v = ggx_half_vector(xi[2 * s], xi[2 * s + 1], alpha);
      h[3 * s] = v.x, h[3 * s + 1] = v.y, h[3 * s + 2] = v.z;
    }
    dfg_point(n_dot_v[p], alpha, h.data(), count, schlick, out + 2 * p);
  }
}

// dfg_terms on the grid roughness (rows) x n_dot_v (columns), out (rows * columns, 2): each
// row's half vectors are drawn once and reused along it.
inline void dfg_grid(const double* n_dot_v, index_t width, const double* roughness, index_t rows,
                     const double* xi, index_t count, bool schlick, double* out) {
#pragma omp parallel for schedule(dynamic)
  for (index_t row = 0; row < rows; ++row) {
    const double alpha = roughness[row] * roughness[row];
    std::vector<double> h(static_cast<size_t>(3 * count));
    for (index_t s = 0; s < count; ++s) {
      const Vec3 v = ggx_half_vector(xi[2 * s], xi[2 * s + 1], alpha);
      h[3 * s] = v.x, h[3 * s + 1] = v.y, h[3 * s + 2] = v.z;
    }
    for (index_t col = 0; col < width; ++col)
      dfg_point(n_dot_v[col], alpha, h.data(), count, schlick, out + 2 * (row * width + col));
  }
}

}  // namespace bakeshop::light
