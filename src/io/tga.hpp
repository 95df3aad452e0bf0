// Truevision TGA kernels (bakeshop/io/tga.py): the RLE decoder of an untrusted file, the RLE
// encoder of the writer and the expansion of 8-bit samples through a lookup table.
#pragma once

#include <cstring>

#include "common/kernel.hpp"

namespace bakeshop::io {

// Decode `count` pixels of `bpp` bytes from data[start:n] into out[0:count * bpp]. Returns the
// offset after the last packet, -1 if the data ends early, -2 if a packet runs past the last
// pixel: every packet is checked against both ends before its bytes are copied.
inline index_t tga_unrle(const uint8_t* data, index_t n, index_t start, index_t count,
                         index_t bpp, uint8_t* out) {
  index_t pos = start;
  index_t i = 0;
  while (i < count) {
    if (pos >= n) return -1;
    const uint8_t h = data[pos];
    pos += 1;
    const index_t run = (h & 0x7F) + 1;
    if (i + run > count) return -2;
    if (h & 0x80) {
      if (pos + bpp > n) return -1;
      for (index_t k = 0; k < run; ++k)
        for (index_t b = 0; b < bpp; ++b) out[(i + k) * bpp + b] = data[pos + b];
      pos += bpp;
    } else {
      const index_t m = run * bpp;
      if (pos + m > n) return -1;
      std::memcpy(out + i * bpp, data + pos, static_cast<size_t>(m));
      pos += m;
    }
    i += run;
  }
  return pos;
}

// Whether pixels a and b (of bpp bytes) of a row are equal.
inline bool tga_same(const uint8_t* row, index_t a, index_t b, index_t bpp) {
  for (index_t k = 0; k < bpp; ++k)
    if (row[a * bpp + k] != row[b * bpp + k]) return false;
  return true;
}

// Run-length encode each of the `height` rows of rows ((H, W * bpp) bytes) into TGA packets
// (never crossing a row) into out, which holds at least height * width * (bpp + 1) bytes (the
// worst case); return the bytes written.
inline index_t tga_rle(const uint8_t* rows, index_t height, index_t width, index_t bpp,
                       uint8_t* out) {
  index_t o = 0;
  for (index_t y = 0; y < height; ++y) {
    const uint8_t* row = rows + y * width * bpp;
    index_t x = 0;
    while (x < width) {
      index_t run = 1;
      while (x + run < width && run < 128 && tga_same(row, x, x + run, bpp)) run += 1;
      if (run >= 2) {
        out[o] = static_cast<uint8_t>(0x80 | (run - 1));
        std::memcpy(out + o + 1, row + x * bpp, static_cast<size_t>(bpp));
        o += 1 + bpp;
        x += run;
      } else {
        const index_t start = x;
        x += 1;
        while (x < width && x - start < 128) {
          if (x + 1 < width && tga_same(row, x, x + 1, bpp)) break;
          x += 1;
        }
        const index_t n = x - start;
        out[o] = static_cast<uint8_t>(n - 1);
        std::memcpy(out + o + 1, row + start * bpp, static_cast<size_t>(n * bpp));
        o += 1 + n * bpp;
      }
    }
  }
  return o;
}

// out[y, x, c] = lut[byte order[c] of the stored pixel that lands at (x, y)]: raw holds height *
// width pixels of bpp bytes, every order[c] < bpp, lut 256 entries (the binding checks them).
inline void tga_expand8(const uint8_t* raw, index_t height, index_t width, index_t bpp,
                        const int64_t* order, index_t channels, bool flip_x, bool flip_y,
                        const float* lut, float* out) {
#pragma omp parallel for schedule(static)
  for (index_t y = 0; y < height; ++y) {
    const index_t sy = flip_y ? height - 1 - y : y;
    for (index_t x = 0; x < width; ++x) {
      const index_t sx = flip_x ? width - 1 - x : x;
      const index_t base = (sy * width + sx) * bpp;
      for (index_t c = 0; c < channels; ++c)
        out[(y * width + x) * channels + c] = lut[raw[base + order[c]]];
    }
  }
}

}  // namespace bakeshop::io
