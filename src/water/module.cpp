// bakeshop.water._native: the kernels of bakeshop.water (ocean spectra and normals, mode
// amplitudes, Gerstner sums, cascade lookups, the ripple wave equation, preview shading).
#include <complex>

#include "common/bind.hpp"
#include "water/amplitudes.hpp"
#include "water/cascades.hpp"
#include "water/gerstner.hpp"
#include "water/ocean.hpp"
#include "water/ripples.hpp"
#include "water/textures.hpp"

using namespace bakeshop;

namespace {

template <class T>
void bind_ocean(nb::module_& m) {
  using C = std::complex<T>;
  m.def(
      "loop_spectra",
      [](In<C, 2> a, In<C, 2> b, In<int64_t, 2> cycles, In<int64_t, 1> frames, In<C, 1> table,
         In<C, 3> mult, Out<C, 4> out) {
        const size_t rows = a.shape(0), cols = a.shape(1), nf = frames.shape(0),
                     np_ = mult.shape(0);
        require(shape_is(b, {rows, cols}) && shape_is(cycles, {rows, cols}) &&
                    shape_is(mult, {np_, rows, cols}) && shape_is(out, {nf, np_, rows, cols}),
                "loop_spectra: a, b, cycles (R, C), mult (P, R, C), out (F, P, R, C)");
        require(table.shape(0) > 0, "loop_spectra: the phase table is empty");
        water::loop_spectra<T>(a.data(), b.data(), cycles.data(), rows, cols, frames.data(), nf,
                               table.data(), table.shape(0), mult.data(), np_, out.data());
      },
      "a"_a, "b"_a, "cycles"_a, "frames"_a, "table"_a, "mult"_a, "out"_a.noconvert(),
      release_gil());
  m.def(
      "free_spectra",
      [](In<C, 2> a, In<C, 2> b, In<double, 2> omega, In<double, 1> times, In<C, 3> mult,
         Out<C, 4> out) {
        const size_t rows = a.shape(0), cols = a.shape(1), nt = times.shape(0),
                     np_ = mult.shape(0);
        require(shape_is(b, {rows, cols}) && shape_is(omega, {rows, cols}) &&
                    shape_is(mult, {np_, rows, cols}) && shape_is(out, {nt, np_, rows, cols}),
                "free_spectra: a, b, omega (R, C), mult (P, R, C), out (T, P, R, C)");
        water::free_spectra<T>(a.data(), b.data(), omega.data(), rows, cols, times.data(), nt,
                               mult.data(), np_, out.data());
      },
      "a"_a, "b"_a, "omega"_a, "times"_a, "mult"_a, "out"_a.noconvert(), release_gil());
  // the normals read the batch's spectra (F, P, R, C) after the inverse FFT, pairs by index
  m.def(
      "normals",
      [](In<C, 4> spectra, size_t slope, size_t stretch, size_t height, double lam,
         Out<T, 4> out) {
        const size_t f = spectra.shape(0), np_ = spectra.shape(1), r = spectra.shape(2),
                     c = spectra.shape(3);
        require(slope < np_ && stretch < np_ && height < np_,
                "normals: the pair indices must be below the spectra's pair count");
        require(shape_is(out, {f, r, c, 3}), "normals: spectra (F, P, R, C) and out (F, R, C, 3)");
        const C* base = spectra.data();
        const index_t plane = r * c;
        water::normals<T>(base + slope * plane, base + stretch * plane, base + height * plane,
                          np_ * plane, f, r, c, lam, out.data());
      },
      "spectra"_a, "slope"_a, "stretch"_a, "height"_a, "lam"_a, "out"_a.noconvert(),
      release_gil());
  m.def(
      "flat_normals",
      [](In<C, 4> spectra, size_t slope, Out<T, 4> out) {
        const size_t f = spectra.shape(0), np_ = spectra.shape(1), r = spectra.shape(2),
                     c = spectra.shape(3);
        require(slope < np_, "flat_normals: the pair index must be below the pair count");
        require(shape_is(out, {f, r, c, 3}),
                "flat_normals: spectra (F, P, R, C) and out (F, R, C, 3)");
        const index_t plane = r * c;
        water::flat_normals<T>(spectra.data() + slope * plane, np_ * plane, f, r, c, out.data());
      },
      "spectra"_a, "slope"_a, "out"_a.noconvert(), release_gil());
}

bool neighbours_ok(const In<int64_t, 1>& a, size_t n) {
  if (a.shape(0) != n) return false;
  for (size_t i = 0; i < n; ++i)
    if (a.data()[i] < 0 || static_cast<size_t>(a.data()[i]) >= n) return false;
  return true;
}

}  // namespace

NB_MODULE(_native, m) {
  m.attr("FOLD_FLOOR") = water::kFoldFloor;

  m.def("splitmix64", &water::splitmix64, "z"_a);
  m.def(
      "mode_normals",
      [](uint64_t seed, In<int64_t, 1> mx, In<int64_t, 1> my, Out<double, 2> out) {
        const size_t n = mx.shape(0);
        require(my.shape(0) == n && shape_is(out, {n, 2}),
                "mode_normals: mx, my (M,) and out (M, 2)");
        water::mode_normals(seed, mx.data(), my.data(), n, out.data());
      },
      "seed"_a, "mx"_a, "my"_a, "out"_a.noconvert(), release_gil());

  // complex64 / float32 and complex128 / float64 frames (ocean_frames' dtype)
  bind_ocean<float>(m);
  bind_ocean<double>(m);

  m.def(
      "gerstner_sums",
      [](In<double, 1> amp, In<double, 1> kx, In<double, 1> ky, In<double, 1> phase,
         In<double, 1> x, In<double, 1> y, Out<double, 2> out) {
        const size_t w = amp.shape(0), p = x.shape(0);
        require(kx.shape(0) == w && ky.shape(0) == w && phase.shape(0) == w &&
                    y.shape(0) == p && shape_is(out, {p, 8}),
                "gerstner_sums: amp, kx, ky, phase (M,), x, y (N,) and out (N, 8)");
        water::gerstner_sums(amp.data(), kx.data(), ky.data(), phase.data(), w, x.data(),
                             y.data(), p, out.data());
      },
      "amp"_a, "kx"_a, "ky"_a, "phase"_a, "x"_a, "y"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "sample_add",
      [](In<double, 3> field, double size, In<double, 1> x, In<double, 1> y, double weight,
         Out<double, 2> out) {
        const size_t n = field.shape(0), ch = field.shape(2), p = x.shape(0);
        require(n > 0 && field.shape(1) == n, "sample_add: the field must be (N, N, C), N > 0");
        require(y.shape(0) == p && shape_is(out, {p, ch}),
                "sample_add: x, y (M,) and out (M, C) of a field (N, N, C)");
        water::sample_add(field.data(), n, ch, size, x.data(), y.data(), p, weight, out.data());
      },
      "field"_a, "size"_a, "x"_a, "y"_a, "weight"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "laplacian_step",
      [](Out<double, 2> h, Out<double, 2> v, double c2, double damp_a, double damp_b, double dt,
         double dx2, In<double, 2> force, In<int64_t, 1> rm, In<int64_t, 1> rp,
         In<int64_t, 1> cm, In<int64_t, 1> cp) {
        const size_t rows = h.shape(0), cols = h.shape(1);
        require(shape_is(v, {rows, cols}) && shape_is(force, {rows, cols}),
                "laplacian_step: h, v and force must have one shape");
        require(neighbours_ok(rm, rows) && neighbours_ok(rp, rows) && neighbours_ok(cm, cols) &&
                    neighbours_ok(cp, cols),
                "laplacian_step: the neighbours must be indices of the grid's rows and columns");
        water::laplacian_step(h.data(), v.data(), rows, cols, c2, damp_a, damp_b, dt, dx2,
                              force.data(), rm.data(), rp.data(), cm.data(), cp.data());
      },
      "h"_a.noconvert(), "v"_a.noconvert(), "c2"_a, "damp_a"_a, "damp_b"_a, "dt"_a, "dx2"_a,
      "force"_a, "rm"_a, "rp"_a, "cm"_a, "cp"_a, release_gil());

  m.def(
      "shade",
      [](In<float, 3> normals, In<float, 1> view, In<float, 1> sun, Out<float, 3> out) {
        const size_t h = normals.shape(0), w = normals.shape(1);
        require(normals.shape(2) == 3 && view.shape(0) == 3 && sun.shape(0) == 3 &&
                    shape_is(out, {h, w, 3}),
                "shade: normals and out (H, W, 3), view and sun (3,)");
        water::shade(normals.data(), h, w, view.data(), sun.data(), out.data());
      },
      "normals"_a, "view"_a, "sun"_a, "out"_a.noconvert(), release_gil());
}
