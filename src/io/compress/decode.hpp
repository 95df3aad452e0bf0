// The block decoders of bakeshop/io/compress/decode.py: BC7 and BC6H (BPTC) to their integer
// texels, BC1, BC3, BC4 and BC5 (S3TC, RGTC) to float32, one block per loop iteration, blocks
// in parallel. The tables are decode.py's (from _bptc.py), checked by the bindings.
#pragma once

#include <algorithm>
#include <cstdint>

#include "common/kernel.hpp"
#include "io/compress/bptc.hpp"

namespace bakeshop::io::compress {

// The BPTC tables, in the layouts of decode.py's arrays (row-major).
struct BptcTables {
  const int64_t* bc7_modes = nullptr;  // (8, 10): NS, PB, RB, ISB, CB, AB, EPB, SPB, IB, IB2
  const int64_t* weights = nullptr;    // (5, 16): the weights of 2-, 3- and 4-bit indices
  const uint8_t* p2 = nullptr;         // (64, 16): subset of each texel, two subsets
  const uint8_t* p3 = nullptr;         // (64, 16): three subsets
  const uint8_t* a2 = nullptr;         // (64,): anchor of subset 1, two subsets
  const uint8_t* a31 = nullptr;        // (64,): anchors of subsets 1 and 2, three subsets
  const uint8_t* a32 = nullptr;
  const int64_t* bc6h_modes = nullptr;   // (32, 7): valid, transformed, PB, EPB, delta R G B
  const int8_t* bc6h_layout = nullptr;   // (32, 82, 2): (field, bit) of each block bit
};

// BC7 blocks (n, 16) -> RGBA texels (n, 16, 4) float32: the spec's 8-bit values divided by 255
// in float32 (as numpy's uint8 -> float32 / 255).
inline void decode_bc7(const uint8_t* blocks, index_t n, float* out, const BptcTables& t) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t b = 0; b < n; ++b) {
    const uint8_t* block = blocks + 16 * b;
    float* texels = out + 64 * b;
    const int first = block[0];
    if (first == 0) {  // reserved: every channel 0
      std::fill(texels, texels + 64, 0.0f);
      continue;
    }
    int mode = 0;
    while (!((first >> mode) & 1)) ++mode;
    const int64_t* m = t.bc7_modes + 10 * mode;
    const int ns = static_cast<int>(m[0]), pb = static_cast<int>(m[1]),
              rb = static_cast<int>(m[2]), isb = static_cast<int>(m[3]),
              cb = static_cast<int>(m[4]), ab = static_cast<int>(m[5]),
              epb = static_cast<int>(m[6]), spb = static_cast<int>(m[7]),
              ib = static_cast<int>(m[8]), ib2 = static_cast<int>(m[9]);
    const Block128 bits(block);
    int position = mode + 1;
    const int64_t part = bits.bits(position, pb);
    position += pb;
    if (part >= 64) {  // the tables hold 64 partitions
      errors.fail("BC7 block with partition " + std::to_string(part));
      continue;
    }
    const int64_t rotation = bits.bits(position, rb);
    position += rb;
    const int64_t selector = bits.bits(position, isb);
    position += isb;
    int64_t endpoints[6][4] = {};
    for (int c = 0; c < 3; ++c)
      for (int e = 0; e < 2 * ns; ++e) {
        endpoints[e][c] = bits.bits(position, cb);
        position += cb;
      }
    if (ab)
      for (int e = 0; e < 2 * ns; ++e) {
        endpoints[e][3] = bits.bits(position, ab);
        position += ab;
      }
    int color_bits = cb, alpha_bits = ab;
    if (epb || spb) {
      for (int e = 0; e < 2 * ns; ++e) {
        const int64_t p = bits.bits(epb ? position + e : position + e / 2, 1);
        for (int c = 0; c < 4; ++c) endpoints[e][c] = endpoints[e][c] << 1 | p;
      }
      position += epb ? 2 * ns : ns;
      color_bits += 1;
      if (ab) alpha_bits += 1;
    }
    for (int e = 0; e < 2 * ns; ++e)
      for (int c = 0; c < 4; ++c) {
        const int bits_n = c < 3 ? color_bits : alpha_bits;
        if (bits_n == 0) {
          endpoints[e][c] = 255;
        } else {
          const int64_t v = endpoints[e][c] << (8 - bits_n);
          endpoints[e][c] = v | (v >> bits_n);
        }
      }
    int subset[16] = {};
    if (ns == 2)
      for (int i = 0; i < 16; ++i) subset[i] = t.p2[16 * part + i];
    else if (ns == 3)
      for (int i = 0; i < 16; ++i) subset[i] = t.p3[16 * part + i];
    int64_t primary[16] = {}, secondary[16] = {};
    for (int i = 0; i < 16; ++i) {
      bool anchor = i == 0;
      if (ns == 2)
        anchor = anchor || i == t.a2[part];
      else if (ns == 3)
        anchor = anchor || i == t.a31[part] || i == t.a32[part];
      const int count = anchor ? ib - 1 : ib;
      primary[i] = bits.bits(position, count);
      position += count;
    }
    if (ib2)
      for (int i = 0; i < 16; ++i) {
        const int count = i == 0 ? ib2 - 1 : ib2;
        secondary[i] = bits.bits(position, count);
        position += count;
      }
    for (int i = 0; i < 16; ++i) {
      const int e0 = 2 * subset[i];
      int64_t wc, wa;
      if (ib2 && selector) {
        wc = t.weights[16 * ib2 + secondary[i]];
        wa = t.weights[16 * ib + primary[i]];
      } else if (ib2) {
        wc = t.weights[16 * ib + primary[i]];
        wa = t.weights[16 * ib2 + secondary[i]];
      } else {
        wc = wa = t.weights[16 * ib + primary[i]];
      }
      int64_t texel[4];
      for (int c = 0; c < 4; ++c)
        texel[c] = interpolate(endpoints[e0][c], endpoints[e0 + 1][c], c < 3 ? wc : wa);
      if (rotation) std::swap(texel[rotation - 1], texel[3]);
      for (int c = 0; c < 4; ++c) texels[4 * i + c] = static_cast<float>(texel[c]) / 255.0f;
    }
  }
  errors.check();
}

// BC6H blocks (n, 16) -> half-float bit patterns (n, 16, 3); a reserved mode decodes to 0.
inline void decode_bc6h(const uint8_t* blocks, index_t n, bool is_signed, uint16_t* out,
                        const BptcTables& t) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t b = 0; b < n; ++b) {
    const Block128 bits(blocks + 16 * b);
    uint16_t* texels = out + 48 * b;
    int mode = static_cast<int>(bits.low() & 3);
    if (mode >= 2) mode = static_cast<int>(bits.low() & 31);
    const int64_t* m = t.bc6h_modes + 7 * mode;
    if (!m[0]) {
      std::fill(texels, texels + 48, uint16_t{0});
      continue;
    }
    const bool transformed = m[1] != 0;
    const int pb = static_cast<int>(m[2]), epb = static_cast<int>(m[3]);
    const int delta[3] = {static_cast<int>(m[4]), static_cast<int>(m[5]), static_cast<int>(m[6])};
    int64_t fields[13] = {};
    const int8_t* layout = t.bc6h_layout + 2 * 82 * mode;
    for (int i = 0; i < 82; ++i) {
      const int f = layout[2 * i];
      if (f >= 0) fields[f] |= bits.bits(i, 1) << layout[2 * i + 1];
    }
    const int ns = pb ? 2 : 1;
    const int64_t part = fields[12];
    if (part >= 64) {  // the tables hold 64 partitions
      errors.fail("BC6H block with partition " + std::to_string(part));
      continue;
    }
    int64_t endpoints[4][3] = {};
    for (int c = 0; c < 3; ++c) {
      int64_t base = fields[c];
      if (is_signed) base = sign_extend(base, epb);
      endpoints[0][c] = base;
      for (int e = 1; e < 2 * ns; ++e) {
        int64_t v = fields[3 * e + c];
        if (is_signed || transformed) v = sign_extend(v, delta[c]);
        if (transformed) {
          v = (base + v) & ((int64_t{1} << epb) - 1);
          if (is_signed) v = sign_extend(v, epb);
        }
        endpoints[e][c] = v;
      }
    }
    for (int e = 0; e < 2 * ns; ++e)
      for (int c = 0; c < 3; ++c)
        endpoints[e][c] = is_signed ? unquantize_signed(endpoints[e][c], epb)
                                    : unquantize_unsigned(endpoints[e][c], epb);
    const int index_bits = ns == 1 ? 4 : 3;
    int position = ns == 1 ? 65 : 82;
    for (int i = 0; i < 16; ++i) {
      const bool anchor = i == 0 || (ns == 2 && i == t.a2[part]);
      const int count = anchor ? index_bits - 1 : index_bits;
      const int64_t index = bits.bits(position, count);
      position += count;
      const int s = ns == 2 ? t.p2[16 * part + i] : 0;
      const int64_t w = t.weights[16 * index_bits + index];
      for (int c = 0; c < 3; ++c) {
        const int64_t v = interpolate(endpoints[2 * s][c], endpoints[2 * s + 1][c], w);
        int64_t half;
        if (!is_signed)
          half = (v * 31) >> 6;
        else if (v < 0)
          half = (((-v) * 31) >> 5) | 0x8000;
        else
          half = (v * 31) >> 5;
        texels[3 * i + c] = static_cast<uint16_t>(half);
      }
    }
  }
  errors.check();
}

namespace detail {

// The four RGBA colours of a BC1 colour block (real arithmetic, values in [0, 1]).
inline void bc1_colors(int64_t c0, int64_t c1, bool four, double colors[4][4]) {
  const double r0 = (c0 >> 11) / 31.0, g0 = ((c0 >> 5) & 63) / 63.0, b0 = (c0 & 31) / 31.0;
  const double r1 = (c1 >> 11) / 31.0, g1 = ((c1 >> 5) & 63) / 63.0, b1 = (c1 & 31) / 31.0;
  colors[0][0] = r0, colors[0][1] = g0, colors[0][2] = b0, colors[0][3] = 1.0;
  colors[1][0] = r1, colors[1][1] = g1, colors[1][2] = b1, colors[1][3] = 1.0;
  if (four) {
    colors[2][0] = (2 * r0 + r1) / 3;
    colors[2][1] = (2 * g0 + g1) / 3;
    colors[2][2] = (2 * b0 + b1) / 3;
    colors[3][0] = (r0 + 2 * r1) / 3;
    colors[3][1] = (g0 + 2 * g1) / 3;
    colors[3][2] = (b0 + 2 * b1) / 3;
    colors[2][3] = colors[3][3] = 1.0;
  } else {
    colors[2][0] = (r0 + r1) / 2;
    colors[2][1] = (g0 + g1) / 2;
    colors[2][2] = (b0 + b1) / 2;
    colors[2][3] = 1.0;
    colors[3][0] = colors[3][1] = colors[3][2] = colors[3][3] = 0.0;
  }
}

// The eight values of a BC4 block (or BC3's alpha, BC5's channel) at `block`.
inline void bc4_values(const uint8_t* block, double values[8]) {
  const double r0 = block[0], r1 = block[1];
  values[0] = r0 / 255;
  values[1] = r1 / 255;
  if (r0 > r1) {
    for (int i = 2; i < 8; ++i) values[i] = ((8 - i) * r0 + (i - 1) * r1) / 7 / 255;
  } else {
    for (int i = 2; i < 6; ++i) values[i] = ((6 - i) * r0 + (i - 1) * r1) / 5 / 255;
    values[6] = 0.0;
    values[7] = 1.0;
  }
}

// The sixteen 3-bit codes of a BC4 block at `block`, as 48 bits.
inline uint64_t bc4_codes(const uint8_t* block) {
  uint64_t bits = 0;
  for (int k = 0; k < 6; ++k) bits |= static_cast<uint64_t>(block[2 + k]) << (8 * k);
  return bits;
}

}  // namespace detail

// BC1 (kind 1), BC3 (3), BC4 (4) and BC5 (5) blocks (n, 8 or 16) -> texels (n, 16, C) float32
// (C: 4, 4, 1, 2), computed in float64 and rounded once.
inline void decode_s3tc(const uint8_t* blocks, index_t n, int kind, float* out) {
  const index_t block_bytes = (kind == 1 || kind == 4) ? 8 : 16;
  const index_t channels = kind == 4 ? 1 : kind == 5 ? 2 : 4;
#pragma omp parallel for schedule(static)
  for (index_t b = 0; b < n; ++b) {
    const uint8_t* block = blocks + block_bytes * b;
    float* texels = out + 16 * channels * b;
    double values[8];
    if (kind == 1 || kind == 3) {
      const uint8_t* color = block + (kind == 3 ? 8 : 0);
      const int64_t c0 = int64_t{color[0]} | int64_t{color[1]} << 8;
      const int64_t c1 = int64_t{color[2]} | int64_t{color[3]} << 8;
      double colors[4][4];
      detail::bc1_colors(c0, c1, kind == 3 || c0 > c1, colors);
      int64_t codes = 0;
      for (int k = 0; k < 4; ++k) codes |= int64_t{color[4 + k]} << (8 * k);
      for (int i = 0; i < 16; ++i) {
        const int64_t code = (codes >> (2 * i)) & 3;
        for (int c = 0; c < 4; ++c) texels[4 * i + c] = static_cast<float>(colors[code][c]);
      }
      if (kind == 3) {
        detail::bc4_values(block, values);
        const uint64_t bits = detail::bc4_codes(block);
        for (int i = 0; i < 16; ++i)
          texels[4 * i + 3] = static_cast<float>(values[(bits >> (3 * i)) & 7]);
      }
    } else {
      for (index_t channel = 0; channel < channels; ++channel) {
        detail::bc4_values(block + 8 * channel, values);
        const uint64_t bits = detail::bc4_codes(block + 8 * channel);
        for (int i = 0; i < 16; ++i)
          texels[channels * i + channel] = static_cast<float>(values[(bits >> (3 * i)) & 7]);
      }
    }
  }
}

}  // namespace bakeshop::io::compress
