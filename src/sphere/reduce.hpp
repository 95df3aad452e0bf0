// The exact reductions and the supersampled area filter's sums (bakeshop/sphere/reductions.py,
// bakeshop/sphere/area.py): weighted means of k x k blocks, the bright texels' statistics, the
// fused supersampling of a cube.
#pragma once

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/gather.hpp"
#include "sphere/maps.hpp"

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

namespace supersample_detail {

// Source coordinates (face, x, y) of cube face f's point (sc, tc) (rot 3x3 row-major: R^T d).
inline Coords source_xy(int skind, index_t sh, index_t sw, const double* rot, index_t f,
                        double sc, double tc) {
  const double(*b)[3] = FACE_BASES[f];
  const double x = b[0][0] + sc * b[1][0] + tc * b[2][0];
  const double y = b[0][1] + sc * b[1][1] + tc * b[2][1];
  const double z = b[0][2] + sc * b[1][2] + tc * b[2][2];
  const Vec3 r = rotate(rot, x, y, z);
  if (skind == LATLONG) {
    double u, v;
    latlong_xy(sh, sw, r.x, r.y, r.z, u, v);
    return {0.0, u, v};
  }
  return coordinates(skind, sh, sw, r.x, r.y, r.z);
}

// acc += weight x the seam-aware bilinear value at (f, x, y), every texel clamped at clamp (a
// cube corner's missing texel is the mean of the other three); false for a texel beyond src.
template <class T>
inline bool add_bilinear(int kind, index_t h, index_t w, const T* src, index_t n_src,
                         index_t channels, double clamp, double f, double x, double y,
                         double weight, double* acc) {
  const double xs = x - 0.5, ys = y - 0.5;
  const double x0 = std::floor(xs), y0 = std::floor(ys);
  const double fx = xs - x0, fy = ys - y0;
  const index_t i0 = trunc_index(x0), j0 = trunc_index(y0);
  const index_t base = block(kind, h, w, f, i0, j0, 2);
  index_t t[4];
  if (base >= 0) {
    t[0] = base;
    t[1] = base + 1;
    t[2] = base + w;
    t[3] = base + w + 1;
  } else {
    t[0] = resolve(kind, h, w, f, i0, j0, x);
    t[1] = resolve(kind, h, w, f, i0 + 1, j0, x);
    t[2] = resolve(kind, h, w, f, i0, j0 + 1, x);
    t[3] = resolve(kind, h, w, f, i0 + 1, j0 + 1, x);
  }
  for (int k = 0; k < 4; ++k)
    if (t[k] >= n_src) return false;
  const double w0 = (1.0 - fx) * (1.0 - fy) * weight, w1 = fx * (1.0 - fy) * weight;
  const double w2 = (1.0 - fx) * fy * weight, w3 = fx * fy * weight;
  const bool missing = t[0] < 0 || t[1] < 0 || t[2] < 0 || t[3] < 0;
  for (index_t c = 0; c < channels; ++c) {
    double v[4];
    for (int k = 0; k < 4; ++k)
      v[k] = t[k] >= 0 ? std::min(static_cast<double>(src[t[k] * channels + c]), clamp) : 0.0;
    if (missing) {
      const double m = (v[0] + v[1] + v[2] + v[3]) / 3.0;
      for (int k = 0; k < 4; ++k) v[k] = t[k] >= 0 ? v[k] : m;
    }
    acc[c] += w0 * v[0] + w1 * v[1] + w2 * v[2] + w3 * v[3];
  }
  return true;
}

}  // namespace supersample_detail

// Where a cube texel's samples' source coordinates are interpolated from its centre's (k >= 3
// samples a side), they may be this far (in source texels) from the exact ones.
constexpr double SUPERSAMPLE_LINEAR_TOLERANCE = 0.05;

// out[f, j, i] = sum_s w_s R(p_s) / sum_s w_s over the k x k sample points of cube texel
// (f, i, j), w_s = (1 + sc^2 + tc^2)^-1.5, R the bilinear lookup of the source (n_src,
// channels) clamped at clamp; out (6 size, size, channels). With k >= 3 the samples' source
// coordinates are the centre's plus the map's derivatives times their offsets, where that is
// within SUPERSAMPLE_LINEAR_TOLERANCE of exact.
template <class T>
inline void supersample_cube(int skind, index_t sh, index_t sw, const T* src, index_t n_src,
                             index_t channels, double clamp, index_t size, index_t k,
                             const double* rot, T* out, Errors& errors) {
  using namespace supersample_detail;
  const double step = 2.0 / static_cast<double>(size * k);
  const double half = 0.5 * static_cast<double>(k - 1);
#pragma omp parallel for schedule(static)
  for (index_t row = 0; row < 6 * size; ++row) {
    const index_t f = row / size;
    const index_t j = row - f * size;
    std::vector<double> acc(static_cast<size_t>(channels));
    for (index_t i = 0; i < size; ++i) {
      std::fill(acc.begin(), acc.end(), 0.0);
      double total = 0.0;
      const double sc0 = (static_cast<double>(i * k) + 0.5 + half) * step - 1.0;
      const double tc0 = (static_cast<double>(j * k) + 0.5 + half) * step - 1.0;
      bool linear = false;
      Coords c0{}, c1{}, c2{}, c3{};
      double dus = 0, dvs = 0, dut = 0, dvt = 0;
      if (k >= 3) {
        c0 = source_xy(skind, sh, sw, rot, f, sc0, tc0);
        c1 = source_xy(skind, sh, sw, rot, f, sc0 + step, tc0);
        c2 = source_xy(skind, sh, sw, rot, f, sc0, tc0 + step);
        c3 = source_xy(skind, sh, sw, rot, f, sc0 - half * step, tc0 - half * step);
        dus = c1.x - c0.x;
        dvs = c1.y - c0.y;
        dut = c2.x - c0.x;
        dvt = c2.y - c0.y;
        const double pu = c0.x - half * (dus + dut);
        const double pv = c0.y - half * (dvs + dvt);
        linear = c0.f == c1.f && c0.f == c2.f && c0.f == c3.f &&
                 std::fabs(pu - c3.x) < SUPERSAMPLE_LINEAR_TOLERANCE &&
                 std::fabs(pv - c3.y) < SUPERSAMPLE_LINEAR_TOLERANCE;
      }
      for (index_t a = 0; a < k; ++a) {
        const double tc = (static_cast<double>(j * k + a) + 0.5) * step - 1.0;
        for (index_t b = 0; b < k; ++b) {
          const double sc = (static_cast<double>(i * k + b) + 0.5) * step - 1.0;
          const double q = 1.0 + sc * sc + tc * tc;
          const double w = 1.0 / (q * std::sqrt(q));
          Coords s;
          if (linear) {
            const double bh = static_cast<double>(b) - half, ah = static_cast<double>(a) - half;
            s = {c0.f, c0.x + bh * dus + ah * dut, c0.y + bh * dvs + ah * dvt};
          } else {
            s = source_xy(skind, sh, sw, rot, f, sc, tc);
          }
          total += w;
          if (!add_bilinear(skind, sh, sw, src, n_src, channels, clamp, s.f, s.x, s.y, w,
                            acc.data()))
            errors.fail("supersample_cube: a tap beyond the source");
        }
      }
      for (index_t c = 0; c < channels; ++c)
        out[(row * size + i) * channels + c] = static_cast<T>(acc[c] / total);
    }
  }
}

}  // namespace bakeshop::sphere
