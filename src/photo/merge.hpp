// The merge of an exposure stack into HDR radiance with its confidence
// (bakeshop/photo/merge.py's module notes): per pixel, the weighted mean of the unclipped
// frames' estimates, an optional ghost test against the median frame, and the status of the
// pixels no frame votes for. The float32 products and float64 sums are the old JIT's, operation for
// operation.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::photo {

struct MergeInputs {
  index_t frames, height, width, channels;  // codes is (frames, height, width, channels)
  const float* table;                        // (Z, channels) linear value of each code
  const float* weight;                       // (Z, channels) merge weight
  const float* slope;                        // (Z, channels) log slope per full scale
  index_t levels;                            // Z: every code of the codes' type is below it
  int64_t low, high;                         // clipped ends (codes)
  const float* inv_exposure;                 // (frames,)
  const double* shifts;                      // (frames, 2): dy, dx
  double ghost;                              // 0: no ghost test
  double noise;
};

struct MergeOutputs {
  float* out;       // (height, width, channels)
  uint8_t* votes;   // (height, width)
  float* wsum;      // (height, width)
  uint8_t* status;  // (height, width)
  int32_t* counts;  // (height, frames, 3): clipped high, clipped low, ghost-rejected
};

template <class Code>
void merge_rows(const Code* codes, const MergeInputs& in, index_t row0, index_t row1,
                const MergeOutputs& o) {
  const index_t p = in.frames, h = in.height, w = in.width, nc = in.channels, nz = in.levels;
  std::vector<double> shift_y(p), shift_x(p), frac_y(p), frac_x(p);
  std::vector<int64_t> iys(p), ixs(p);
  bool whole = true;
  for (index_t j = 0; j < p; ++j) {
    shift_y[j] = std::floor(in.shifts[2 * j]);
    shift_x[j] = std::floor(in.shifts[2 * j + 1]);
    frac_y[j] = in.shifts[2 * j] - shift_y[j];
    frac_x[j] = in.shifts[2 * j + 1] - shift_x[j];
    // finite (merge_stack checks); beyond +-1e15 rows every tap is clamped to an edge anyway
    iys[j] = static_cast<int64_t>(std::fmax(-1e15, std::fmin(1e15, shift_y[j])));
    ixs[j] = static_cast<int64_t>(std::fmax(-1e15, std::fmin(1e15, shift_x[j])));
    if (frac_y[j] != 0.0 || frac_x[j] != 0.0) whole = false;
  }
  std::vector<float> lut(static_cast<size_t>(p * nz * nc));
  for (index_t j = 0; j < p; ++j)
    for (index_t z = 0; z < nz; ++z)
      for (index_t c = 0; c < nc; ++c)
        lut[(j * nz + z) * nc + c] = in.table[z * nc + c] * in.inv_exposure[j];
  std::vector<uint8_t> flag(static_cast<size_t>(nz), 0);
  for (index_t z = 0; z < nz; ++z) flag[z] = z >= in.high ? 1 : (z <= in.low ? 2 : 0);
  auto clamp = [](int64_t v, int64_t hi) { return v < 0 ? 0 : (v > hi ? hi : v); };
  auto code_at = [&](index_t j, int64_t y, int64_t x, index_t c) {
    return static_cast<index_t>(codes[((j * h + y) * w + x) * nc + c]);
  };

#pragma omp parallel
  {
    std::vector<float> est(p * nc), wts(p * nc), sig(p);
    std::vector<int8_t> state(p);
    std::vector<double> order_level(p), order_w(p);
    std::vector<int64_t> order_j(p);
    std::vector<double> acc(nc), den(nc), acc_all(nc), den_all(nc), first(nc), last(nc);
#pragma omp for schedule(static)
    for (index_t y = row0; y < row1; ++y) {
      int32_t* counts = o.counts + y * p * 3;
      for (index_t x = 0; x < w; ++x) {
        float* out = o.out + (y * w + x) * nc;
        if (in.ghost == 0.0 && whole) {  // no ghost test, whole-pixel shifts: one fused pass
          int64_t n = 0;
          double wsum_total = 0.0;
          for (index_t c = 0; c < nc; ++c) acc[c] = den[c] = acc_all[c] = den_all[c] = 0.0;
          int first_state = 0, last_state = 0;
          for (index_t j = 0; j < p; ++j) {
            const int64_t y0 = clamp(y + iys[j], h - 1), x0 = clamp(x + ixs[j], w - 1);
            int f = 0;
            for (index_t c = 0; c < nc; ++c) f |= flag[code_at(j, y0, x0, c)];
            const int state_j = f & 1 ? 1 : (f ? 2 : 0);
            if (state_j == 1)
              counts[j * 3] += 1;
            else if (state_j == 2)
              counts[j * 3 + 1] += 1;
            double total = 0.0;
            for (index_t c = 0; c < nc; ++c) {
              const index_t z = code_at(j, y0, x0, c);
              const float e = lut[(j * nz + z) * nc + c];
              const float wt = in.weight[z * nc + c];
              const float we = wt * e;
              acc_all[c] += we;
              den_all[c] += wt;
              if (j == 0) first[c] = e;
              if (j == p - 1) last[c] = e;
              if (state_j == 0) {
                acc[c] += we;
                den[c] += wt;
                total += wt;
              }
            }
            if (j == 0) first_state = state_j;
            if (j == p - 1) last_state = state_j;
            if (state_j == 0) {
              n += 1;
              wsum_total += total / static_cast<double>(nc);
            }
          }
          int code = 0;
          if (n == 0) {
            if (first_state == 1) {
              code = 1;
              for (index_t c = 0; c < nc; ++c) acc[c] = first[c], den[c] = 1.0;
            } else if (last_state == 2) {
              code = 2;
              for (index_t c = 0; c < nc; ++c) acc[c] = last[c], den[c] = 1.0;
            } else {
              for (index_t c = 0; c < nc; ++c) {
                if (den_all[c] > 0.0) {
                  acc[c] = acc_all[c];
                  den[c] = den_all[c];
                } else {
                  acc[c] = first[c];
                  den[c] = 1.0;
                }
              }
            }
          }
          for (index_t c = 0; c < nc; ++c)
            out[c] = static_cast<float>(den[c] > 0.0 ? acc[c] / den[c] : 0.0);
          o.votes[y * w + x] = static_cast<uint8_t>(n);
          o.wsum[y * w + x] = static_cast<float>(wsum_total);
          o.status[y * w + x] = static_cast<uint8_t>(code);
          continue;
        }
        for (index_t j = 0; j < p; ++j) {
          const int64_t iy = iys[j], ix = ixs[j];
          const double fy = frac_y[j], fx = frac_x[j];
          const int64_t y0 = clamp(y + iy, h - 1), x0 = clamp(x + ix, w - 1);
          const int64_t y1 = clamp(y + iy + 1, h - 1), x1 = clamp(x + ix + 1, w - 1);
          bool hi = false, lo = false;
          sig[j] = 0.0f;
          if (fy == 0.0 && fx == 0.0) {  // a whole-pixel shift (or none): one tap
            double s_j = 0.0;
            for (index_t c = 0; c < nc; ++c) {
              const index_t z = code_at(j, y0, x0, c);
              const int f = flag[z];
              if (f == 1)
                hi = true;
              else if (f == 2)
                lo = true;
              est[j * nc + c] = in.table[z * nc + c] * in.inv_exposure[j];
              wts[j * nc + c] = in.weight[z * nc + c];
              s_j += in.slope[z * nc + c];
            }
            sig[j] = static_cast<float>(s_j / static_cast<double>(nc));
          } else {
            for (index_t c = 0; c < nc; ++c) {
              double lin = 0.0, wt = 0.0, sl = 0.0;
              for (int t = 0; t < 4; ++t) {
                const int64_t ty = t < 2 ? y0 : y1;
                const int64_t tx = t % 2 == 0 ? x0 : x1;
                const double tw = (t < 2 ? 1.0 - fy : fy) * (t % 2 == 0 ? 1.0 - fx : fx);
                if (tw <= 0.0) continue;
                const index_t z = code_at(j, ty, tx, c);
                if (z >= in.high) hi = true;
                if (z <= in.low) lo = true;
                lin += tw * static_cast<double>(in.table[z * nc + c]);
                wt += tw * static_cast<double>(in.weight[z * nc + c]);
                sl += tw * static_cast<double>(in.slope[z * nc + c]);
              }
              est[j * nc + c] = static_cast<float>(lin * static_cast<double>(in.inv_exposure[j]));
              wts[j * nc + c] = static_cast<float>(wt);
              sig[j] = static_cast<float>(static_cast<double>(sig[j]) + sl / static_cast<double>(nc));
            }
          }
          state[j] = hi ? 1 : (lo ? 2 : 0);
          if (hi)
            counts[j * 3] += 1;
          else if (lo)
            counts[j * 3 + 1] += 1;
        }
        // the reference for the ghost test: the median of the unclipped frames' log levels,
        // one vote each
        double ref_level = 0.0, ref_sig = 0.0;
        if (in.ghost > 0.0) {
          index_t m = 0;
          double total_w = 0.0;
          for (index_t j = 0; j < p; ++j) {
            if (state[j] != 0) continue;
            double level = 0.0;
            for (index_t c = 0; c < nc; ++c) level += est[j * nc + c];
            if (level > 0.0) {
              order_level[m] = std::log(level);
              order_w[m] = 1.0;
              order_j[m] = j;
              total_w += 1.0;
              m += 1;
            }
          }
          for (index_t a = 1; a < m; ++a) {  // insertion sort by level
            const double lv = order_level[a], wv = order_w[a];
            const int64_t jv = order_j[a];
            index_t b = a - 1;
            while (b >= 0 && order_level[b] > lv) {
              order_level[b + 1] = order_level[b];
              order_w[b + 1] = order_w[b];
              order_j[b + 1] = order_j[b];
              b -= 1;
            }
            order_level[b + 1] = lv;
            order_w[b + 1] = wv;
            order_j[b + 1] = jv;
          }
          double run = 0.0;
          for (index_t a = 0; a < m; ++a) {
            run += order_w[a];
            if (run >= 0.5 * total_w) {
              ref_level = order_level[a];
              ref_sig = sig[order_j[a]];
              break;
            }
          }
        }
        int64_t n = 0;
        double wsum_total = 0.0;
        for (index_t c = 0; c < nc; ++c) out[c] = 0.0f;
        for (index_t c = 0; c < nc; ++c) acc[c] = den[c] = 0.0;
        for (index_t j = 0; j < p; ++j) {
          if (state[j] != 0) continue;
          if (in.ghost > 0.0) {
            double level = 0.0;
            for (index_t c = 0; c < nc; ++c) level += est[j * nc + c];
            if (level <= 0.0) continue;
            if (std::fabs(std::log(level) - ref_level) >
                in.ghost + 3.0 * in.noise * (static_cast<double>(sig[j]) + ref_sig)) {
              counts[j * 3 + 2] += 1;
              continue;
            }
          }
          n += 1;
          double total = 0.0;
          for (index_t c = 0; c < nc; ++c) {
            acc[c] += wts[j * nc + c] * est[j * nc + c];
            den[c] += wts[j * nc + c];
            total += wts[j * nc + c];
          }
          wsum_total += total / static_cast<double>(nc);
        }
        int code = 0;
        if (n == 0) {
          if (state[0] == 1) {
            code = 1;  // the darkest frame is clipped: a lower bound
            for (index_t c = 0; c < nc; ++c) acc[c] = est[c], den[c] = 1.0;
          } else if (state[p - 1] == 2) {
            code = 2;  // the brightest frame is dark: an upper bound
            for (index_t c = 0; c < nc; ++c) acc[c] = est[(p - 1) * nc + c], den[c] = 1.0;
          } else {  // each frame clipped in some channel: every channel on its own
            for (index_t j = 0; j < p; ++j)
              for (index_t c = 0; c < nc; ++c) {
                acc[c] += wts[j * nc + c] * est[j * nc + c];
                den[c] += wts[j * nc + c];
              }
            for (index_t c = 0; c < nc; ++c)
              if (den[c] <= 0.0) acc[c] = est[c], den[c] = 1.0;
          }
        }
        for (index_t c = 0; c < nc; ++c)
          out[c] = static_cast<float>(den[c] > 0.0 ? acc[c] / den[c] : 0.0);
        o.votes[y * w + x] = static_cast<uint8_t>(n);
        o.wsum[y * w + x] = static_cast<float>(wsum_total);
        o.status[y * w + x] = static_cast<uint8_t>(code);
      }
    }
  }
}

}  // namespace bakeshop::photo
