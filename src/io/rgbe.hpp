// The Radiance RGBE codec's kernels (bakeshop/io/rgbe.py, bakeshop/io/stream/rgbe.py): the
// scanline decoder (serial, and in parts on every thread for a file of new-style scanlines), the
// scanline walk of the window reader and the parallel encoder.
//
// The decoder reads an untrusted file: every read of `data` is checked against its size before
// it is made, and every run is checked against the scanline before it is written; a problem is
// a status code (below), which the Python side turns into its message.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::io {

// Status codes of the decoders (bakeshop/io/_rgbe_codes.py).
enum RgbeStatus : int { kOk = 0, kTruncated, kOverrun, kEmptyRun, kLength, kNoPrevious };

// Scanline lengths that the new run-length form can encode (Radiance's MINELEN, MAXELEN).
constexpr index_t kRleMin = 8, kRleMax = 0x7FFF;

// float32 bit patterns: +infinity (larger patterns are NaN and negatives) and the largest
// finite value.
constexpr int64_t kInfBits = 0x7F800000, kMaxBits = 0x7F7FFFFF;

struct RgbeResult {
  int status;
  index_t scanline;
  index_t pos;
};

// A float32 (scanline, pixel, channel) array with any strides (in elements, negative ones
// included: the flipped and transposed views of a read).
struct Strided3 {
  float* data;
  index_t s0, s1, s2;
  float& operator()(index_t i, index_t j, index_t c) const { return data[i * s0 + j * s1 + c * s2]; }
};

// Decode `nscan` scanlines of `scanlen` pixels from data[pos:n] into out(scan, pixel, channel),
// multiplying channel c by factors[c]: (m + 0.5) * 2**(e - 136) * factor in float64, rounded
// once to float32, and 0 where e == 0. With `dry` nothing is written: the pass only checks that
// the data holds the whole image. Returns (status, scanline, position after the last byte used).
inline RgbeResult rgbe_decode_serial(const uint8_t* data, index_t n, index_t pos, index_t nscan,
                                     index_t scanlen, const Strided3& out, const double* factors,
                                     bool dry) {
  std::vector<uint8_t> line(static_cast<size_t>(scanlen) * 4, 0);  // (pixel, channel)
  uint8_t previous[4] = {0, 0, 0, 0};
  bool has_previous = false;
  double scale[256];
  for (int e = 0; e < 256; ++e) scale[e] = std::ldexp(1.0, e - 136);
  for (index_t s = 0; s < nscan; ++s) {
    if (kRleMin <= scanlen && scanlen <= kRleMax && pos + 4 <= n && data[pos] == 2 &&
        data[pos + 1] == 2 && data[pos + 2] < 128) {
      if ((static_cast<index_t>(data[pos + 2]) << 8) + data[pos + 3] != scanlen)
        return {kLength, s, pos};
      pos += 4;
      for (int c = 0; c < 4; ++c) {
        index_t j = 0;
        while (j < scanlen) {
          if (pos >= n) return {kTruncated, s, pos};
          const index_t code = data[pos];
          pos += 1;
          if (code > 128) {
            const index_t count = code - 128;
            if (j + count > scanlen) return {kOverrun, s, pos};
            if (pos >= n) return {kTruncated, s, pos};
            const uint8_t value = data[pos];
            pos += 1;
            for (index_t k = j; k < j + count; ++k) line[k * 4 + c] = value;
            j += count;
          } else {
            const index_t count = code;
            if (count == 0) return {kEmptyRun, s, pos};
            if (j + count > scanlen) return {kOverrun, s, pos};
            if (pos + count > n) return {kTruncated, s, pos};
            for (index_t k = 0; k < count; ++k) line[(j + k) * 4 + c] = data[pos + k];
            pos += count;
            j += count;
          }
        }
      }
    } else {
      index_t j = 0;
      index_t shift = 0;  // grows by 8 a repeat record (int64, as the old JIT had it)
      while (j < scanlen) {
        if (pos + 4 > n) return {kTruncated, s, pos};
        if (data[pos] == 1 && data[pos + 1] == 1 && data[pos + 2] == 1) {
          const index_t e = data[pos + 3];
          pos += 4;
          if (e != 0) {
            if (shift > 24 || j + (e << shift) > scanlen) return {kOverrun, s, pos};
            if (j == 0 && !has_previous) return {kNoPrevious, s, pos};
            const index_t count = e << shift;
            for (index_t k = j; k < j + count; ++k)
              for (int c = 0; c < 4; ++c)
                line[k * 4 + c] = k == 0 ? previous[c] : line[(k - 1) * 4 + c];
            j += count;
          }
          shift += 8;
        } else {
          for (int c = 0; c < 4; ++c) line[j * 4 + c] = data[pos + c];
          pos += 4;
          j += 1;
          shift = 0;
        }
      }
    }
    for (int c = 0; c < 4; ++c) previous[c] = line[(scanlen - 1) * 4 + c];
    has_previous = true;
    if (!dry) {
      for (index_t j = 0; j < scanlen; ++j) {
        const uint8_t e = line[j * 4 + 3];
        if (e == 0) {
          for (int c = 0; c < 3; ++c) out(s, j, c) = 0.0f;
        } else {
          const double f = scale[e];
          for (int c = 0; c < 3; ++c)
            out(s, j, c) = static_cast<float>((static_cast<double>(line[j * 4 + c]) + 0.5) * f *
                                              factors[c]);
        }
      }
    }
  }
  return {kOk, nscan, pos};
}

struct RgbeWalk {
  index_t walked;  // scanlines walked
  index_t end;     // position after the last complete one
  int status;      // 0, or 1 length, 2 empty run, 3 overrun
};

// Walk up to `count` scanlines of data[pos:n] (packet headers only), writing each one's start
// plus `first` (the offset of `data` in the file) into starts[0:count]. Stops, status 0, at an
// incomplete scanline.
inline RgbeWalk rgbe_scan(const uint8_t* data, index_t n, index_t pos, index_t scanlen,
                          index_t count, int64_t* starts, int64_t first) {
  index_t done = 0;
  while (done < count) {
    const index_t start = pos;
    if (kRleMin <= scanlen && scanlen <= kRleMax && pos + 4 <= n && data[pos] == 2 &&
        data[pos + 1] == 2 && data[pos + 2] < 128) {
      if ((static_cast<index_t>(data[pos + 2]) << 8) + data[pos + 3] != scanlen)
        return {done, start, 1};
      pos += 4;
      for (int c = 0; c < 4; ++c) {
        index_t j = 0;
        while (j < scanlen) {
          if (pos >= n) return {done, start, 0};
          const index_t code = data[pos];
          pos += 1;
          if (code > 128) {
            pos += 1;
            j += code - 128;
          } else if (code == 0) {
            return {done, start, 2};
          } else {
            pos += code;
            j += code;
          }
          if (j > scanlen) return {done, start, 3};
        }
      }
      if (pos > n) return {done, start, 0};
    } else {
      index_t j = 0;
      index_t shift = 0;  // grows by 8 a repeat record (int64, as the old JIT had it)
      while (j < scanlen) {
        if (pos + 4 > n) return {done, start, 0};
        if (data[pos] == 1 && data[pos + 1] == 1 && data[pos + 2] == 1) {
          const index_t e = data[pos + 3];
          if (e != 0) {
            if (shift > 24) return {done, start, 3};
            j += e << shift;
          }
          shift += 8;
        } else {
          j += 1;
          shift = 0;
        }
        pos += 4;
      }
      if (j > scanlen) return {done, start, 3};
    }
    starts[done] = start + first;
    done += 1;
  }
  return {done, pos, 0};
}

// The decoder of the codec: rgbe_decode_serial's result and float32 bits. A file of new-style
// scanlines (which never refer to the scanline before) is decoded in parts on every thread:
// the scanlines located first (their packet headers only), each part starting at one; anything
// else (a dry pass, one thread, old-style or faulty scanlines) by the serial decoder, which
// reports what is wrong.
inline RgbeResult rgbe_decode(const uint8_t* data, index_t n, index_t pos, index_t nscan,
                              index_t scanlen, const Strided3& out, const double* factors,
                              bool dry) {
  const index_t parts = omp_get_max_threads();
  if (!dry && parts >= 2 && nscan >= 2 * parts) {
    std::vector<int64_t> starts(static_cast<size_t>(nscan) + 1);
    const RgbeWalk walk = rgbe_scan(data, n, pos, scanlen, nscan, starts.data(), 0);
    std::vector<index_t> bounds(static_cast<size_t>(parts) + 1);
    for (index_t k = 0; k <= parts; ++k) bounds[k] = k * nscan / parts;
    bool new_style = walk.walked == nscan && walk.status == 0;
    for (index_t k = 0; new_style && k < parts; ++k) {
      const int64_t p = starts[bounds[k]];
      new_style = p + 1 < n && data[p] == 2 && data[p + 1] == 2;
    }
    if (new_style) {
      index_t ok = 0;
#pragma omp parallel for schedule(static) reduction(+ : ok)
      for (index_t k = 0; k < parts; ++k) {
        const Strided3 part{out.data + bounds[k] * out.s0, out.s0, out.s1, out.s2};
        const RgbeResult r = rgbe_decode_serial(data, n, starts[bounds[k]], bounds[k + 1] - bounds[k],
                                                scanlen, part, factors, false);
        ok += r.status == kOk;
      }
      if (ok == parts) return {kOk, nscan, walk.end};
    }
  }
  return rgbe_decode_serial(data, n, pos, nscan, scanlen, out, factors, dry);
}

// floor(value * 2**(136 - e)) capped at 255 for a non-negative finite float32 of bits b: the
// significand (implicit 1 included) shifted right by the exponents' difference, exact in
// integers.
inline uint8_t rgbe_mantissa(int64_t b, int64_t e) {
  const int64_t biased = b >> 23;
  const int64_t mant = (b & 0x7FFFFF) | (biased > 0 ? 0x800000 : 0);
  const int64_t shift = std::min<int64_t>(e + 14 - std::max<int64_t>(biased, 1), 31);
  return static_cast<uint8_t>(std::min<int64_t>(mant >> shift, 255));
}

// Encode one row of `width` linear pixels of `channels` float32 (1 grey, or 3) into line[c *
// width + x] (R, G, B mantissas and exponent). The bytes minimise the error of the (m + 0.5)
// reconstruction: the largest component picks the smallest exponent that holds it (its
// mantissa in [128, 256)) and each mantissa is the floor. NaN and negatives become 0; values
// beyond RGBE's largest (infinities included) saturate to it; values below 2**-128 make a black
// pixel. Everything is read from the bit patterns (non-negative floats order like their bits).
inline void rgbe_row(const float* values, index_t width, index_t channels, uint8_t* line) {
  constexpr int64_t smallest = int64_t{1} << 21;  // the bits of 2**-128
  const index_t g = channels == 3 ? 1 : 0, r = channels == 3 ? 2 : 0;
  for (index_t x = 0; x < width; ++x) {
    const float* v = values + x * channels;
    uint32_t u0, u1, u2;
    std::memcpy(&u0, v, 4);
    std::memcpy(&u1, v + g, 4);
    std::memcpy(&u2, v + r, 4);
    int64_t b0 = u0, b1 = u1, b2 = u2;
    b0 = b0 <= kInfBits ? std::min(b0, kMaxBits) : 0;
    b1 = b1 <= kInfBits ? std::min(b1, kMaxBits) : 0;
    b2 = b2 <= kInfBits ? std::min(b2, kMaxBits) : 0;
    const int64_t top = std::max({b0, b1, b2});
    if (top < smallest) {
      line[x] = line[width + x] = line[2 * width + x] = line[3 * width + x] = 0;
      continue;
    }
    const int64_t biased = top >> 23;
    int64_t e;
    if (biased >= 2) {
      e = std::min<int64_t>(biased + 2, 255);
    } else {  // a subnormal float32 or the smallest normals: let frexp find the exponent
      const float f = top == b0 ? v[0] : (top == b1 ? v[g] : v[r]);
      int exponent;
      std::frexp(static_cast<double>(f), &exponent);
      e = exponent + 128;
    }
    line[x] = rgbe_mantissa(b0, e);
    line[width + x] = rgbe_mantissa(b1, e);
    line[2 * width + x] = rgbe_mantissa(b2, e);
    line[3 * width + x] = static_cast<uint8_t>(e);
  }
}

// Append one byte plane of n bytes as new-style runs (>= 4 equal bytes, <= 127 per run) and
// literals (<= 128 per packet) to buf at pos; return the new position. `differ` is scratch of n
// rounded up to 8 bytes. This is the packing of Radiance's fwritecolrs and of Walter's rgbe.c:
// the next run is the first place where four equal bytes start; the literal bytes before it are
// written as a short run when they are 2 or 3 equal bytes. Where runs of four start is computed
// for the whole plane first and searched eight bytes a step.
inline index_t rgbe_rle_plane(const uint8_t* plane, index_t n, uint8_t* buf, index_t pos,
                              uint8_t* differ, index_t padded) {
  // differ[i] == 0 where plane[i] == plane[i + 1] == plane[i + 2] == plane[i + 3]: a run can
  // start there; padded with 1, no run.
  for (index_t i = std::max<index_t>(n - 3, 0); i < padded; ++i) differ[i] = 1;
  for (index_t i = 0; i < n - 3; ++i) {
    const uint8_t p = plane[i];
    differ[i] = static_cast<uint8_t>((p ^ plane[i + 1]) | (p ^ plane[i + 2]) | (p ^ plane[i + 3]));
  }
  constexpr uint64_t ones = 0x0101010101010101ull, highs = 0x8080808080808080ull;
  index_t cur = 0;
  while (cur < n) {
    index_t begin = cur;
    while (begin < n && differ[begin] != 0) {  // to the next run, eight bytes a step
      uint64_t w;
      std::memcpy(&w, differ + (begin / 8) * 8, 8);
      if (begin % 8 == 0 && ((w - ones) & ~w & highs) == 0)  // no zero byte in w
        begin += 8;
      else
        begin += 1;
    }
    begin = std::min(begin, n);
    const bool short_run = 2 <= begin - cur && begin - cur <= 3;
    if (short_run && plane[cur] == plane[cur + 1] && plane[cur] == plane[begin - 1]) {
      buf[pos] = static_cast<uint8_t>(128 + begin - cur);
      buf[pos + 1] = plane[cur];
      pos += 2;
      cur = begin;
    }
    while (cur < begin) {
      const index_t count = std::min<index_t>(begin - cur, 128);
      buf[pos] = static_cast<uint8_t>(count);
      std::memcpy(buf + pos + 1, plane + cur, static_cast<size_t>(count));
      pos += count + 1;
      cur += count;
    }
    if (begin < n) {
      index_t run = 4;
      while (begin + run < n && run < 127 && plane[begin + run] == plane[begin]) run += 1;
      buf[pos] = static_cast<uint8_t>(128 + run);
      buf[pos + 1] = plane[begin];
      pos += 2;
      cur += run;
    }
  }
  return pos;
}

// Bytes of one encoded scanline at worst.
inline index_t rgbe_line_bytes(index_t width, bool rle) {
  return rle ? 4 + 4 * (width + (width + 127) / 128) : 4 * width;
}

// Encode a C-contiguous (H, W, C) float32 image (C = 1 grey or 3 RGB) into Radiance scanlines,
// blocks of `block_rows` scanlines in parallel, block k into buf[k * block_rows *
// rgbe_line_bytes:] (pages never written are never touched); its bytes are
// buf[starts[k]:stops[k]], and the file's bytes are the blocks' bytes in order.
inline void rgbe_encode(const float* image, index_t height, index_t width, index_t channels,
                        bool rle, index_t block_rows, uint8_t* buf, int64_t* starts,
                        int64_t* stops) {
  const index_t per_line = rgbe_line_bytes(width, rle);
  const index_t blocks = (height + block_rows - 1) / block_rows;
  const index_t padded = (width + 7) / 8 * 8;
#pragma omp parallel
  {
    std::vector<uint8_t> line(static_cast<size_t>(4 * width));
    std::vector<uint8_t> differ(static_cast<size_t>(padded));
#pragma omp for schedule(static)
    for (index_t k = 0; k < blocks; ++k) {
      index_t pos = k * block_rows * per_line;
      starts[k] = pos;
      for (index_t y = k * block_rows; y < std::min(height, (k + 1) * block_rows); ++y) {
        rgbe_row(image + y * width * channels, width, channels, line.data());
        if (rle) {
          buf[pos] = 2;
          buf[pos + 1] = 2;
          buf[pos + 2] = static_cast<uint8_t>(width >> 8);
          buf[pos + 3] = static_cast<uint8_t>(width & 255);
          pos += 4;
          for (index_t c = 0; c < 4; ++c)
            pos = rgbe_rle_plane(line.data() + c * width, width, buf, pos, differ.data(), padded);
        } else {
          for (index_t x = 0; x < width; ++x) {
            for (index_t c = 0; c < 4; ++c) buf[pos + c] = line[c * width + x];
            pos += 4;
          }
        }
      }
      stops[k] = pos;
    }
  }
}

}  // namespace bakeshop::io
