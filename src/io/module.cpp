// bakeshop.io._native: the codecs' kernels.
#include <nanobind/stl/tuple.h>

#include <tuple>

#include "common/bind.hpp"
#include "io/half.hpp"
#include "io/ldr.hpp"
#include "io/quantize.hpp"
#include "io/rgbe.hpp"
#include "io/tga.hpp"

using namespace bakeshop;

namespace {

// A float32 (H, W, C) output with any strides (the flipped and transposed views of a read).
using Strided = nb::ndarray<float, nb::numpy, nb::ndim<3>, nb::device::cpu>;

template <class T>
void bind_quantize(nb::module_& m) {
  m.def(
      "quantize",
      [](In<float, 1> values, int64_t top, Out<T, 1> out) {
        require(out.shape(0) == values.shape(0), "quantize: out must have the size of values");
        require(0 <= top && top <= static_cast<int64_t>(T(~T(0))),
                "quantize: top is beyond the output's samples");
        io::quantize<T>(values.data(), static_cast<index_t>(values.shape(0)), static_cast<T>(top),
                        out.data());
      },
      "values"_a, "top"_a, "out"_a.noconvert(), release_gil());
}

}  // namespace

NB_MODULE(_native, m) {
  m.def(
      "half_planes",
      [](In<uint32_t, 3> bits, Out<uint16_t, 3> out) {
        const index_t h = bits.shape(0), w = bits.shape(1), c = bits.shape(2);
        require(out.shape(0) == static_cast<size_t>(c) && out.shape(1) == static_cast<size_t>(h) &&
                    out.shape(2) == static_cast<size_t>(w),
                "half_planes: out must be (C, H, W) of bits (H, W, C)");
        io::half_planes(bits.data(), h, w, c, out.data());
      },
      "bits"_a, "out"_a.noconvert(), release_gil());

  // --- Radiance RGBE ---------------------------------------------------------------------------
  m.def(
      "rgbe_decode",
      [](In<uint8_t, 1> data, int64_t pos, int64_t nscan, int64_t scanlen, Strided out,
         In<double, 1> factors, bool dry) {
        require(pos >= 0 && nscan >= 0 && scanlen >= 1, "rgbe_decode: bad position or sizes");
        require(factors.shape(0) >= 3, "rgbe_decode: factors must hold 3 numbers");
        if (!dry)
          require(out.shape(0) >= static_cast<size_t>(nscan) &&
                      out.shape(1) >= static_cast<size_t>(scanlen) && out.shape(2) >= 3,
                  "rgbe_decode: out must hold (nscan, scanlen, 3) pixels");
        const io::Strided3 view{out.data(), out.stride(0), out.stride(1), out.stride(2)};
        const io::RgbeResult r =
            io::rgbe_decode(data.data(), static_cast<index_t>(data.shape(0)), pos, nscan, scanlen,
                            view, factors.data(), dry);
        return std::make_tuple(r.status, static_cast<int64_t>(r.scanline),
                               static_cast<int64_t>(r.pos));
      },
      "data"_a, "pos"_a, "nscan"_a, "scanlen"_a, "out"_a.noconvert(), "factors"_a, "dry"_a,
      release_gil());
  m.def(
      "rgbe_scan",
      [](In<uint8_t, 1> data, int64_t pos, int64_t scanlen, int64_t count, Out<int64_t, 1> starts,
         int64_t first) {
        require(pos >= 0 && scanlen >= 1 && count >= 0, "rgbe_scan: bad position or sizes");
        require(starts.shape(0) >= static_cast<size_t>(count),
                "rgbe_scan: starts must hold count offsets");
        const io::RgbeWalk w = io::rgbe_scan(data.data(), static_cast<index_t>(data.shape(0)), pos,
                                             scanlen, count, starts.data(), first);
        return std::make_tuple(static_cast<int64_t>(w.walked), static_cast<int64_t>(w.end),
                               w.status);
      },
      "data"_a, "pos"_a, "scanlen"_a, "count"_a, "starts"_a.noconvert(), "first"_a,
      release_gil());
  m.def(
      "rgbe_encode",
      [](In<float, 3> image, bool rle, int64_t block_rows, Out<uint8_t, 1> buf,
         Out<int64_t, 1> starts, Out<int64_t, 1> stops) {
        const index_t h = image.shape(0), w = image.shape(1), c = image.shape(2);
        require(c == 1 || c == 3, "rgbe_encode: the image must have 1 or 3 channels");
        require(!rle || (io::kRleMin <= w && w <= io::kRleMax),
                "rgbe_encode: run-length scanlines must be 8 to 32767 pixels");
        require(block_rows >= 1, "rgbe_encode: block_rows must be positive");
        const index_t blocks = (h + block_rows - 1) / block_rows;
        require(buf.shape(0) >= static_cast<size_t>(h * io::rgbe_line_bytes(w, rle)),
                "rgbe_encode: buf is smaller than the worst case");
        require(starts.shape(0) == static_cast<size_t>(blocks) &&
                    stops.shape(0) == static_cast<size_t>(blocks),
                "rgbe_encode: starts and stops must have one entry per block");
        io::rgbe_encode(image.data(), h, w, c, rle, block_rows, buf.data(), starts.data(),
                        stops.data());
      },
      "image"_a, "rle"_a, "block_rows"_a, "buf"_a.noconvert(), "starts"_a.noconvert(),
      "stops"_a.noconvert(), release_gil());

  // --- TGA -------------------------------------------------------------------------------------
  m.def(
      "tga_unrle",
      [](In<uint8_t, 1> data, int64_t start, int64_t count, int64_t bpp, Out<uint8_t, 1> out) {
        require(start >= 0 && count >= 0 && bpp >= 1, "tga_unrle: bad position or sizes");
        require(out.shape(0) >= static_cast<size_t>(count * bpp),
                "tga_unrle: out must hold count * bpp bytes");
        return static_cast<int64_t>(io::tga_unrle(
            data.data(), static_cast<index_t>(data.shape(0)), start, count, bpp, out.data()));
      },
      "data"_a, "start"_a, "count"_a, "bpp"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "tga_rle",
      [](In<uint8_t, 2> rows, int64_t width, int64_t bpp, Out<uint8_t, 1> out) {
        const index_t h = rows.shape(0);
        require(width >= 0 && bpp >= 1 && rows.shape(1) == static_cast<size_t>(width * bpp),
                "tga_rle: rows must be (H, width * bpp)");
        require(out.shape(0) >= static_cast<size_t>(h * width * (bpp + 1)),
                "tga_rle: out must hold H * width * (bpp + 1) bytes");
        return static_cast<int64_t>(io::tga_rle(rows.data(), h, width, bpp, out.data()));
      },
      "rows"_a, "width"_a, "bpp"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "tga_expand8",
      [](In<uint8_t, 1> raw, int64_t height, int64_t width, int64_t bpp, In<int64_t, 1> order,
         bool flip_x, bool flip_y, In<float, 1> lut, Out<float, 3> out) {
        const index_t channels = order.shape(0);
        require(height >= 0 && width >= 0 && bpp >= 1, "tga_expand8: bad sizes");
        require(raw.shape(0) >= static_cast<size_t>(height * width * bpp),
                "tga_expand8: raw must hold height * width pixels");
        for (index_t c = 0; c < channels; ++c)
          require(0 <= order.data()[c] && order.data()[c] < bpp,
                  "tga_expand8: a byte index is outside the pixel");
        require(lut.shape(0) == 256, "tga_expand8: lut must have 256 entries");
        require(out.shape(0) == static_cast<size_t>(height) &&
                    out.shape(1) == static_cast<size_t>(width) &&
                    out.shape(2) == static_cast<size_t>(channels),
                "tga_expand8: out must be (height, width, channels)");
        io::tga_expand8(raw.data(), height, width, bpp, order.data(), channels, flip_x, flip_y,
                        lut.data(), out.data());
      },
      "raw"_a, "height"_a, "width"_a, "bpp"_a, "order"_a, "flip_x"_a, "flip_y"_a, "lut"_a,
      "out"_a.noconvert(), release_gil());

  // --- PNG -------------------------------------------------------------------------------------
  m.def(
      "png_unfilter",
      [](In<uint8_t, 1> buf, int64_t start, int64_t height, int64_t stride, int64_t bpp,
         Out<uint8_t, 2> out) {
        require(start >= 0 && height >= 0 && stride >= 0 && bpp >= 1,
                "png_unfilter: bad position or sizes");
        require(start + height * (stride + 1) <= static_cast<int64_t>(buf.shape(0)),
                "png_unfilter: the rows run past the end of the data");
        require(out.shape(0) == static_cast<size_t>(height) &&
                    out.shape(1) == static_cast<size_t>(stride),
                "png_unfilter: out must be (height, stride)");
        return static_cast<int64_t>(
            io::png_unfilter(buf.data(), start, height, stride, bpp, out.data()));
      },
      "buf"_a, "start"_a, "height"_a, "stride"_a, "bpp"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "png_filter_rows",
      [](In<uint8_t, 2> rows, int64_t bpp, Out<uint8_t, 2> out) {
        const index_t h = rows.shape(0), s = rows.shape(1);
        require(bpp >= 1, "png_filter_rows: bpp must be positive");
        require(out.shape(0) == static_cast<size_t>(h) && out.shape(1) == static_cast<size_t>(s + 1),
                "png_filter_rows: out must be (H, S + 1)");
        io::png_filter_rows(rows.data(), h, s, bpp, out.data());
      },
      "rows"_a, "bpp"_a, "out"_a.noconvert(), release_gil());

  // --- quantisation ----------------------------------------------------------------------------
  bind_quantize<uint8_t>(m);
  bind_quantize<uint16_t>(m);
}
