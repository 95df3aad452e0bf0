// The sRGB transfer curves and the 8-bit sRGB quantiser of bakeshop/image/display.py.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::image {

// IEC 61966-2-1 constants (display.py's SRGB_*).
constexpr double srgb_linear_limit = 0.0031308;
constexpr double srgb_slope = 12.92;
constexpr double srgb_offset = 0.055;
constexpr double srgb_gamma = 2.4;
constexpr double srgb_encoded_limit = 0.04045;

// The encoding of one value, odd-extended to negatives; NaN stays NaN.
inline double srgb_encode1(double x) {
  const double m = std::fabs(x);
  const double v = m <= srgb_linear_limit
                       ? srgb_slope * m
                       : (1.0 + srgb_offset) * std::pow(m, 1.0 / srgb_gamma) - srgb_offset;
  return x < 0 ? -v : v;
}

inline double srgb_decode1(double x) {
  const double m = std::fabs(x);
  const double v = m <= srgb_encoded_limit
                       ? m / srgb_slope
                       : std::pow((m + srgb_offset) / (1.0 + srgb_offset), srgb_gamma);
  return x < 0 ? -v : v;
}

// out[i] = curve(a[i]) in float64 arithmetic, `decode` picking the curve.
template <class T>
void srgb_apply(const T* a, index_t n, bool decode, T* out) {
  if (decode) {
#pragma omp parallel for schedule(static)
    for (index_t i = 0; i < n; ++i) out[i] = static_cast<T>(srgb_decode1(static_cast<double>(a[i])));
  } else {
#pragma omp parallel for schedule(static)
    for (index_t i = 0; i < n; ++i) out[i] = static_cast<T>(srgb_encode1(static_cast<double>(a[i])));
  }
}

// A uniform number in [0, 1) from a 64-bit key (SplitMix64's finaliser): counter-based, so the
// dither is the same whatever the number of threads.
inline double uniform01(uint64_t key) {
  uint64_t z = key + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z = z ^ (z >> 31);
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

// (N, channels) linear values -> 8-bit codes: the first `colour` channels sRGB-encoded (and
// dithered with triangular noise where 0 < x < 1 when `dither`), the others quantised as they
// are; NaN -> 0, clamped to [0, 1], rounded half to even.
template <class T>
void srgb8(const T* a, index_t n, index_t channels, index_t colour, bool dither, uint64_t seed,
           uint8_t* out) {
  const uint64_t base = seed << 34;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    for (index_t k = 0; k < channels; ++k) {
      double x = static_cast<double>(a[p * channels + k]);
      x = x != x ? 0.0 : std::min(std::max(x, 0.0), 1.0);
      double q = 255.0 * (k < colour ? srgb_encode1(x) : x);
      if (dither && k < colour && 0.0 < x && x < 1.0) {
        const uint64_t key = base + static_cast<uint64_t>(2 * (p * channels + k));
        q += uniform01(key) - uniform01(key + 1);
      }
      out[p * channels + k] = static_cast<uint8_t>(std::min(std::max(std::rint(q), 0.0), 255.0));
    }
  }
}

}  // namespace bakeshop::image
