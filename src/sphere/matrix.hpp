// The area filter's kernels on its matrix (bakeshop/sphere/area.py drives them; CSR: int64 row
// starts, int32 source texels, float32 weights): its rows assembled from the deposits of
// area.hpp and the bilinear fill-in, Sinkhorn balancing, its rows reordered into a cube
// picture's, and its application.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::sphere {

// `EXCEPTION - k` points at row k of a plan's explicit taps (bakeshop.sphere._gather).
constexpr int32_t kException = -2;

// How far the balancing may scale a column (either way): a column that cannot carry its solid
// angle (a mirror ball's rim texels) stops there instead of growing until float32 overflows.
constexpr double kAreaColumnLimit = 1e6;

// The splat plan transposed into rows, one per destination texel q with alpha > 0: source
// texel p's weight w into q becomes the entry (p, w alpha[q] inverse[q]) of row q. Chunk t of
// the source texels (cursor is (chunks, m)) counts its entries per row into cursor[t, q]
// (`fill` false), or writes them at cursor[t, q] onwards (`fill` true), so that each row lists
// p in order. `n_taps` bounds the exception taps (offsets index into taps/weights).
inline void splat_rows(const int32_t* anchor, index_t n, const float* wq, const float* scale,
                       index_t row, const int64_t* offsets, index_t n_offsets,
                       const int32_t* taps, const float* weights, index_t n_taps,
                       const float* alpha, const float* inverse, index_t m, int64_t* cursor,
                       index_t chunks, bool fill, int32_t* indices, float* values,
                       index_t n_entries, Errors& errors) {
#pragma omp parallel for schedule(static)
  for (index_t t = 0; t < chunks; ++t) {
    int64_t* cur = cursor + t * m;
    for (index_t p = t * n / chunks; p < (t + 1) * n / chunks; ++p) {
      const int32_t b = anchor[p];
      if (b >= 0) {
        const double wx0 = wq[4 * p], wx1 = wq[4 * p + 1];
        const double wy0 = wq[4 * p + 2], wy1 = wq[4 * p + 3];
        const double wx2 = std::max(0.0, 1.0 - wx0 - wx1), wy2 = std::max(0.0, 1.0 - wy0 - wy1);
        for (int yb = 0; yb < 3; ++yb) {
          const double wy = yb == 0 ? wy0 : (yb == 1 ? wy1 : wy2);
          for (int xa = 0; xa < 3; ++xa) {
            const double w =
                static_cast<double>(scale[p]) * wy * (xa == 0 ? wx0 : (xa == 1 ? wx1 : wx2));
            const index_t q = b + yb * row + xa;
            if (q >= m) {
              errors.fail("splat_rows: a block beyond the destination");
              continue;
            }
            if (w > 0 && alpha[q] > 0) {
              if (fill) {
                const int64_t e = cur[q];
                if (e < 0 || e >= n_entries) {
                  errors.fail("splat_rows: an entry beyond the rows");
                  continue;
                }
                indices[e] = static_cast<int32_t>(p);
                values[e] = static_cast<float>(w * alpha[q] * inverse[q]);
              }
              cur[q] += 1;
            }
          }
        }
      } else if (b != -1) {
        const index_t k = kException - static_cast<index_t>(b);
        if (k < 0 || k + 1 >= n_offsets || offsets[k] < 0 || offsets[k + 1] > n_taps) {
          errors.fail("splat_rows: an exception beyond its taps");
          continue;
        }
        for (int64_t e2 = offsets[k]; e2 < offsets[k + 1]; ++e2) {
          const int32_t q = taps[e2];
          if (q < 0 || q >= m) {
            errors.fail("splat_rows: a tap beyond the destination");
            continue;
          }
          if (weights[e2] > 0 && alpha[q] > 0) {
            if (fill) {
              const int64_t e = cur[q];
              if (e < 0 || e >= n_entries) {
                errors.fail("splat_rows: an entry beyond the rows");
                continue;
              }
              indices[e] = static_cast<int32_t>(p);
              // float32 throughout, as the old JIT's float32 x float32
              values[e] = weights[e2] * alpha[q] * inverse[q];
            }
            cur[q] += 1;
          }
        }
      }
    }
  }
}

// Row q holds sum_t cursor[t, q] + extra[q] entries: indptr their running sum, and cursor[t, q]
// becomes where chunk t's entries of row q start (after the earlier chunks').
inline void row_starts(int64_t* cursor, index_t chunks, const int64_t* extra, index_t m,
                       int64_t* indptr) {
  int64_t total = 0;
  for (index_t q = 0; q < m; ++q) {
    indptr[q] = total;
    for (index_t t = 0; t < chunks; ++t) {
      const int64_t count = cursor[t * m + q];
      cursor[t * m + q] = total;
      total += count;
    }
    total += extra[q];
  }
  indptr[m] = total;
}

// Append to row q (at indptr[q + 1] - counts[q]) the bilinear taps of the plan (base, frac,
// taps) weighted by 1 - alpha[q], where alpha[q] < 1 (`fill`); else count them into counts[q].
// A cube corner's missing tap gives a third of its weight to each of the other three.
inline void bilinear_rows(const float* alpha, index_t m, index_t row, const int32_t* base,
                          const float* frac, index_t n_frac, const int32_t* taps,
                          index_t n_taps, const int64_t* indptr, int64_t* counts, bool fill,
                          int32_t* indices, float* values, index_t n_entries, Errors& errors) {
#pragma omp parallel for schedule(static)
  for (index_t q = 0; q < m; ++q) {
    const int32_t b = base[q];
    if (alpha[q] >= 1 || b == -1) continue;
    int64_t i0, i1, i2, i3;
    if (b >= 0) {
      i0 = b;
      i1 = static_cast<int64_t>(b) + 1;
      i2 = static_cast<int64_t>(b) + row;
      i3 = static_cast<int64_t>(b) + row + 1;
    } else {
      const index_t x = kException - static_cast<index_t>(b);
      if (x < 0 || x >= n_taps) {
        errors.fail("bilinear_rows: an exception beyond the plan's taps");
        continue;
      }
      i0 = taps[4 * x];
      i1 = taps[4 * x + 1];
      i2 = taps[4 * x + 2];
      i3 = taps[4 * x + 3];
    }
    if (!fill) {
      counts[q] = (i0 >= 0) + (i1 >= 0) + (i2 >= 0) + (i3 >= 0);
      continue;
    }
    if (q >= n_frac) {
      errors.fail("bilinear_rows: no fractions for a texel");
      continue;
    }
    // as the old JIT typed them: fx, fy float32, 1 - fx float64, fx * fy a float32 product
    const float fx = frac[2 * q], fy = frac[2 * q + 1];
    const double w0 = (1 - static_cast<double>(fx)) * (1 - static_cast<double>(fy));
    const double w1 = fx * (1 - static_cast<double>(fy));
    const double w2 = (1 - static_cast<double>(fx)) * fy;
    const double w3 = fx * fy;
    double lost = (i0 < 0 ? w0 : 0.0) + (i1 < 0 ? w1 : 0.0);
    lost += (i2 < 0 ? w2 : 0.0) + (i3 < 0 ? w3 : 0.0);
    const double scale = 1.0 - static_cast<double>(alpha[q]);
    int64_t e = indptr[q + 1] - counts[q];
    const int64_t is[4] = {i0, i1, i2, i3};
    const double ws[4] = {w0, w1, w2, w3};
    for (int k = 0; k < 4; ++k) {
      if (is[k] >= 0) {
        if (e < 0 || e >= n_entries) {
          errors.fail("bilinear_rows: an entry beyond the rows");
          break;
        }
        indices[e] = static_cast<int32_t>(is[k]);
        values[e] = static_cast<float>(scale * (ws[k] + lost / 3));
        ++e;
      }
    }
  }
}

// Multiply each entry by `factor` of its column (none: all 1), then scale each nonempty row to
// sum 1.
inline void scale_rows(const int64_t* indptr, index_t rows, const int32_t* indices, float* values,
                       const double* factor, index_t n_factor) {
  const bool scaled = n_factor > 0;
#pragma omp parallel for schedule(static)
  for (index_t q = 0; q < rows; ++q) {
    double total = 0.0;
    for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e) {
      if (scaled) values[e] = static_cast<float>(values[e] * factor[indices[e]]);
      total += values[e];
    }
    if (total > 0)
      for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e)
        values[e] = static_cast<float>(values[e] / total);
  }
}

// The row step of the balancing of M = diag(r) K diag(col) (K: values), with the next column
// step's sums gathered on the way: r[q] makes every nonempty row of M sum 1, and energy[t, p] +=
// omega_out[q] r[q] K[q, p] over the rows q of block t (rows blocks[t]:blocks[t + 1]).
inline void balance_rows(const int64_t* indptr, const int32_t* indices, const float* values,
                         const double* omega_out, const double* col, const int64_t* blocks,
                         index_t n_blocks, double* energy, index_t n) {
#pragma omp parallel for schedule(static)
  for (index_t t = 0; t < n_blocks; ++t) {
    double* sums = energy + t * n;
    for (int64_t q = blocks[t]; q < blocks[t + 1]; ++q) {
      double total = 0.0;
      for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e) total += values[e] * col[indices[e]];
      if (total > 0) {
        const double sent = omega_out[q] / total;
        for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e) sums[indices[e]] += values[e] * sent;
      }
    }
  }
}

// The column step, over-relaxed with momentum (see bakeshop.sphere.area._balance); returns the
// largest |omega_in / energy - 1|.
inline double balance_columns(double* energy, index_t threads, const double* omega_in, index_t n,
                              double* col, double* step) {
  double err = 0.0;
#pragma omp parallel for schedule(static) reduction(max : err)
  for (index_t p = 0; p < n; ++p) {
    double sent = 0.0;
    for (index_t t = 0; t < threads; ++t) {
      sent += energy[t * n + p];
      energy[t * n + p] = 0.0;
    }
    sent *= col[p];
    if (sent > 0) {
      const double r = omega_in[p] / sent;
      err = std::max(err, std::abs(r - 1));
      double scaled = col[p] * r * std::sqrt(r * step[p]);
      scaled = std::min(std::max(scaled, 1 / kAreaColumnLimit), kAreaColumnLimit);
      step[p] = scaled / col[p];
      col[p] = scaled;
    }
  }
  return err;
}

// Row p of the output matrix = row order[p] of the input (empty where -1).
inline void reorder_rows(const int64_t* indptr, const int32_t* indices, const float* values,
                         const int32_t* order, index_t n, const int64_t* out_indptr,
                         int32_t* out_indices, float* out_values) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < n; ++p) {
    const int32_t q = order[p];
    if (q >= 0) {
      int64_t o = out_indptr[p];
      for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e) {
        out_indices[o] = indices[e];
        out_values[o] = values[e];
        ++o;
      }
    }
  }
}

// The area filter applied: out[q] = sum over row q of weight x src[p], summed in float64 (the
// products in src's type), four channels at a time.
template <class T>
inline void area_gather(const T* src, index_t nc, const int64_t* indptr, const int32_t* indices,
                        const float* values, T* out, index_t m) {
#pragma omp parallel for schedule(static)
  for (index_t q = 0; q < m; ++q) {
    for (index_t c = 0; c < nc; c += 4) {
      const index_t k = std::min<index_t>(4, nc - c);
      double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
      for (int64_t e = indptr[q]; e < indptr[q + 1]; ++e) {
        const T* s = src + static_cast<index_t>(indices[e]) * nc + c;
        // a float32 weight: its products with float32 texels are float32 (as the old JIT's were)
        const float w = values[e];
        s0 += w * s[0];
        if (k > 1) s1 += w * s[1];
        if (k > 2) s2 += w * s[2];
        if (k > 3) s3 += w * s[3];
      }
      T* o = out + q * nc + c;
      o[0] = static_cast<T>(s0);
      if (k > 1) o[1] = static_cast<T>(s1);
      if (k > 2) o[2] = static_cast<T>(s2);
      if (k > 3) o[3] = static_cast<T>(s3);
    }
  }
}

}  // namespace bakeshop::sphere
