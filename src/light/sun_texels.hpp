// The texel searches of bakeshop/light/sun_texels.py: the texels of a cap, and the brightest
// texel outside one. 64 chunks whatever the thread count, so the answers never depend on it.
#pragma once

#include <algorithm>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::light {

// Indices (ascending) of the texels with a solid angle within acos(cos_limit) of centre.
inline std::vector<int64_t> cap(const double* dirs, const double* omega, index_t n,
                                const double* centre, double cos_limit) {
  constexpr index_t chunks = 64;
  const index_t step = (n + chunks - 1) / chunks;
  auto inside = [&](index_t i) {
    const double cos = dirs[3 * i] * centre[0] + dirs[3 * i + 1] * centre[1] +
                       dirs[3 * i + 2] * centre[2];
    return cos > cos_limit && omega[i] > 0;
  };
  index_t counts[chunks + 1] = {0};
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    index_t m = 0;
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t i = c * step; i < stop; ++i) m += inside(i) ? 1 : 0;
    counts[c + 1] = m;
  }
  for (index_t c = 0; c < chunks; ++c) counts[c + 1] += counts[c];
  std::vector<int64_t> out(static_cast<size_t>(counts[chunks]));
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    index_t j = counts[c];
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t i = c * step; i < stop; ++i)
      if (inside(i)) out[static_cast<size_t>(j++)] = i;
  }
  return out;
}

// The luminance of texel i in the values' type (texel_luminance): values (n, channels) at
// element strides (row, col).
template <class T>
inline T texel_lum(const T* values, index_t row, index_t col, index_t channels, const T* weights,
                   index_t i) {
  const T* v = values + i * row;
  if (channels < 3) return v[0];
  return v[0] * weights[0] + v[col] * weights[1] + v[2 * col] * weights[2];
}

// The texel of largest luminance among those with a solid angle and at more than
// acos(cos_limit) from centre (cos_limit > 1: all of them, dirs unread); -1 if none is
// positive; the first on a tie.
template <class T>
int64_t brightest(const T* values, index_t row, index_t col, index_t channels, index_t n,
                  const T* weights, const double* omega, const double* dirs,
                  const double* centre, double cos_limit) {
  constexpr index_t chunks = 64;
  int64_t best[chunks];
  const index_t step = (n + chunks - 1) / chunks;
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    double top = 0.0;
    best[c] = -1;
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t i = c * step; i < stop; ++i) {
      const T lum = texel_lum(values, row, col, channels, weights, i);
      if (static_cast<double>(lum) > top && omega[i] > 0) {
        if (cos_limit > 1.0 || dirs[3 * i] * centre[0] + dirs[3 * i + 1] * centre[1] +
                                       dirs[3 * i + 2] * centre[2] <
                                   cos_limit) {
          top = static_cast<double>(lum);
          best[c] = i;
        }
      }
    }
  }
  int64_t k = -1;
  for (index_t c = 0; c < chunks; ++c)
    if (best[c] >= 0 && (k < 0 || texel_lum(values, row, col, channels, weights, best[c]) >
                                      texel_lum(values, row, col, channels, weights, k)))
      k = best[c];
  return k;
}

}  // namespace bakeshop::light
