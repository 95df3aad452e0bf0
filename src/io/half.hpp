// float32 -> IEEE half planes for the OpenEXR writer (bakeshop/io/_half.py).
#pragma once

#include <algorithm>

#include "common/kernel.hpp"

namespace bakeshop::io {

// The half bits of the float32 whose bits are `x`: round to nearest even, finite overflow
// clamped to 0x7BFF, infinities kept, NaN -> the quiet NaN 0x7E00 with its sign.
inline uint16_t half_bits(uint32_t x) {
  const uint32_t sign = (x >> 16) & 0x8000u;
  const uint32_t a = x & 0x7FFFFFFFu;
  uint32_t h;
  if (a > 0x7F800000u) {
    h = 0x7E00u;
  } else if (a == 0x7F800000u) {
    h = 0x7C00u;
  } else if (a >= 0x38800000u) {
    h = (a - 0x38000000u + 0xFFFu + ((a >> 13) & 1u)) >> 13;
    h = std::min<uint32_t>(h, 0x7BFFu);
  } else {
    const int e = static_cast<int>(a >> 23);
    const uint32_t m = (a & 0x7FFFFFu) | (e > 0 ? 0x800000u : 0u);
    const int shift = std::min(126 - std::max(e, 1), 31);
    uint32_t q = m >> shift;
    const uint32_t rest = m - (q << shift);
    const uint32_t halfway = (1u << shift) >> 1;
    q += (rest > halfway || (rest == halfway && (q & 1u) == 1u)) ? 1u : 0u;
    h = q;
  }
  return static_cast<uint16_t>(sign | h);
}

// (H, W, C) float32 bits -> (C, H, W) half bits.
inline void half_planes(const uint32_t* bits, index_t height, index_t width, index_t channels,
                        uint16_t* out) {
#pragma omp parallel for schedule(static)
  for (index_t y = 0; y < height; ++y)
    for (index_t x = 0; x < width; ++x)
      for (index_t c = 0; c < channels; ++c)
        out[(c * height + y) * width + x] = half_bits(bits[(y * width + x) * channels + c]);
}

}  // namespace bakeshop::io
