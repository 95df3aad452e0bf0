// Ocean frame synthesis (bakeshop/water/ocean.py): the spectra of a batch of frames (looped
// through a phase table, or at free times) and the normals of the displaced surface. The
// complex arithmetic is written out (CPython's and the old JIT's product: ac - bd, ad + bc) so that
// the results are the old JIT's bit for bit.
#pragma once

#include <cmath>
#include <complex>
#include <cstdint>

#include "common/kernel.hpp"

namespace bakeshop::water {

//: A folded texel (J <= 0) has no outward normal; its normal's z is clamped to this.
constexpr double kFoldFloor = 1e-3;

namespace detail {

template <class R>
struct Cx {
  R re, im;
};

template <class R>
inline Cx<R> mul(Cx<R> z, Cx<R> w) {
  const R ac = z.re * w.re, bd = z.im * w.im, ad = z.re * w.im, bc = z.im * w.re;
  return {ac - bd, ad + bc};
}

template <class R>
inline Cx<R> add(Cx<R> z, Cx<R> w) {
  return {z.re + w.re, z.im + w.im};
}

template <class R, class T>
inline Cx<R> cx(const std::complex<T>& z) {
  return {static_cast<R>(z.real()), static_cast<R>(z.imag())};
}

// Python's float `x % y` (the remainder takes the sign of y).
inline double py_mod(double x, double y) {
  double m = std::fmod(x, y);
  if (m != 0.0) {
    if ((y < 0) != (m < 0)) m += y;
  } else {
    m = std::copysign(0.0, y);
  }
  return m;
}

// Python's integer `a % n` for n > 0.
inline int64_t floor_mod(int64_t a, int64_t n) {
  const int64_t m = a % n;
  return m < 0 ? m + n : m;
}

}  // namespace detail

// out[f, p] = (a P + b conj(P)) mult[p] with P = table[(n f) mod F]; all complex of T.
template <class T>
void loop_spectra(const std::complex<T>* a, const std::complex<T>* b, const int64_t* cycles,
                  index_t rows, index_t cols, const int64_t* frames, index_t n_frames,
                  const std::complex<T>* table, index_t count, const std::complex<T>* mult,
                  index_t npairs, std::complex<T>* out) {
  using detail::Cx;
  const index_t plane = rows * cols;
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < rows; ++r) {
    for (index_t c = 0; c < cols; ++c) {
      const index_t rc = r * cols + c;
      const Cx<T> ar = detail::cx<T>(a[rc]);
      const Cx<T> br = detail::cx<T>(b[rc]);
      if (ar.re == 0 && ar.im == 0 && br.re == 0 && br.im == 0) {
        for (index_t f = 0; f < n_frames; ++f)
          for (index_t p = 0; p < npairs; ++p) out[(f * npairs + p) * plane + rc] = 0;
        continue;
      }
      const int64_t nc = detail::floor_mod(cycles[rc], count);
      for (index_t f = 0; f < n_frames; ++f) {
        const Cx<T> ph = detail::cx<T>(table[(nc * detail::floor_mod(frames[f], count)) % count]);
        const Cx<T> h = detail::add(detail::mul(ar, ph), detail::mul(br, Cx<T>{ph.re, -ph.im}));
        for (index_t p = 0; p < npairs; ++p) {
          const Cx<T> v = detail::mul(h, detail::cx<T>(mult[p * plane + rc]));
          out[(f * npairs + p) * plane + rc] = std::complex<T>(v.re, v.im);
        }
      }
    }
  }
}

// out[f, p] = (a e^{-i w t_f} + b e^{i w t_f}) mult[p] for arbitrary times; the phase and the
// products in double (as the old JIT promoted them), stored as complex of T.
template <class T>
void free_spectra(const std::complex<T>* a, const std::complex<T>* b, const double* omega,
                  index_t rows, index_t cols, const double* times, index_t n_times,
                  const std::complex<T>* mult, index_t npairs, std::complex<T>* out) {
  using detail::Cx;
  const index_t plane = rows * cols;
  const double two_pi = 2.0 * M_PI;
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < rows; ++r) {
    for (index_t c = 0; c < cols; ++c) {
      const index_t rc = r * cols + c;
      const Cx<double> ar = detail::cx<double>(a[rc]);
      const Cx<double> br = detail::cx<double>(b[rc]);
      for (index_t f = 0; f < n_times; ++f) {
        const double angle = -detail::py_mod(omega[rc] * times[f], two_pi);
        const Cx<double> ph{std::cos(angle), std::sin(angle)};
        const Cx<double> h =
            detail::add(detail::mul(ar, ph), detail::mul(br, Cx<double>{ph.re, -ph.im}));
        for (index_t p = 0; p < npairs; ++p) {
          const Cx<double> v = detail::mul(h, detail::cx<double>(mult[p * plane + rc]));
          out[(f * npairs + p) * plane + rc] =
              std::complex<T>(static_cast<T>(v.re), static_cast<T>(v.im));
        }
      }
    }
  }
}

// Unit normals of the displaced surface from the packed FFT outputs (slope = hx + i hy,
// stretch = dxx + i dyy, height's imaginary part = dxy): planes of `rows * cols` texels, frame f's
// at f * stride, into out (F, R, C, 3).
template <class T>
void normals(const std::complex<T>* slope, const std::complex<T>* stretch,
             const std::complex<T>* height, index_t stride, index_t frames, index_t rows,
             index_t cols, double lam, T* out) {
#pragma omp parallel for schedule(static)
  for (index_t fr = 0; fr < frames * rows; ++fr) {
    const index_t f = fr / rows, r = fr % rows;
    for (index_t c = 0; c < cols; ++c) {
      const index_t i = f * stride + r * cols + c;
      const index_t o = 3 * (fr * cols + c);
      const double hx = slope[i].real();
      const double hy = slope[i].imag();
      const double dxx = lam * static_cast<double>(stretch[i].real());
      const double dyy = lam * static_cast<double>(stretch[i].imag());
      const double dxy = lam * static_cast<double>(height[i].imag());
      const double nx = -hx * (1.0 + dyy) + dxy * hy;
      const double ny = -hy * (1.0 + dxx) + dxy * hx;
      double nz = (1.0 + dxx) * (1.0 + dyy) - dxy * dxy;
      if (nz < kFoldFloor) nz = kFoldFloor;
      const double s = 1.0 / std::sqrt(nx * nx + ny * ny + nz * nz);
      out[o] = static_cast<T>(nx * s);
      out[o + 1] = static_cast<T>(ny * s);
      out[o + 2] = static_cast<T>(nz * s);
    }
  }
}

// Unit normals (-hx, -hy, 1) / |.| of the undisplaced surface (planes as for `normals`); the
// squares summed in T (as the old JIT typed them), the rest in double.
template <class T>
void flat_normals(const std::complex<T>* slope, index_t stride, index_t frames, index_t rows,
                  index_t cols, T* out) {
#pragma omp parallel for schedule(static)
  for (index_t fr = 0; fr < frames * rows; ++fr) {
    const index_t f = fr / rows, r = fr % rows;
    for (index_t c = 0; c < cols; ++c) {
      const index_t i = f * stride + r * cols + c;
      const index_t o = 3 * (fr * cols + c);
      const T hx = slope[i].real();
      const T hy = slope[i].imag();
      const T squares = hx * hx + hy * hy;
      const double s = 1.0 / std::sqrt(static_cast<double>(squares) + 1.0);
      out[o] = static_cast<T>(-static_cast<double>(hx) * s);
      out[o + 1] = static_cast<T>(-static_cast<double>(hy) * s);
      out[o + 2] = static_cast<T>(s);
    }
  }
}

}  // namespace bakeshop::water
