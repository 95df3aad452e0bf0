// PNG kernels (bakeshop/io/ldr.py): undoing the filters of an untrusted file's scanlines
// (16-bit colour, which Pillow reduces to 8 bits) and choosing and applying them when writing.
//
// The loops are written per filter type (the type is the same for a whole row), so that the
// byte loops have no branch per byte and the cost sums vectorise.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::io {

// Paeth's predictor of PNG filter 4.
inline int32_t png_paeth(int32_t a, int32_t b, int32_t c) {
  const int32_t p = a + b - c;
  const int32_t pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

// The predictor of filter `kind` (0 none, 1 sub, 2 up, 3 average, 4 Paeth) from the byte to the
// left (a), above (b) and above-left (c), 0 outside the image.
template <int kind>
inline int32_t png_predict(int32_t a, int32_t b, int32_t c) {
  if constexpr (kind == 0)
    return 0;
  else if constexpr (kind == 1)
    return a;
  else if constexpr (kind == 2)
    return b;
  else if constexpr (kind == 3)
    return (a + b) >> 1;
  else
    return png_paeth(a, b, c);
}

// Undo filter `kind` of one row: src (stride filtered bytes) into row, up = the row above (zeros
// for the first row).
template <int kind>
inline void png_unfilter_row(const uint8_t* src, const uint8_t* up, index_t stride, index_t bpp,
                             uint8_t* row) {
  const index_t lead = std::min(bpp, stride);
  for (index_t i = 0; i < lead; ++i)
    row[i] = static_cast<uint8_t>((src[i] + png_predict<kind>(0, up[i], 0)) & 0xFF);
  for (index_t i = lead; i < stride; ++i)
    row[i] = static_cast<uint8_t>(
        (src[i] + png_predict<kind>(row[i - bpp], up[i], up[i - bpp])) & 0xFF);
}

// Undo the PNG filters of `height` rows of `stride` bytes, each after its filter byte, from
// buf[start:] into out ((height, stride)); the binding checks that buf holds them. Returns 0,
// or the 1-based row number whose filter type is invalid.
inline index_t png_unfilter(const uint8_t* buf, index_t start, index_t height, index_t stride,
                            index_t bpp, uint8_t* out) {
  const std::vector<uint8_t> zeros(static_cast<size_t>(stride), 0);
  for (index_t y = 0; y < height; ++y) {
    const uint8_t f = buf[start + y * (stride + 1)];
    const uint8_t* src = buf + start + y * (stride + 1) + 1;
    uint8_t* row = out + y * stride;
    const uint8_t* up = y > 0 ? row - stride : zeros.data();
    switch (f) {
      case 0: png_unfilter_row<0>(src, up, stride, bpp, row); break;
      case 1: png_unfilter_row<1>(src, up, stride, bpp, row); break;
      case 2: png_unfilter_row<2>(src, up, stride, bpp, row); break;
      case 3: png_unfilter_row<3>(src, up, stride, bpp, row); break;
      case 4: png_unfilter_row<4>(src, up, stride, bpp, row); break;
      default: return y + 1;
    }
  }
  return 0;
}

// Byte i of a row under filter `kind`: x - predictor, modulo 256.
template <int kind>
inline int32_t png_filtered(const uint8_t* row, const uint8_t* up, index_t i, index_t bpp) {
  const int32_t a = i >= bpp ? row[i - bpp] : 0;
  const int32_t c = i >= bpp ? up[i - bpp] : 0;
  return (row[i] - png_predict<kind>(a, up[i], c)) & 0xFF;
}

// The sum of absolute signed bytes of a row under filter `kind`, or a value >= `bound` once the
// sum reaches it (checked every block of bytes: the sums only grow, so the filter chosen is the
// one a byte-by-byte check chooses).
template <int kind>
inline int64_t png_cost(const uint8_t* row, const uint8_t* up, index_t stride, index_t bpp,
                        int64_t bound) {
  constexpr index_t block = 256;
  int64_t cost = 0;
  const index_t lead = std::min(bpp, stride);
  for (index_t i = 0; i < lead; ++i) {
    const int32_t d = png_filtered<kind>(row, up, i, bpp);
    cost += d < 128 ? d : 256 - d;
  }
  for (index_t i0 = lead; i0 < stride && cost < bound; i0 += block) {
    const index_t i1 = std::min(stride, i0 + block);
    int32_t sum = 0;
    for (index_t i = i0; i < i1; ++i) {
      const int32_t d = (row[i] - png_predict<kind>(row[i - bpp], up[i], up[i - bpp])) & 0xFF;
      sum += d < 128 ? d : 256 - d;
    }
    cost += sum;
  }
  return cost;
}

template <int kind>
inline void png_filter_row(const uint8_t* row, const uint8_t* up, index_t stride, index_t bpp,
                           uint8_t* dst) {
  for (index_t i = 0; i < stride; ++i)
    dst[i] = static_cast<uint8_t>(png_filtered<kind>(row, up, i, bpp));
}

// Filter each row of rows ((H, S) bytes) into out ((H, S + 1)), choosing per row the filter with
// the least sum of absolute signed bytes (libpng's heuristic; the first of equal sums).
inline void png_filter_rows(const uint8_t* rows, index_t height, index_t stride, index_t bpp,
                            uint8_t* out) {
  const std::vector<uint8_t> zeros(static_cast<size_t>(stride), 0);
#pragma omp parallel for schedule(static)
  for (index_t y = 0; y < height; ++y) {
    const uint8_t* row = rows + y * stride;
    const uint8_t* up = y > 0 ? row - stride : zeros.data();
    int best = 0;
    int64_t best_cost = int64_t{1} << 62;
    for (int kind = 0; kind < 5; ++kind) {
      int64_t cost = 0;
      switch (kind) {
        case 0: cost = png_cost<0>(row, up, stride, bpp, best_cost); break;
        case 1: cost = png_cost<1>(row, up, stride, bpp, best_cost); break;
        case 2: cost = png_cost<2>(row, up, stride, bpp, best_cost); break;
        case 3: cost = png_cost<3>(row, up, stride, bpp, best_cost); break;
        default: cost = png_cost<4>(row, up, stride, bpp, best_cost); break;
      }
      if (cost < best_cost) {
        best = kind;
        best_cost = cost;
      }
    }
    uint8_t* dst = out + y * (stride + 1);
    dst[0] = static_cast<uint8_t>(best);
    switch (best) {
      case 0: png_filter_row<0>(row, up, stride, bpp, dst + 1); break;
      case 1: png_filter_row<1>(row, up, stride, bpp, dst + 1); break;
      case 2: png_filter_row<2>(row, up, stride, bpp, dst + 1); break;
      case 3: png_filter_row<3>(row, up, stride, bpp, dst + 1); break;
      default: png_filter_row<4>(row, up, stride, bpp, dst + 1); break;
    }
  }
}

}  // namespace bakeshop::io
