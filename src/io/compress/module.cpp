// bakeshop.io.compress._native: the block decoders, the signed BC6H encoder and the half-float
// surface of the ISPC encoder (bakeshop/io/compress/decode.py, bc6h_signed.py, encode.py).
#include <initializer_list>

#include "common/bind.hpp"
#include "io/compress/bc6h_signed.hpp"
#include "io/compress/decode.hpp"
#include "io/compress/encode.hpp"

using namespace bakeshop;
namespace compress = bakeshop::io::compress;

namespace {

// A table of decode.py's: its shape, and every value within [lo, hi] (the kernels index with
// them). They are the module's constants; the check costs microseconds a call.
template <class Array>
void require_table(const Array& a, std::initializer_list<size_t> shape, long lo, long hi,
                   const char* what) {
  require(a.ndim() == shape.size(), what);
  size_t d = 0, n = 1;
  for (size_t extent : shape) {
    require(a.shape(d++) == extent, what);
    n *= extent;
  }
  const auto* p = a.data();
  for (size_t i = 0; i < n; ++i) require(p[i] >= lo && p[i] <= hi, what);
}

// The blocks (n, block_bytes) and their texels (n, 16, channels).
template <class Array>
void require_blocks(const In<uint8_t, 2>& blocks, size_t block_bytes, const Array& out,
                    size_t channels, const char* what) {
  require(blocks.shape(1) == block_bytes && out.shape(0) == blocks.shape(0) &&
              out.shape(1) == 16 && out.shape(2) == channels,
          what);
}

}  // namespace

NB_MODULE(_native, m) {
  m.def(
      "decode_bc7",
      [](In<uint8_t, 2> blocks, Out<float, 3> out, In<int64_t, 2> modes,
         In<int64_t, 2> weights, In<uint8_t, 2> p2, In<uint8_t, 2> p3, In<uint8_t, 1> a2,
         In<uint8_t, 1> a31, In<uint8_t, 1> a32) {
        require_blocks(blocks, 16, out, 4, "decode_bc7: blocks (n, 16) -> out (n, 16, 4)");
        require_table(modes, {8, 10}, 0, 8, "decode_bc7: bad mode table");
        for (int k = 0; k < 8; ++k) {
          const int64_t* row = modes.data() + 10 * k;
          const int64_t ns = row[0], pb = row[1], rb = row[2], isb = row[3], cb = row[4],
                        ab = row[5], epb = row[6], spb = row[7], ib = row[8], ib2 = row[9];
          const int64_t p = epb || spb ? 1 : 0;
          // 1..3 subsets, endpoints of at most 8 bits with their P-bit, index bits 2..4 (IB2:
          // none or 2..4), and every field inside the block's 128 bits
          const int64_t used = k + 1 + pb + rb + isb + 2 * ns * (3 * cb + ab) +
                               (epb ? 2 * ns : spb ? ns : 0) + 16 * ib - ns +
                               (ib2 ? 16 * ib2 - 1 : 0);
          require(ns >= 1 && ns <= 3 && cb + p <= 8 && ab + p <= 8 && ib >= 2 && ib <= 4 &&
                      (ib2 == 0 || (ib2 >= 2 && ib2 <= 4)) && used <= 128,
                  "decode_bc7: bad mode table");
        }
        require_table(weights, {5, 16}, 0, 64, "decode_bc7: bad weight table");
        require_table(p2, {64, 16}, 0, 1, "decode_bc7: bad partition table");
        require_table(p3, {64, 16}, 0, 2, "decode_bc7: bad partition table");
        require_table(a2, {64}, 0, 15, "decode_bc7: bad anchor table");
        require_table(a31, {64}, 0, 15, "decode_bc7: bad anchor table");
        require_table(a32, {64}, 0, 15, "decode_bc7: bad anchor table");
        compress::BptcTables t;
        t.bc7_modes = modes.data(), t.weights = weights.data(), t.p2 = p2.data();
        t.p3 = p3.data(), t.a2 = a2.data(), t.a31 = a31.data(), t.a32 = a32.data();
        compress::decode_bc7(blocks.data(), static_cast<index_t>(blocks.shape(0)), out.data(), t);
      },
      "blocks"_a, "out"_a.noconvert(), "modes"_a, "weights"_a, "p2"_a, "p3"_a, "a2"_a, "a31"_a,
      "a32"_a, release_gil());

  m.def(
      "decode_bc6h",
      [](In<uint8_t, 2> blocks, Out<uint16_t, 3> out, bool is_signed, In<int64_t, 2> modes,
         In<int8_t, 3> layout, In<int64_t, 2> weights, In<uint8_t, 2> p2, In<uint8_t, 1> a2) {
        require_blocks(blocks, 16, out, 3, "decode_bc6h: blocks (n, 16) -> out (n, 16, 3)");
        // valid, transformed, PB (0 or 5 bits), endpoint bits (at most 16), deltas (at most 16)
        require_table(modes, {32, 7}, 0, 16, "decode_bc6h: bad mode table");
        const int64_t* mode = modes.data();
        for (int k = 0; k < 32; ++k)
          require(mode[7 * k] <= 1 && mode[7 * k + 2] <= 6 &&
                      (!mode[7 * k] || (mode[7 * k + 3] >= 1 && mode[7 * k + 4] >= 1 &&
                                        mode[7 * k + 5] >= 1 && mode[7 * k + 6] >= 1)),
                  "decode_bc6h: bad mode table");
        require_table(layout, {32, 82, 2}, -1, 15, "decode_bc6h: bad layout table");
        const int8_t* bit = layout.data();
        for (int k = 0; k < 32 * 82; ++k)  // fields R0..B3 and PB
          require(bit[2 * k] <= 12 && bit[2 * k + 1] >= (bit[2 * k] < 0 ? -1 : 0),
                  "decode_bc6h: bad layout table");
        require_table(weights, {5, 16}, 0, 64, "decode_bc6h: bad weight table");
        require_table(p2, {64, 16}, 0, 1, "decode_bc6h: bad partition table");
        require_table(a2, {64}, 0, 15, "decode_bc6h: bad anchor table");
        compress::BptcTables t;
        t.bc6h_modes = modes.data(), t.bc6h_layout = layout.data(), t.weights = weights.data();
        t.p2 = p2.data(), t.a2 = a2.data();
        compress::decode_bc6h(blocks.data(), static_cast<index_t>(blocks.shape(0)), is_signed,
                              out.data(), t);
      },
      "blocks"_a, "out"_a.noconvert(), "signed"_a, "modes"_a, "layout"_a, "weights"_a, "p2"_a,
      "a2"_a, release_gil());

  m.def(
      "decode_s3tc",
      [](In<uint8_t, 2> blocks, Out<float, 3> out, int kind) {
        require(kind == 1 || kind == 3 || kind == 4 || kind == 5,
                "decode_s3tc: kind is 1 (BC1), 3 (BC3), 4 (BC4) or 5 (BC5)");
        require_blocks(blocks, kind == 1 || kind == 4 ? 8 : 16, out,
                       kind == 4 ? 1 : kind == 5 ? 2 : 4,
                       "decode_s3tc: blocks (n, 8 or 16) -> out (n, 16, channels of the kind)");
        compress::decode_s3tc(blocks.data(), static_cast<index_t>(blocks.shape(0)), kind,
                              out.data());
      },
      "blocks"_a, "out"_a.noconvert(), "kind"_a, release_gil());

  m.def(
      "encode_bc6h_signed",
      [](In<double, 3> q_blocks, Out<uint8_t, 2> out, In<int8_t, 3> layout) {
        require(q_blocks.shape(1) == 16 && q_blocks.shape(2) == 3 &&
                    out.shape(0) == q_blocks.shape(0) && out.shape(1) == 16,
                "encode_bc6h_signed: q_blocks (n, 16, 3) -> out (n, 16)");
        require_table(layout, {32, 82, 2}, -1, 15, "encode_bc6h_signed: bad layout table");
        const int8_t* bit = layout.data();
        for (int k = 0; k < 32 * 82; ++k)  // fields R0..B3 and PB
          require(bit[2 * k] <= 12, "encode_bc6h_signed: bad layout table");
        compress::encode_bc6h_signed(q_blocks.data(), static_cast<index_t>(q_blocks.shape(0)),
                                     out.data(), layout.data());
      },
      "q_blocks"_a, "out"_a.noconvert(), "layout"_a, release_gil());

  m.def(
      "half_rgba",
      [](In<uint32_t, 3> bits, Out<uint16_t, 3> out) {
        require(bits.shape(2) >= 1 && bits.shape(2) <= 4 && out.shape(0) >= bits.shape(0) &&
                    out.shape(1) >= bits.shape(1) && out.shape(2) == 4,
                "half_rgba: bits (H, W, 1..4) -> out (H' >= H, W' >= W, 4)");
        compress::half_rgba(bits.data(), static_cast<index_t>(bits.shape(0)),
                            static_cast<index_t>(bits.shape(1)),
                            static_cast<index_t>(bits.shape(2)), out.data(),
                            static_cast<index_t>(out.shape(1)));
      },
      "bits"_a, "out"_a.noconvert(), release_gil());
}
