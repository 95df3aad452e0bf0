// The exact irradiance kernels of bakeshop/light/diffuse.py: the cone-bounded cosine sum, the
// cube-face bins of `compress` and the energy measure. Float64 throughout.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::light {

// Cones of sources for cosine_sum: members starts[g]..starts[g+1] (of the sources, or of the
// smaller cones), unit axes (G, 3), sin of the half-angle (G,) and the linear sums
// sum_j e_cj w_j (G, 3, 3).
struct Cones {
  const int64_t* starts;
  const double* axes;
  const double* sin_half;
  const double* linear;
  index_t count;
};

// out[i, c] = sum_j energy[c, j] max(0, normals[i] . dirs[:, j]) for c < 3: the cones wholly
// above the horizon of n add n . linear, those wholly below nothing, only those the horizon
// crosses are opened (first the large cones `supers`, then the small ones `groups`). `dirs`
// and `energy` are (3, N), `normals` and `out` (M, 3).
inline void cosine_sum(const double* normals, index_t m, const double* dirs, const double* energy,
                       index_t n, const Cones& groups, const Cones& supers, double* out) {
  const double* d0 = dirs;
  const double* d1 = dirs + n;
  const double* d2 = dirs + 2 * n;
  const double* e0 = energy;
  const double* e1 = energy + n;
  const double* e2 = energy + 2 * n;
#pragma omp parallel for schedule(dynamic, 16)
  for (index_t i = 0; i < m; ++i) {
    const double nx = normals[3 * i], ny = normals[3 * i + 1], nz = normals[3 * i + 2];
    double acc[3] = {0.0, 0.0, 0.0};
    for (index_t s = 0; s < supers.count; ++s) {
      const double* sa = supers.axes + 3 * s;
      double c = nx * sa[0] + ny * sa[1] + nz * sa[2];
      if (c < -supers.sin_half[s] - 1e-12) continue;
      if (c > supers.sin_half[s] + 1e-12) {
        const double* l = supers.linear + 9 * s;
        for (int k = 0; k < 3; ++k) acc[k] += nx * l[3 * k] + ny * l[3 * k + 1] + nz * l[3 * k + 2];
        continue;
      }
      for (int64_t g = supers.starts[s]; g < supers.starts[s + 1]; ++g) {
        const double* ga = groups.axes + 3 * g;
        c = nx * ga[0] + ny * ga[1] + nz * ga[2];
        if (c < -groups.sin_half[g] - 1e-12) continue;
        if (c > groups.sin_half[g] + 1e-12) {
          const double* l = groups.linear + 9 * g;
          for (int k = 0; k < 3; ++k)
            acc[k] += nx * l[3 * k] + ny * l[3 * k + 1] + nz * l[3 * k + 2];
          continue;
        }
        double a0 = 0.0, a1 = 0.0, a2 = 0.0;
        for (int64_t j = groups.starts[g]; j < groups.starts[g + 1]; ++j) {
          const double cj = std::max(nx * d0[j] + ny * d1[j] + nz * d2[j], 0.0);
          a0 += cj * e0[j];
          a1 += cj * e1[j];
          a2 += cj * e2[j];
        }
        acc[0] += a0;
        acc[1] += a1;
        acc[2] += a2;
      }
    }
    out[3 * i] = acc[0];
    out[3 * i + 1] = acc[1];
    out[3 * i + 2] = acc[2];
  }
}

// Whether the cones' starts are a non-decreasing run from 0 to `members` (each cone's
// members exist): checked before cosine_sum reads through them.
inline bool cones_valid(const int64_t* starts, index_t count, index_t members) {
  if (starts[0] != 0 || starts[count] != members) return false;
  for (index_t g = 0; g < count; ++g)
    if (starts[g + 1] < starts[g]) return false;
  return true;
}

// A private spatial hash of directions: cube-face bins, size x size per face, that nest (bin i
// at 2*size holds bins 2i and 2i+1). Not a panorama layout: faces are unoriented.
inline int64_t bin_of(double x, double y, double z, int64_t size) {
  const double ax = std::fabs(x), ay = std::fabs(y), az = std::fabs(z);
  int64_t face;
  double u, v, m;
  if (ax >= ay && ax >= az) {
    face = x > 0 ? 0 : 1, u = y, v = z, m = ax;
  } else if (ay >= az) {
    face = y > 0 ? 2 : 3, u = x, v = z, m = ay;
  } else {
    face = z > 0 ? 4 : 5, u = x, v = y, m = az;
  }
  if (m == 0.0) return 0;
  // int() truncates toward zero; u / m + 1 >= 0, so the cast is the same
  const int64_t i = std::min(static_cast<int64_t>((u / m + 1.0) * 0.5 * size), size - 1);
  const int64_t j = std::min(static_cast<int64_t>((v / m + 1.0) * 0.5 * size), size - 1);
  return (face * size + j) * size + i;
}

// out[k] = the bin at `size` of texel k (of all texels, or of those listed in subset).
inline void bins(const double* dirs, index_t n_dirs, const int64_t* subset, index_t n_subset,
                 int64_t size, int64_t* out) {
  const index_t count = n_subset > 0 ? n_subset : n_dirs;
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t k = 0; k < count; ++k) {
    const int64_t t = n_subset > 0 ? subset[k] : k;
    if (t < 0 || t >= n_dirs) {
      errors.fail("bins: a texel index out of range");
      continue;
    }
    out[k] = bin_of(dirs[3 * t], dirs[3 * t + 1], dirs[3 * t + 2], size);
  }
  errors.check();
}

// Row b of `sums` (n_bins, channels + 5) sums, over texel k (of all texels, or of those
// listed in subset) with index[k] == b: its energy per channel, its weight (sum over the
// first `colour` channels of |energy|), weight * direction, and a count. Chunks of texels run
// in parallel into partial sums, added in chunk order. With size > 0, index[k] is first set
// to the texel's bin at that size.
template <class T>
void accumulate(const T* values, index_t channels, index_t n_texels, const double* dirs,
                const double* omega, const int64_t* subset, index_t n_subset, int64_t* index,
                index_t count, index_t n_bins, index_t chunks, int64_t size, index_t colour,
                double* sums) {
  const index_t row = channels + 5;
  std::vector<double> partial(static_cast<size_t>(chunks * n_bins * row), 0.0);
  const index_t step = (count + chunks - 1) / chunks;
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    double* part = partial.data() + c * n_bins * row;
    const index_t stop = std::min(count, (c + 1) * step);
    for (index_t k = c * step; k < stop; ++k) {
      const int64_t t = n_subset > 0 ? subset[k] : k;
      if (t < 0 || t >= n_texels) {
        errors.fail("accumulate: a texel index out of range");
        break;
      }
      if (size > 0) index[k] = bin_of(dirs[3 * t], dirs[3 * t + 1], dirs[3 * t + 2], size);
      const int64_t b = index[k];
      if (b < 0 || b >= n_bins) {
        errors.fail("accumulate: a bin index out of range");
        break;
      }
      double* p = part + b * row;
      p[channels + 4] += 1.0;
      const double w = omega[t];
      if (w == 0.0) continue;
      double total = 0.0;
      for (index_t ch = 0; ch < channels; ++ch) {
        const double e = static_cast<double>(values[t * channels + ch]) * w;
        p[ch] += e;
        if (ch < colour) total += std::fabs(e);
      }
      p[channels] += total;
      for (int a = 0; a < 3; ++a) p[channels + 1 + a] += total * dirs[3 * t + a];
    }
  }
  errors.check();
  const index_t size_out = n_bins * row;
#pragma omp parallel for schedule(static)
  for (index_t q = 0; q < size_out; ++q) {
    double s = 0.0;
    for (index_t c = 0; c < chunks; ++c) s += partial[c * size_out + q];
    sums[q] = s;
  }
}

// sum over texels and the colour channels of |L omega|: compress's measure of energy, in 16
// chunks added in order.
template <class T>
double energy(const T* values, index_t channels, index_t n, const double* omega, index_t colour) {
  constexpr index_t chunks = 16;
  double partial[chunks];
  const index_t step = (n + chunks - 1) / chunks;
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < chunks; ++c) {
    double acc = 0.0;
    const index_t stop = std::min(n, (c + 1) * step);
    for (index_t t = c * step; t < stop; ++t)
      for (index_t ch = 0; ch < colour; ++ch)
        acc += std::fabs(static_cast<double>(values[t * channels + ch]) * omega[t]);
    partial[c] = acc;
  }
  double total = 0.0;
  for (index_t c = 0; c < chunks; ++c) total += partial[c];
  return total;
}

}  // namespace bakeshop::light
