// The box and separable area filters of bakeshop/image/resize.py: float64 accumulation along
// rows of w * C samples (vectorised), one float64 row of scratch per output row.
#pragma once

#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::image {

// row[:n] (+)= src[y] + ... + src[y + k - 1] for k in 1, 2, 4, left to right in float64: the
// same sums, rounding for rounding, as adding the rows one at a time from zero.
template <class S>
inline void add_rows(double* row, const S* src, index_t stride, index_t y, int k, index_t n,
                     bool first) {
  const S* a = src + y * stride;
  if (k == 4) {
    const S *b = a + stride, *c = b + stride, *d = c + stride;
    if (first)
      for (index_t t = 0; t < n; ++t)
        row[t] = static_cast<double>(a[t]) + static_cast<double>(b[t]) +
                 static_cast<double>(c[t]) + static_cast<double>(d[t]);
    else
      for (index_t t = 0; t < n; ++t)
        row[t] = row[t] + static_cast<double>(a[t]) + static_cast<double>(b[t]) +
                 static_cast<double>(c[t]) + static_cast<double>(d[t]);
  } else if (k == 2) {
    const S* b = a + stride;
    if (first)
      for (index_t t = 0; t < n; ++t) row[t] = static_cast<double>(a[t]) + static_cast<double>(b[t]);
    else
      for (index_t t = 0; t < n; ++t)
        row[t] = row[t] + static_cast<double>(a[t]) + static_cast<double>(b[t]);
  } else {
    if (first)
      for (index_t t = 0; t < n; ++t) row[t] = static_cast<double>(a[t]);
    else
      for (index_t t = 0; t < n; ++t) row[t] += static_cast<double>(a[t]);
  }
}

// out[i, j, c] = the mean of the fy x fx block of src (rows of w * C samples, `stride` apart)
// that it covers: the block's columns summed down its rows, then the fx column sums of each
// texel, in float64, rounded once. out is (rows, width, channels).
template <class S, class O>
void box(const S* src, index_t stride, index_t fy, index_t fx, index_t rows, index_t width,
         index_t channels, O* out) {
  const index_t n = width * fx * channels;
  const double scale = 1.0 / static_cast<double>(fy * fx);
#pragma omp parallel
  {
    std::vector<double> scratch(static_cast<size_t>(n));
    double* row = scratch.data();
#pragma omp for schedule(static)
    for (index_t i = 0; i < rows; ++i) {
      index_t y = i * fy;
      const index_t stop = (i + 1) * fy;
      while (y < stop) {
        const int k = stop - y >= 4 ? 4 : (stop - y >= 2 ? 2 : 1);
        add_rows(row, src, stride, y, k, n, y == i * fy);
        y += k;
      }
      O* o = out + i * width * channels;
      for (index_t j = 0; j < width; ++j)
        for (index_t c = 0; c < channels; ++c) {
          const index_t base = j * fx * channels + c;
          double acc = row[base];
          for (index_t x = 1; x < fx; ++x) acc += row[base + x * channels];
          o[j * channels + c] = static_cast<O>(acc * scale);
        }
    }
  }
}

// out[i, j, c] = sum_t wx[t] sum_s wy[s] src[ky[s], kx[t] * C + c] over the CSR rows i of
// (ry, ky, wy) and j of (rx, kx, wx): the weighted input rows summed into one float64 row,
// then each texel's column taps. The CSR arrays are checked by the caller.
template <class S, class O>
void separable(const S* src, index_t stride, index_t n, const int64_t* ry, const int64_t* ky,
               const double* wy, const int64_t* rx, const int64_t* kx, const double* wx,
               index_t rows, index_t width, index_t channels, O* out) {
#pragma omp parallel
  {
    std::vector<double> scratch(static_cast<size_t>(n));
    double* row = scratch.data();
#pragma omp for schedule(static)
    for (index_t i = 0; i < rows; ++i) {
      for (index_t x = 0; x < n; ++x) row[x] = 0.0;
      for (int64_t t = ry[i]; t < ry[i + 1]; ++t) {
        const S* s = src + ky[t] * stride;
        const double wgt = wy[t];
        for (index_t x = 0; x < n; ++x) row[x] += wgt * static_cast<double>(s[x]);
      }
      O* o = out + i * width * channels;
      for (index_t j = 0; j < width; ++j)
        for (index_t c = 0; c < channels; ++c) {
          double acc = 0.0;
          for (int64_t t = rx[j]; t < rx[j + 1]; ++t) acc += wx[t] * row[kx[t] * channels + c];
          o[j * channels + c] = static_cast<O>(acc);
        }
    }
  }
}

// Whether (indptr, indices) is a CSR matrix of `rows` rows over [0, extent): indptr starts at
// 0, never decreases and ends within `nnz` entries, every index is in range.
inline bool csr_ok(const int64_t* indptr, index_t rows, const int64_t* indices, index_t nnz,
                   index_t extent) {
  if (indptr[0] < 0) return false;
  for (index_t i = 0; i < rows; ++i)
    if (indptr[i + 1] < indptr[i]) return false;
  if (indptr[rows] > nnz) return false;
  for (int64_t t = indptr[0]; t < indptr[rows]; ++t)
    if (indices[t] < 0 || indices[t] >= extent) return false;
  return true;
}

}  // namespace bakeshop::image
