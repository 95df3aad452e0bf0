// bakeshop.io._native: the codecs' kernels.
#include "common/bind.hpp"
#include "io/half.hpp"

using namespace bakeshop;

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
}
