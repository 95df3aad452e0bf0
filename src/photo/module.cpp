// bakeshop.photo._native: the kernels of bakeshop.photo (the stack merge).
#include "common/bind.hpp"
#include "photo/merge.hpp"

using namespace bakeshop;

namespace {

template <class Code>
void bind_merge(nb::module_& m) {
  m.def(
      "merge_rows",
      [](In<Code, 4> codes, In<float, 2> table, In<float, 2> weight, In<float, 2> slope,
         int64_t low, int64_t high, In<float, 1> inv_exposure, In<double, 2> shifts,
         double ghost, double noise, int64_t row0, int64_t row1, Out<float, 3> out,
         Out<uint8_t, 2> votes, Out<float, 2> wsum, Out<uint8_t, 2> status,
         Out<int32_t, 3> counts) {
        const size_t p = codes.shape(0), h = codes.shape(1), w = codes.shape(2),
                     c = codes.shape(3), z = table.shape(0);
        require(p >= 1 && c >= 1, "merge_rows: no frames or no channels");
        // every code of the type indexes the tables
        require(z >= (size_t{1} << (8 * sizeof(Code))) && table.shape(1) == c &&
                    weight.shape(0) == z && weight.shape(1) == c && slope.shape(0) == z &&
                    slope.shape(1) == c,
                "merge_rows: the tables must be (2**bits, C) of the codes' type");
        require(inv_exposure.shape(0) == p && shifts.shape(0) == p && shifts.shape(1) == 2,
                "merge_rows: inv_exposure (P,) and shifts (P, 2)");
        require(out.shape(0) == h && out.shape(1) == w && out.shape(2) == c &&
                    votes.shape(0) == h && votes.shape(1) == w && wsum.shape(0) == h &&
                    wsum.shape(1) == w && status.shape(0) == h && status.shape(1) == w &&
                    counts.shape(0) == h && counts.shape(1) == p && counts.shape(2) == 3,
                "merge_rows: out (H, W, C), votes, wsum, status (H, W), counts (H, P, 3)");
        require(0 <= row0 && row0 <= row1 && static_cast<size_t>(row1) <= h,
                "merge_rows: the rows must lie within the frames");
        for (size_t j = 0; j < 2 * p; ++j)
          require(std::isfinite(shifts.data()[j]), "merge_rows: the shifts must be finite");
        const photo::MergeInputs in{static_cast<index_t>(p), static_cast<index_t>(h),
                                    static_cast<index_t>(w), static_cast<index_t>(c),
                                    table.data(), weight.data(), slope.data(),
                                    static_cast<index_t>(z), low, high, inv_exposure.data(),
                                    shifts.data(), ghost, noise};
        const photo::MergeOutputs o{out.data(), votes.data(), wsum.data(), status.data(),
                                    counts.data()};
        photo::merge_rows(codes.data(), in, row0, row1, o);
      },
      "codes"_a.noconvert(), "table"_a, "weight"_a, "slope"_a, "low"_a, "high"_a,
      "inv_exposure"_a, "shifts"_a, "ghost"_a, "noise"_a, "row0"_a, "row1"_a,
      "out"_a.noconvert(), "votes"_a.noconvert(), "wsum"_a.noconvert(), "status"_a.noconvert(),
      "counts"_a.noconvert(), release_gil());
}

}  // namespace

NB_MODULE(_native, m) {
  bind_merge<uint8_t>(m);
  bind_merge<uint16_t>(m);
}
