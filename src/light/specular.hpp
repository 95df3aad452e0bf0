// The prefiltering kernels of bakeshop/light/specular.py: filtered importance sampling over the
// padded mip pyramid, and the exact lobe sums.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/kernel.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::light {

// The padded mip pyramid: levels concatenated in one flat float32 array, level k is
// (6, s_k + 2, s_k + 2, 4) at offsets[k].
struct Pyramid {
  const float* data;
  const int64_t* offsets;
  const int64_t* sizes;
  index_t levels;
};

// Whether every level lies inside the flat array (checked before a kernel reads it).
inline bool pyramid_valid(const Pyramid& p, index_t size) {
  for (index_t k = 0; k < p.levels; ++k) {
    const int64_t s = p.sizes[k];
    if (s < 1 || p.offsets[k] < 0 || p.offsets[k] + 6 * (s + 2) * (s + 2) * 4 > size) return false;
  }
  return p.levels > 0;
}

// int(v) clamped to [0, hi] (v >= 0 truncates as Python's int(); NaN gives 0).
inline index_t clamp_index(double v, index_t hi) {
  if (!(v > 0.0)) return 0;
  if (v >= static_cast<double>(hi)) return hi;
  return static_cast<index_t>(v);
}

// The bilinear RGBA value of pyramid `level` at face coordinates (sc, tc) into v[4].
inline void bilinear(const Pyramid& pyr, index_t level, index_t face, double sc, double tc,
                     double* v) {
  const index_t s = pyr.sizes[level];
  const index_t p = s + 2;
  const double sd = static_cast<double>(s);
  // continuous coordinate (sc + 1) / 2 * s, shifted by the one-texel padding, minus 0.5
  const double px = (sc + 1.0) * 0.5 * sd + 0.5;
  const double py = (tc + 1.0) * 0.5 * sd + 0.5;
  const index_t i0 = clamp_index(px, s);
  const index_t j0 = clamp_index(py, s);
  const double fx = std::min(std::max(px - static_cast<double>(i0), 0.0), 1.0);
  const double fy = std::min(std::max(py - static_cast<double>(j0), 0.0), 1.0);
  const float* t = pyr.data + pyr.offsets[level] + ((face * p + j0) * p + i0) * 4;
  const index_t r = p * 4;
  const double w00 = (1.0 - fx) * (1.0 - fy);
  const double w10 = fx * (1.0 - fy);
  const double w01 = (1.0 - fx) * fy;
  const double w11 = fx * fy;
  for (int c = 0; c < 4; ++c)
    v[c] = w00 * static_cast<double>(t[c]) + w10 * static_cast<double>(t[c + 4]) +
           w01 * static_cast<double>(t[r + c]) + w11 * static_cast<double>(t[r + c + 4]);
}

// out[p] = sum_k w_k L(l_k(p)) / sum_k w_k, each L read at its filtered-importance level.
// samples (K, 5): (lx, ly, lz, weight, log2 Omega_s) about +z; log2_fit: polynomial
// coefficients of log2(q) on [1, 3] (highest power first); dirs (n, 3), out (n, 4).
inline void filter(const double* dirs, index_t n, const double* samples, index_t count,
                   const Pyramid& pyr, double lod_bias, const double* log2_fit, index_t fit_size,
                   double* out) {
  const index_t top = pyr.levels - 1;
  const double s0 = static_cast<double>(pyr.sizes[0]);
  // log2 of a level-0 texel's solid angle at a face centre: (2 / s0)^2
  const double log_texel = 2.0 * std::log2(2.0 / s0);
  double total = 0.0;
  for (index_t k = 0; k < count; ++k) total += samples[5 * k + 3];
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    const double nx = dirs[3 * p], ny = dirs[3 * p + 1], nz = dirs[3 * p + 2];
    // Duff et al. 2017: a continuous orthonormal frame (t, b, n) except across n.z = 0
    const double sign = nz >= 0.0 ? 1.0 : -1.0;
    const double a = -1.0 / (sign + nz);
    const double b = nx * ny * a;
    const double tx = 1.0 + sign * nx * nx * a, ty = sign * b, tz = -sign * nx;
    const double bx = b, by = sign + ny * ny * a, bz = -ny;
    double acc[4] = {0.0, 0.0, 0.0, 0.0};
    for (index_t k = 0; k < count; ++k) {
      const double* smp = samples + 5 * k;
      const double lx = smp[0], ly = smp[1], lz = smp[2];
      const double x = lx * tx + ly * bx + lz * nx;
      const double y = lx * ty + ly * by + lz * ny;
      const double z = lx * tz + ly * bz + lz * nz;
      const sphere::Face f = sphere::cube_face(x, y, z);
      // the texel solid angle where l lands is (2 / s0)^2 / (1 + sc^2 + tc^2)^1.5
      const double q = 1.0 + f.sc * f.sc + f.tc * f.tc;
      double log2_q = log2_fit[0];
      for (index_t i = 1; i < fit_size; ++i) log2_q = log2_q * q + log2_fit[i];
      double lod = 0.5 * (smp[4] - log_texel) + 0.75 * log2_q;
      lod = std::min(std::max(lod + lod_bias, 0.0), static_cast<double>(top));
      const index_t lo = clamp_index(lod, top);
      const double fr = lod - static_cast<double>(lo);
      const double w = smp[3];
      double v[4], u[4];
      bilinear(pyr, lo, f.f, f.sc, f.tc, v);
      if (fr > 0.0 && lo < top) {
        bilinear(pyr, lo + 1, f.f, f.sc, f.tc, u);
        for (int c = 0; c < 4; ++c) v[c] += fr * (u[c] - v[c]);
      }
      for (int c = 0; c < 4; ++c) acc[c] += w * v[c];
    }
    for (int c = 0; c < 4; ++c) out[4 * p + c] = acc[c] / total;
  }
}

// acc[p] += sum_j w(n_p . l_j) Omega_j L_j and total[p] = sum_j w(n_p . l_j) Omega_j. The lobe
// w is GGX's D(h) (n.l) up to the constant alpha^2 / pi (param = alpha^2), or Phong's (n.l)^e
// (param = e), over n.l > cos_cut.
inline void lobe(const double* dirs, index_t n, const double* src_dirs, const double* src_omega,
                 const double* src_values, index_t m, index_t channels, bool ggx, double param,
                 double cos_cut, double* acc, double* total) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    const double nx = dirs[3 * p], ny = dirs[3 * p + 1], nz = dirs[3 * p + 2];
    double t = 0.0;
    double* a = acc + p * channels;
    for (index_t j = 0; j < m; ++j) {
      const double nl = nx * src_dirs[3 * j] + ny * src_dirs[3 * j + 1] + nz * src_dirs[3 * j + 2];
      if (nl <= cos_cut) continue;
      double w;
      if (ggx) {
        // (n.h)^2 = (1 + n.l) / 2 for h = normalize(n + l)
        const double q = 0.5 * (1.0 + nl) * (param - 1.0) + 1.0;
        w = nl / (q * q) * src_omega[j];
      } else {
        w = std::pow(nl, param) * src_omega[j];
      }
      t += w;
      for (index_t c = 0; c < channels; ++c) a[c] += w * src_values[j * channels + c];
    }
    total[p] = t;
  }
}

}  // namespace bakeshop::light
