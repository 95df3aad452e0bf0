// The mip-chain samplers of bakeshop/normals/tiling.py (bilinear with wrap or clamp, trilinear
// between two levels) and the kernels that place a tileable detail map with them.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "common/kernel.hpp"

namespace bakeshop::normals {

// Python's max(a, b) and min(a, b) on floats: the first argument unless the second is
// strictly greater (smaller), so a NaN first argument is kept.
inline double py_max(double a, double b) { return b > a ? b : a; }
inline double py_min(double a, double b) { return b < a ? b : a; }

// int(math.floor(x)) as the old JIT computes it: out of the int64 range (and NaN) it is INT64_MIN,
// the x86 conversion's "integer indefinite", without C++'s undefined behaviour.
inline int64_t floor_int(double x) {
  const double f = std::floor(x);
  if (!(f >= -9223372036854775808.0 && f < 9223372036854775808.0))
    return std::numeric_limits<int64_t>::min();
  return static_cast<int64_t>(f);
}
inline int64_t ceil_int(double x) {
  const double f = std::ceil(x);
  if (!(f >= -9223372036854775808.0 && f < 9223372036854775808.0))
    return std::numeric_limits<int64_t>::min();
  return static_cast<int64_t>(f);
}

// Python's a % b for b > 0 (the result has b's sign).
inline int64_t floor_mod(int64_t a, int64_t b) {
  const int64_t r = a % b;
  return r < 0 ? r + b : r;
}

// A packed mip chain (tiling.MipChain): texels (T, channels) float32, level l's first texel at
// offsets[l], its (height, width) at shapes[2 l], shapes[2 l + 1].
struct Chain {
  const float* texels;
  index_t channels;
  const int64_t* offsets;
  const int64_t* shapes;
  index_t levels;
};

// Whether every level of `chain` lies within its `count` texels.
inline bool chain_ok(const Chain& c, index_t count) {
  if (c.levels < 1 || c.channels < 1) return false;
  for (index_t l = 0; l < c.levels; ++l) {
    const int64_t h = c.shapes[2 * l], w = c.shapes[2 * l + 1], o = c.offsets[l];
    if (h < 1 || w < 1 || o < 0 || h > (int64_t{1} << 31) || w > (int64_t{1} << 31)) return false;
    if (o > count || h * w > count - o) return false;
  }
  return true;
}

// out += weight * the bilinear sample at texel coordinates (x, y) of the (h, w) level whose first
// texel is texels[base]; each of the two sums is rounded to T as the old JIT's `out[k] +=` did.
template <class T>
inline void bilinear_add(const Chain& c, int64_t base, int64_t h, int64_t w, double x, double y,
                         bool wrap, double weight, T* out) {
  x -= 0.5;
  y -= 0.5;
  const int64_t x0 = floor_int(x), y0 = floor_int(y);
  const double fx = x - static_cast<double>(x0);
  const double fy = y - static_cast<double>(y0);
  int64_t i0, i1, j0, j1;
  if (wrap) {
    i0 = floor_mod(x0, w);
    i1 = (i0 + 1) % w;
    j0 = floor_mod(y0, h);
    j1 = (j0 + 1) % h;
  } else {
    auto clamp = [](int64_t v, int64_t hi) { return v < 0 ? 0 : (v > hi ? hi : v); };
    i0 = clamp(x0, w - 1);
    i1 = clamp(x0 + 1, w - 1);  // floor_int never gives INT64_MAX
    j0 = clamp(y0, h - 1);
    j1 = clamp(y0 + 1, h - 1);
  }
  const double w00 = (1 - fx) * (1 - fy) * weight;
  const double w10 = fx * (1 - fy) * weight;
  const double w01 = (1 - fx) * fy * weight;
  const double w11 = fx * fy * weight;
  const index_t n = c.channels;
  const float* r0 = c.texels + (base + j0 * w) * n;
  const float* r1 = c.texels + (base + j1 * w) * n;
  for (index_t k = 0; k < n; ++k) {
    out[k] = static_cast<T>(static_cast<double>(out[k]) +
                            (w00 * static_cast<double>(r0[i0 * n + k]) +
                             w10 * static_cast<double>(r0[i1 * n + k])));
    out[k] = static_cast<T>(static_cast<double>(out[k]) +
                            (w01 * static_cast<double>(r1[i0 * n + k]) +
                             w11 * static_cast<double>(r1[i1 * n + k])));
  }
}

// out += the trilinear sample of the chain at level-0 texel coordinates (x, y) and lod (log2 of
// the footprint in level-0 texels): the two nearest levels blended.
template <class T>
inline void trilinear_add(const Chain& c, double x, double y, double lod, bool wrap, T* out) {
  const index_t n = c.levels;
  lod = py_min(py_max(lod, 0.0), static_cast<double>(n) - 1.0);
  const int64_t lo = floor_int(lod);
  const double t = lod - static_cast<double>(lo);
  const double h0 = static_cast<double>(c.shapes[0]), w0 = static_cast<double>(c.shapes[1]);
  for (int k = 0; k < 2; ++k) {
    const int64_t lv = lo + k;
    const double weight = k == 0 ? 1.0 - t : t;
    if (weight <= 0.0 || lv >= n || lv < 0) continue;
    const int64_t h = c.shapes[2 * lv], w = c.shapes[2 * lv + 1];
    bilinear_add(c, c.offsets[lv], h, w, x * static_cast<double>(w) / w0,
                 y * static_cast<double>(h) / h0, wrap, weight, out);
  }
}

// out[p] = the trilinear sample at (xs[p], ys[p]) and lods[p]; out is (N, channels) float32.
inline void sample_points(const Chain& c, const double* xs, const double* ys, const double* lods,
                          index_t n, bool wrap, float* out) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    float* o = out + p * c.channels;
    for (index_t k = 0; k < c.channels; ++k) o[k] = 0.0f;
    trilinear_add(c, xs[p], ys[p], lods[p], wrap, o);
  }
}

// Samples of a 3-channel chain along an affine map (3 x 3, row-major) of output texel centres to
// level-0 texels, XY rotated by (cos_r, sin_r) and mirrored by the signs, renormalised; out is
// (height, width, 3) float32.
inline void place(const Chain& c, double lod, const double* affine, double cos_r, double sin_r,
                  double sign_x, double sign_y, index_t height, index_t width, float* out) {
#pragma omp parallel for schedule(static)
  for (index_t j = 0; j < height; ++j) {
    double a[3];
    for (index_t i = 0; i < width; ++i) {
      a[0] = 0.0;
      a[1] = 0.0;
      a[2] = 0.0;
      const double ci = static_cast<double>(i) + 0.5, cj = static_cast<double>(j) + 0.5;
      const double x = affine[0] * ci + affine[1] * cj + affine[2];
      const double y = affine[3] * ci + affine[4] * cj + affine[5];
      trilinear_add(c, x, y, lod, true, a);
      const double nx = (cos_r * a[0] - sin_r * a[1]) * sign_x;
      const double ny = (sin_r * a[0] + cos_r * a[1]) * sign_y;
      const double nz = a[2];
      const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
      float* o = out + (j * width + i) * 3;
      if (length > 0 && std::isfinite(length)) {
        o[0] = static_cast<float>(nx / length);
        o[1] = static_cast<float>(ny / length);
        o[2] = static_cast<float>(nz / length);
      } else {
        o[0] = 0.0f;
        o[1] = 0.0f;
        o[2] = 1.0f;
      }
    }
  }
}

}  // namespace bakeshop::normals
