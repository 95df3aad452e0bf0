// The half-float surface ISPC's BC6H encoder reads (bakeshop/io/compress/encode.py's
// to_half_surface): float32 texels -> RGBA binary16 in one pass.
#pragma once

#include <cstdint>
#include <cstring>

#include "common/kernel.hpp"

namespace bakeshop::io::compress {

// IEEE binary16 bits of a float32 given by its bits, rounded to nearest even; beyond +-65504
// (and infinity) saturated to +-65504, never infinity (NaN is refused before).
//
// The rounding is Giesen's "float_to_half_fast3_rtne": normal halves add the rounding bias
// 0xFFF + odd before dropping 13 mantissa bits; subnormal halves add 0.5f, whose float addition
// rounds the 10 kept bits to nearest even.
inline uint16_t half_bits_saturating(uint32_t bits) {
  const uint32_t sign = bits & 0x80000000u;
  const uint32_t u = bits ^ sign;
  uint32_t half;
  if (u >= 0x47800000u) {  // 2^16 and up: beyond every half
    half = 0x7BFFu;
  } else if (u < 0x38800000u) {  // below 2^-14: a subnormal half or zero
    float value;
    std::memcpy(&value, &u, sizeof value);
    value += 0.5f;
    uint32_t rounded;
    std::memcpy(&rounded, &value, sizeof rounded);
    half = rounded - 0x3F000000u;
  } else {
    half = (u - (112u << 23) + 0xFFFu + ((u >> 13) & 1u)) >> 13;
    if (half >= 0x7C00u) half = 0x7BFFu;  // rounded up past 65504
  }
  return static_cast<uint16_t>(half | (sign >> 16));
}

// out[:h, :w] (rows of `out_width` RGBA uint16 texels) = the half floats of `bits`, (h, w, c)
// float32 bits with c in 1..4: grey repeated to RGB, missing blue 0, missing alpha 1 (0x3C00).
inline void half_rgba(const uint32_t* bits, index_t height, index_t width, index_t channels,
                      uint16_t* out, index_t out_width) {
#pragma omp parallel for schedule(static)
  for (index_t y = 0; y < height; ++y) {
    const uint32_t* row = bits + y * width * channels;
    uint16_t* texel = out + y * out_width * 4;
    for (index_t x = 0; x < width; ++x, row += channels, texel += 4) {
      for (index_t k = 0; k < 3; ++k) {
        if (channels == 1)
          texel[k] = half_bits_saturating(row[0]);
        else if (k < channels)
          texel[k] = half_bits_saturating(row[k]);
        else
          texel[k] = 0;
      }
      texel[3] = channels == 4 ? half_bits_saturating(row[3]) : uint16_t{0x3C00};
    }
  }
}

}  // namespace bakeshop::io::compress
