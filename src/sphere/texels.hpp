// Texel geometry and checks (bakeshop/sphere/texels.py): directions of rows or single texels,
// cosines to an axis, and the count of non-finite values of an environment. The directions are
// the maps' (maps.hpp), bit-identical to the old JIT kernels these replace.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::sphere {

// Texel i of flat row `row` (face row // h): a latlong as the separable products of
// latlong_directions (trig: latlong_trig, rows m long), the others as direction computes them.
inline Vec3 texel_direction(int kind, index_t h, index_t w, index_t row, index_t i,
                            const double* trig, index_t m) {
  if (kind == LATLONG) {
    const double st = trig[2 * m + row];
    return {st * trig[i], trig[3 * m + row], -st * trig[m + i]};
  }
  const index_t f = py_div(row, h);
  return direction(kind, h, w, static_cast<double>(f), static_cast<double>(i) + 0.5,
                   static_cast<double>(row - f * h) + 0.5);
}

// Directions ((r1 - r0) w, 3) of flat rows r0..r1 (faces stacked).
inline void row_directions(int kind, index_t h, index_t w, index_t r0, index_t r1,
                           const double* trig, index_t m, double* out) {
#pragma omp parallel
  {
    std::vector<double> buf(static_cast<size_t>(3 * w));
#pragma omp for schedule(static)
    for (index_t r = 0; r < r1 - r0; ++r) {
      double* row = out + 3 * r * w;
      if (is_cubic(kind)) {
        const index_t f = py_div(r0 + r, h);
        face_row(kind, w, f, r0 + r - f * h, w, buf.data(), buf.data() + w, buf.data() + 2 * w);
        for (index_t i = 0; i < w; ++i) {
          row[3 * i] = buf[i];
          row[3 * i + 1] = buf[w + i];
          row[3 * i + 2] = buf[2 * w + i];
        }
        continue;
      }
      for (index_t i = 0; i < w; ++i) {
        const Vec3 d = texel_direction(kind, h, w, r0 + r, i, trig, m);
        row[3 * i] = d.x;
        row[3 * i + 1] = d.y;
        row[3 * i + 2] = d.z;
      }
    }
  }
}

// Directions (count, 3) of the flat texels index (each < rows * w: checked).
inline void index_directions(int kind, index_t h, index_t w, index_t rows, const int64_t* index,
                             index_t count, const double* trig, index_t m, double* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    if (index[p] < 0 || index[p] >= rows * w) {
      errors.fail("texel indices outside the layout's image");
      continue;
    }
    const index_t row = index[p] / w;
    const index_t i = index[p] - row * w;
    const Vec3 d = texel_direction(kind, h, w, row, i, trig, m);
    out[3 * p] = d.x;
    out[3 * p + 1] = d.y;
    out[3 * p + 2] = d.z;
  }
  errors.check();
}

// out (faces h w): d . up of each texel centre's direction d; NaN where invalid.
inline void texel_cosines(int kind, index_t faces, index_t h, index_t w, const double* up,
                          double* out) {
#pragma omp parallel for schedule(static)
  for (index_t row = 0; row < faces * h; ++row) {
    const index_t f = row / h, j = row % h;
    for (index_t i = 0; i < w; ++i) {
      if (valid(kind, h, w, static_cast<double>(f), i, j)) {
        const Vec3 d = direction(kind, h, w, static_cast<double>(f),
                                 static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5);
        out[row * w + i] = d.x * up[0] + d.y * up[1] + d.z * up[2];
      } else {
        out[row * w + i] = std::numeric_limits<double>::quiet_NaN();
      }
    }
  }
}

// (NaNs, infinities, flat index of the first non-finite value or -1) of flat (n,).
template <class T>
inline void count_nonfinite(const T* flat, index_t n, int64_t& nans, int64_t& infs,
                            int64_t& first) {
  constexpr index_t chunks = 64;
  int64_t chunk_nans[chunks] = {}, chunk_infs[chunks] = {}, firsts[chunks];
  for (index_t c = 0; c < chunks; ++c) firsts[c] = -1;
#pragma omp parallel for schedule(dynamic)
  for (index_t c = 0; c < chunks; ++c) {
    for (index_t k = c * n / chunks; k < (c + 1) * n / chunks; ++k) {
      const T v = flat[k];
      if (!std::isfinite(v)) {
        if (v != v) {
          chunk_nans[c] += 1;
        } else {
          chunk_infs[c] += 1;
        }
        if (firsts[c] < 0) firsts[c] = k;
      }
    }
  }
  nans = infs = 0;
  first = -1;
  for (index_t c = 0; c < chunks; ++c) {
    nans += chunk_nans[c];
    infs += chunk_infs[c];
    if (first < 0 && firsts[c] >= 0) first = firsts[c];
  }
}

}  // namespace bakeshop::sphere
