// bakeshop.image._native: the kernels of bakeshop.image (display curves, 8-bit sRGB, the area
// resize filters).
#include "common/bind.hpp"
#include "image/display.hpp"
#include "image/resize.hpp"

using namespace bakeshop;

namespace {

// Rows of samples, each row contiguous, rows any distance apart (a window of an image).
template <class T>
using Rows = nb::ndarray<const T, nb::numpy, nb::ndim<2>, nb::device::cpu>;

template <class T>
void bind_display(nb::module_& m) {
  m.def(
      "srgb_apply",
      [](In<T, 1> a, bool decode, Out<T, 1> out) {
        require(out.shape(0) == a.shape(0), "srgb_apply: out must have the shape of a");
        image::srgb_apply(a.data(), static_cast<index_t>(a.shape(0)), decode, out.data());
      },
      "a"_a.noconvert(), "decode"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "srgb8",
      [](In<T, 2> a, int64_t colour, bool dither, uint64_t seed, Out<uint8_t, 2> out) {
        require(out.shape(0) == a.shape(0) && out.shape(1) == a.shape(1),
                "srgb8: out must have the shape of a");
        require(colour >= 0, "srgb8: colour must be >= 0");
        image::srgb8(a.data(), static_cast<index_t>(a.shape(0)), static_cast<index_t>(a.shape(1)),
                     colour, dither, seed, out.data());
      },
      "a"_a.noconvert(), "colour"_a, "dither"_a, "seed"_a, "out"_a.noconvert(), release_gil());
}

template <class S>
void bind_box(nb::module_& m) {
  m.def(
      "box",
      [](Rows<S> src, int64_t fy, int64_t fx, Out<S, 3> out) {
        const index_t rows = out.shape(0), width = out.shape(1), channels = out.shape(2);
        require(fy >= 1 && fx >= 1, "box: the factors must be >= 1");
        require(src.shape(0) == 0 || src.stride(1) == 1, "box: src's rows must be contiguous");
        require(static_cast<index_t>(src.shape(0)) >= rows * fy &&
                    static_cast<index_t>(src.shape(1)) >= width * fx * channels,
                "box: src does not cover the blocks of out");
        image::box(src.data(), static_cast<index_t>(src.stride(0)), fy, fx, rows, width, channels,
                   out.data());
      },
      "src"_a.noconvert(), "fy"_a, "fx"_a, "out"_a.noconvert(), release_gil());
}

template <class S, class O>
void bind_separable(nb::module_& m) {
  m.def(
      "separable",
      [](Rows<S> src, In<int64_t, 1> ry, In<int64_t, 1> ky, In<double, 1> wy, In<int64_t, 1> rx,
         In<int64_t, 1> kx, In<double, 1> wx, Out<O, 3> out) {
        const index_t rows = out.shape(0), width = out.shape(1), channels = out.shape(2);
        const index_t h = src.shape(0), n = src.shape(1);
        require(h == 0 || src.stride(1) == 1, "separable: src's rows must be contiguous");
        require(channels >= 1 && n % channels == 0,
                "separable: src's rows must hold whole texels of out's channels");
        require(static_cast<index_t>(ry.shape(0)) == rows + 1 &&
                    static_cast<index_t>(rx.shape(0)) == width + 1,
                "separable: the CSR rows must match out's shape");
        require(ky.shape(0) == wy.shape(0) && kx.shape(0) == wx.shape(0),
                "separable: indices and weights must have the same length");
        require(image::csr_ok(ry.data(), rows, ky.data(), ky.shape(0), h) &&
                    image::csr_ok(rx.data(), width, kx.data(), kx.shape(0), n / channels),
                "separable: a weight indexes outside the source");
        image::separable(src.data(), static_cast<index_t>(src.stride(0)), n, ry.data(), ky.data(),
                         wy.data(), rx.data(), kx.data(), wx.data(), rows, width, channels,
                         out.data());
      },
      "src"_a.noconvert(), "ry"_a, "ky"_a, "wy"_a, "rx"_a, "kx"_a, "wx"_a, "out"_a.noconvert(),
      release_gil());
}

}  // namespace

NB_MODULE(_native, m) {
  bind_display<float>(m);
  bind_display<double>(m);
  bind_box<float>(m);
  bind_box<double>(m);
  bind_separable<float, float>(m);
  bind_separable<float, double>(m);
  bind_separable<double, float>(m);
  bind_separable<double, double>(m);
}
