// bakeshop's signed BC6H encoder (bakeshop/io/compress/bc6h_signed.py): the one-subset modes
// 3, 7, 11 and 15, endpoints on the block's principal axis refitted once by least squares, the
// mode with the smallest error in the signed q domain kept. Float64 throughout, in the
// operation order of the old JIT encoder it replaces (its encodings are bit-identical).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/kernel.hpp"
#include "io/compress/bptc.hpp"

namespace bakeshop::io::compress {

namespace bc6h_signed {

constexpr int kModes[4] = {3, 7, 11, 15};
constexpr int kEndpointBits[4] = {10, 11, 12, 16};
constexpr int kDeltaBits[4] = {10, 9, 8, 4};  // mode 3 is untransformed: E1 has 10 bits
constexpr int64_t kW4[16] = {0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64};

// The endpoint of `bits` bits whose unquantised value is nearest `q`.
inline int64_t quantize(double q, int bits) {
  const int64_t top = (int64_t{1} << (bits - 1)) - 1;
  // np.round: to nearest, ties to even (the default rounding mode's nearbyint)
  const double scaled = q * static_cast<double>(int64_t{1} << (bits - 1)) / 32768.0;
  const auto guess = static_cast<int64_t>(std::nearbyint(scaled));
  int64_t best = 0;
  double best_error = 1e30;
  for (int64_t x = guess - 1; x < guess + 2; ++x) {
    const int64_t clamped = std::min(std::max(x, -top), top);
    const double error = std::fabs(static_cast<double>(unquantize_signed(clamped, bits)) - q);
    if (error < best_error) best = clamped, best_error = error;
  }
  return best;
}

// The interpolated integer -> the signed q domain value the half float represents.
inline int64_t finish(int64_t v) { return v < 0 ? -(((-v) * 31) >> 5) : (v * 31) >> 5; }

// Quantise the endpoints `ends` for mode slot `mode`, choose the indices; the squared error in
// the q domain (the endpoints and indices are written in place).
inline double fit(const double q[16][3], int mode, const double ends[2][3],
                  int64_t quantized[2][3], int64_t indices[16]) {
  const int epb = kEndpointBits[mode], delta = kDeltaBits[mode];
  for (int c = 0; c < 3; ++c) {
    const int64_t a = quantize(ends[0][c], epb);
    int64_t b = quantize(ends[1][c], epb);
    if (mode > 0) {  // transformed: B is stored as a difference of `delta` bits
      const int64_t low = -(int64_t{1} << (delta - 1)), high = (int64_t{1} << (delta - 1)) - 1;
      b = a + std::min(std::max(b - a, low), high);
    }
    quantized[0][c] = a, quantized[1][c] = b;
  }
  int64_t unq[2][3];
  for (int e = 0; e < 2; ++e)
    for (int c = 0; c < 3; ++c) unq[e][c] = unquantize_signed(quantized[e][c], epb);
  int64_t palette[16][3];
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) palette[i][c] = finish(interpolate(unq[0][c], unq[1][c], kW4[i]));
  double total = 0.0;
  for (int t = 0; t < 16; ++t) {
    int64_t best = 0;
    double best_error = 1e30;
    for (int i = 0; i < 16; ++i) {
      double error = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = static_cast<double>(palette[i][c]) - q[t][c] * 31.0 / 32.0;
        error += d * d;
      }
      if (error < best_error) best = i, best_error = error;
    }
    indices[t] = best;
    total += best_error;
  }
  return total;
}

// One block of 16 texels in the q domain -> 16 bytes. `layout`: (32, 82, 2) (field, bit) of
// each block bit (_bptc.bc6h_bit_table()).
inline void encode_block(const double q[16][3], uint8_t* out, const int8_t* layout) {
  double mean[3] = {0.0, 0.0, 0.0};
  for (int t = 0; t < 16; ++t)
    for (int c = 0; c < 3; ++c) mean[c] += q[t][c];
  for (double& m : mean) m /= 16;
  double cov[3][3] = {};
  for (int t = 0; t < 16; ++t) {
    double d[3];
    for (int c = 0; c < 3; ++c) d[c] = q[t][c] - mean[c];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov[i][j] += d[i] * d[j];
  }
  const double diagonal = 1.0 / std::sqrt(3.0);
  double axis[3] = {diagonal, diagonal, diagonal};
  for (int iteration = 0; iteration < 8; ++iteration) {
    double next[3];
    for (int i = 0; i < 3; ++i)
      next[i] = cov[i][0] * axis[0] + cov[i][1] * axis[1] + cov[i][2] * axis[2];
    const double n = std::sqrt(0.0 + next[0] * next[0] + next[1] * next[1] + next[2] * next[2]);
    if (n == 0) {
      axis[0] = axis[1] = axis[2] = diagonal;
      break;
    }
    for (int c = 0; c < 3; ++c) axis[c] = next[c] / n;
  }
  double lo = 1e30, hi = -1e30;
  for (int t = 0; t < 16; ++t) {
    double p = 0.0;
    for (int c = 0; c < 3; ++c) p += (q[t][c] - mean[c]) * axis[c];
    lo = std::min(lo, p), hi = std::max(hi, p);
  }
  double best_error = 1e300;
  int best_mode = 0;
  int64_t best_q[2][3] = {}, best_indices[16] = {};
  int64_t quantized[2][3] = {}, indices[16] = {};
  double ends[2][3] = {};
  for (int mode = 0; mode < 4; ++mode) {
    for (int c = 0; c < 3; ++c) {
      ends[0][c] = mean[c] + lo * axis[c];
      ends[1][c] = mean[c] + hi * axis[c];
    }
    for (int attempt = 0; attempt < 2; ++attempt) {
      const double error = fit(q, mode, ends, quantized, indices);
      if (error < best_error) {
        best_error = error, best_mode = mode;
        std::copy(&quantized[0][0], &quantized[0][0] + 6, &best_q[0][0]);
        std::copy(indices, indices + 16, best_indices);
      }
      if (attempt == 1) break;
      // least-squares refit of the endpoints to the chosen weights
      double a = 0.0, b = 0.0, d = 0.0, rhs0[3] = {}, rhs1[3] = {};
      for (int t = 0; t < 16; ++t) {
        const double w = static_cast<double>(kW4[indices[t]]) / 64.0;
        a += (1 - w) * (1 - w);
        b += (1 - w) * w;
        d += w * w;
        for (int c = 0; c < 3; ++c) {
          rhs0[c] += (1 - w) * q[t][c];
          rhs1[c] += w * q[t][c];
        }
      }
      const double det = a * d - b * b;
      if (std::fabs(det) < 1e-9) break;
      for (int c = 0; c < 3; ++c) {
        ends[0][c] = std::min(std::max((d * rhs0[c] - b * rhs1[c]) / det, -32767.0), 32767.0);
        ends[1][c] = std::min(std::max((a * rhs1[c] - b * rhs0[c]) / det, -32767.0), 32767.0);
      }
    }
  }
  // the anchor (texel 0) has three index bits: its index must be below 8
  if (best_indices[0] >= 8) {
    double swapped[2][3];
    for (int c = 0; c < 3; ++c) {
      const int epb = kEndpointBits[best_mode];
      swapped[0][c] = static_cast<double>(unquantize_signed(best_q[1][c], epb));
      swapped[1][c] = static_cast<double>(unquantize_signed(best_q[0][c], epb));
    }
    fit(q, best_mode, swapped, quantized, indices);
    if (indices[0] >= 8) {  // a clamped difference: flip the indices of the same endpoints
      for (int t = 0; t < 16; ++t) indices[t] = 15 - best_indices[t];
      for (int c = 0; c < 3; ++c) quantized[0][c] = best_q[1][c], quantized[1][c] = best_q[0][c];
    }
    std::copy(&quantized[0][0], &quantized[0][0] + 6, &best_q[0][0]);
    std::copy(indices, indices + 16, best_indices);
  }
  int64_t fields[13] = {};
  for (int c = 0; c < 3; ++c) {
    fields[c] = best_q[0][c];
    fields[3 + c] = best_mode > 0 ? best_q[1][c] - best_q[0][c] : best_q[1][c];
  }
  const int mode_number = kModes[best_mode];
  uint8_t bits[128] = {};
  for (int i = 0; i < 5; ++i) bits[i] = (mode_number >> i) & 1;
  const int8_t* mode_layout = layout + 2 * 82 * mode_number;
  for (int i = 0; i < 82; ++i) {
    const int f = mode_layout[2 * i];
    if (f >= 0) bits[i] = static_cast<uint8_t>((fields[f] >> mode_layout[2 * i + 1]) & 1);
  }
  int position = 65;
  for (int t = 0; t < 16; ++t) {
    const int n = t == 0 ? 3 : 4;
    for (int k = 0; k < n; ++k)
      bits[position + k] = static_cast<uint8_t>((best_indices[t] >> k) & 1);
    position += n;
  }
  for (int byte = 0; byte < 16; ++byte) {
    int v = 0;
    for (int k = 0; k < 8; ++k) v |= bits[8 * byte + k] << k;
    out[byte] = static_cast<uint8_t>(v);
  }
}

}  // namespace bc6h_signed

// Blocks of 16 texels in the q domain (n, 16, 3) float64 -> signed BC6H blocks (n, 16).
inline void encode_bc6h_signed(const double* q_blocks, index_t n, uint8_t* out,
                               const int8_t* layout) {
#pragma omp parallel for schedule(static)
  for (index_t b = 0; b < n; ++b)
    bc6h_signed::encode_block(reinterpret_cast<const double(*)[3]>(q_blocks + 48 * b), out + 16 * b,
                              layout);
}

}  // namespace bakeshop::io::compress
