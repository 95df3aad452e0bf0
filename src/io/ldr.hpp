// PNG kernels (bakeshop/io/ldr.py): undoing the filters of an untrusted file's scanlines
// (16-bit colour, which Pillow reduces to 8 bits) and choosing and applying them when writing.
#pragma once

#include <cstdlib>

#include "common/kernel.hpp"

namespace bakeshop::io {

// Paeth's predictor of PNG filter 4.
inline int32_t png_paeth(int32_t a, int32_t b, int32_t c) {
  const int32_t p = a + b - c;
  const int32_t pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

// Undo the PNG filters of `height` rows of `stride` bytes, each after its filter byte, from
// buf[start:] into out ((height, stride)); the binding checks that buf holds them. Returns 0,
// or the 1-based row number whose filter type is invalid.
inline index_t png_unfilter(const uint8_t* buf, index_t start, index_t height, index_t stride,
                            index_t bpp, uint8_t* out) {
  for (index_t y = 0; y < height; ++y) {
    const uint8_t f = buf[start + y * (stride + 1)];
    const uint8_t* src = buf + start + y * (stride + 1) + 1;
    if (f > 4) return y + 1;
    uint8_t* row = out + y * stride;
    const uint8_t* up = y > 0 ? row - stride : row;  // the row above
    for (index_t i = 0; i < stride; ++i) {
      int32_t x = src[i];
      const int32_t a = i >= bpp ? row[i - bpp] : 0;
      const int32_t b = y > 0 ? up[i] : 0;
      const int32_t c = y > 0 && i >= bpp ? up[i - bpp] : 0;
      if (f == 1)
        x += a;
      else if (f == 2)
        x += b;
      else if (f == 3)
        x += (a + b) >> 1;
      else if (f == 4)
        x += png_paeth(a, b, c);
      row[i] = static_cast<uint8_t>(x & 0xFF);
    }
  }
  return 0;
}

// Byte i of row y of rows ((H, stride)) under PNG filter `kind` (0 none, 1 sub, 2 up, 3
// average, 4 Paeth).
inline int32_t png_filtered(const uint8_t* rows, index_t stride, index_t y, index_t i, int kind,
                            index_t bpp) {
  const uint8_t* row = rows + y * stride;
  const int32_t x = row[i];
  if (kind == 0) return x & 0xFF;
  const int32_t a = i >= bpp ? row[i - bpp] : 0;
  if (kind == 1) return (x - a) & 0xFF;
  const int32_t b = y > 0 ? row[i - stride] : 0;
  if (kind == 2) return (x - b) & 0xFF;
  if (kind == 3) return (x - ((a + b) >> 1)) & 0xFF;
  const int32_t c = y > 0 && i >= bpp ? row[i - stride - bpp] : 0;
  return (x - png_paeth(a, b, c)) & 0xFF;
}

// Filter each row of rows ((H, S) bytes) into out ((H, S + 1)), choosing per row the filter with
// the least sum of absolute signed bytes (libpng's heuristic; the first of equal sums).
inline void png_filter_rows(const uint8_t* rows, index_t height, index_t stride, index_t bpp,
                            uint8_t* out) {
#pragma omp parallel for schedule(static)
  for (index_t y = 0; y < height; ++y) {
    int best = 0;
    int64_t best_cost = int64_t{1} << 62;
    for (int kind = 0; kind < 5; ++kind) {
      int64_t cost = 0;
      for (index_t i = 0; i < stride; ++i) {
        const int32_t d = png_filtered(rows, stride, y, i, kind, bpp);
        cost += d < 128 ? d : 256 - d;
        if (cost >= best_cost) break;
      }
      if (cost < best_cost) {
        best = kind;
        best_cost = cost;
      }
    }
    uint8_t* dst = out + y * (stride + 1);
    dst[0] = static_cast<uint8_t>(best);
    for (index_t i = 0; i < stride; ++i)
      dst[i + 1] = static_cast<uint8_t>(png_filtered(rows, stride, y, i, best, bpp));
  }
}

}  // namespace bakeshop::io
