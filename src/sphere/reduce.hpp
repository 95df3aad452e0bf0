// The exact reductions and the supersampled area filter's sums (bakeshop/sphere/reductions.py,
// bakeshop/sphere/area.py): weighted means of k x k blocks, the bright texels' statistics.
#pragma once

#include <algorithm>
#include <limits>
#include <memory>

#include "common/kernel.hpp"

namespace bakeshop::sphere {

// out[J, I] = sum(omega L) / sum(omega) over the k x k fine texels of (J, I), in float64; 0
// where the block has no solid angle. omega's rows repeat (period: its row count), so a cube
// face's table serves its six faces. fine is (>= rows k, >= width k, channels); omega's rows
// are `omega_width` long (>= width k).
template <class T, class W>
inline void box_reduce(const T* fine, index_t fine_rows, index_t fine_width, const W* omega,
                       index_t period, index_t omega_width, index_t k, T* out, index_t rows,
                       index_t width, index_t channels) {
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < rows; ++r) {
    double acc_small[8];
    double* acc = acc_small;
    std::unique_ptr<double[]> heap;
    if (channels > 8) {
      heap.reset(new double[channels]);
      acc = heap.get();
    }
    for (index_t i = 0; i < width; ++i) {
      std::fill(acc, acc + channels, 0.0);
      double total = 0.0;
      for (index_t y = r * k; y < (r + 1) * k; ++y) {
        const W* om = omega + (y % period) * omega_width;
        const T* f = fine + y * fine_width * channels;
        for (index_t x = i * k; x < (i + 1) * k; ++x) {
          const W w = om[x];
          total += w;
          for (index_t c = 0; c < channels; ++c) acc[c] += w * f[x * channels + c];
        }
      }
      for (index_t c = 0; c < channels; ++c)
        out[(r * width + i) * channels + c] = static_cast<T>(total > 0 ? acc[c] / total : 0.0);
    }
  }
}

// peaks[t]: texel t's brightest channel, -inf without solid angle; stats += [sum peak omega,
// sum omega, largest peak] (one thread, in texel order).
template <class T, class W>
inline void peak_stats(const T* values, index_t n, index_t channels, const W* omega,
                       double* stats, T* peaks) {
  for (index_t t = 0; t < n; ++t) {
    peaks[t] = -std::numeric_limits<T>::infinity();
    if (omega[t] > 0) {
      T peak = values[t * channels];
      for (index_t c = 1; c < channels; ++c) peak = std::max(peak, values[t * channels + c]);
      peaks[t] = peak;
      stats[0] += peak * omega[t];
      stats[1] += omega[t];
      stats[2] = std::max<double>(stats[2], peak);
    }
  }
}

}  // namespace bakeshop::sphere
