// Real spherical harmonics of bakeshop/light/sh/harmonics.py: the basis by the fully
// normalised associated Legendre recurrence, and the projection of samples on it.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::light::sh {

// Y(l, m) at one direction into out[l * (l + 1) + m]: the fully normalised associated Legendre
// recurrence in z, and (cm, sm) = Re, Im of (x + iy)^m = sin^m (cos m phi, sin m phi).
inline void basis_into(double x, double y, double z, int order, double* out) {
  const double pi = 3.141592653589793;
  double cm = 1.0, sm = 0.0;
  double pmm = 0.5 / std::sqrt(pi);  // normalised P(m, m) / sin^m
  const double root2 = std::sqrt(2.0);
  for (int m = 0; m <= order; ++m) {
    if (m > 0) {
      const double c2 = cm * x - sm * y, s2 = cm * y + sm * x;
      cm = c2, sm = s2;
      pmm *= std::sqrt(static_cast<double>(2 * m + 1) / static_cast<double>(2 * m));
    }
    double p_prev = 0.0, p = pmm;  // P(l - 1, m), P(l, m) for l = m
    for (int l = m; l <= order; ++l) {
      if (l == m + 1) {
        const double next = std::sqrt(static_cast<double>(2 * m + 3)) * z * p;
        p_prev = p, p = next;
      } else if (l > m + 1) {
        // Python's int / int: true division of the exact integers
        const double a = std::sqrt(static_cast<double>(4 * l * l - 1) /
                                   static_cast<double>(l * l - m * m));
        const double b = std::sqrt(static_cast<double>((l - 1) * (l - 1) - m * m) /
                                   static_cast<double>(4 * (l - 1) * (l - 1) - 1));
        const double next = a * (z * p - b * p_prev);
        p_prev = p, p = next;
      }
      if (m == 0) {
        out[l * (l + 1)] = p;
      } else {
        out[l * (l + 1) + m] = root2 * p * cm;
        out[l * (l + 1) - m] = root2 * p * sm;
      }
    }
  }
}

// The basis rows of directions (n, 3) into out (n, (order + 1)^2).
inline void basis_rows(const double* dirs, index_t n, int order, double* out) {
  const index_t k = static_cast<index_t>(order + 1) * (order + 1);
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < n; ++i)
    basis_into(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2], order, out + i * k);
}

// Sum the chunks' partial sums (chunks, size) in chunk order into out (size).
inline void sum_chunks(const std::vector<double>& partial, index_t chunks, index_t size,
                       double* out) {
  for (index_t q = 0; q < size; ++q) {
    double s = 0.0;
    for (index_t c = 0; c < chunks; ++c) s += partial[c * size + q];
    out[q] = s;
  }
}

// out (K, C) = sum_i values[i] * weights[i] * Y(d_i), in parallel chunks, without a basis
// array (K = (order + 1)^2).
template <class T>
void project(const T* values, index_t channels, const double* dirs, const double* weights,
             index_t n, int order, index_t chunks, double* out) {
  const index_t k_count = static_cast<index_t>(order + 1) * (order + 1);
  const index_t size = k_count * channels;
  std::vector<double> partial(static_cast<size_t>(chunks * size), 0.0);
  const index_t step = (n + chunks - 1) / chunks;
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    std::vector<double> y(static_cast<size_t>(k_count));
    double* part = partial.data() + c * size;
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t i = c * step; i < stop; ++i) {
      const double w = weights[i];
      if (w == 0.0) continue;
      basis_into(dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2], order, y.data());
      for (index_t k = 0; k < k_count; ++k) {
        const double yw = y[k] * w;
        for (index_t ch = 0; ch < channels; ++ch)
          part[k * channels + ch] += yw * static_cast<double>(values[i * channels + ch]);
      }
    }
  }
  sum_chunks(partial, chunks, size, out);
}

// project for order 2 with the nine polynomials written out: ~3x fewer operations than the
// recurrence, the same sums to rounding.
template <class T>
void project_order2(const T* values, index_t channels, const double* dirs, const double* weights,
                    index_t n, index_t chunks, double* out) {
  const double pi = 3.141592653589793;
  const double c0 = 0.5 / std::sqrt(pi);
  const double c1 = std::sqrt(3 / (4 * pi));
  const double c2 = std::sqrt(15 / (4 * pi));
  const double c20 = std::sqrt(5 / (16 * pi));
  const double c22 = std::sqrt(15 / (16 * pi));
  const index_t size = 9 * channels;
  std::vector<double> partial(static_cast<size_t>(chunks * size), 0.0);
  const index_t step = (n + chunks - 1) / chunks;
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    double* acc = partial.data() + c * size;
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t i = c * step; i < stop; ++i) {
      const double w = weights[i];
      const double x = dirs[3 * i], y = dirs[3 * i + 1], z = dirs[3 * i + 2];
      const double b[9] = {c0 * w,
                           c1 * y * w,
                           c1 * z * w,
                           c1 * x * w,
                           c2 * x * y * w,
                           c2 * y * z * w,
                           c20 * (3.0 * z * z - 1.0) * w,
                           c2 * x * z * w,
                           c22 * (x * x - y * y) * w};
      for (index_t ch = 0; ch < channels; ++ch) {
        const double v = static_cast<double>(values[i * channels + ch]);
        for (int k = 0; k < 9; ++k) acc[k * channels + ch] += b[k] * v;
      }
    }
  }
  sum_chunks(partial, chunks, size, out);
}

}  // namespace bakeshop::light::sh
