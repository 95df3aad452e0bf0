// bakeshop.sphere._native, the area filter's part: its matrix (src/sphere/matrix.hpp), the
// exact reductions and the supersampling (src/sphere/reduce.hpp), its geometry
// (src/sphere/area.hpp). Python: bakeshop/sphere/area.py, bakeshop/sphere/reductions.py.
#include "common/bind.hpp"
#include "sphere/matrix.hpp"
#include "sphere/reduce.hpp"

using namespace bakeshop;

namespace {

template <class A>
index_t len(const A& a) {
  return static_cast<index_t>(a.shape(0));
}

template <class T>
void def_area_gather(nb::module_& m) {
  m.def(
      "area_gather",
      [](In<T, 2> src, In<int64_t, 1> indptr, In<int32_t, 1> indices, In<float, 1> values,
         Out<T, 2> out) {
        const index_t rows = len(out), nc = static_cast<index_t>(out.shape(1));
        require(src.shape(1) == out.shape(1), "area_gather: src and out differ in channels");
        require(len(indptr) == rows + 1, "area_gather: indptr must be one longer than out");
        require(len(values) == len(indices), "area_gather: indices and values differ in length");
        const int64_t* ip = indptr.data();
        const int32_t* ix = indices.data();
        const index_t n = len(src);
        bool ok = ip[0] >= 0 && ip[rows] <= len(indices);
        for (index_t q = 0; ok && q < rows; ++q) ok = ip[q] <= ip[q + 1];
        require(ok, "area_gather: indptr out of order or beyond the entries");
        index_t bad = 0;
#pragma omp parallel for schedule(static) reduction(+ : bad)
        for (index_t e = 0; e < len(indices); ++e) bad += ix[e] < 0 || ix[e] >= n;
        require(bad == 0, "area_gather: an index beyond the source");
        sphere::area_gather(src.data(), nc, ip, ix, values.data(), out.data(), rows);
      },
      "src"_a, "indptr"_a, "indices"_a, "values"_a, "out"_a.noconvert(), release_gil());
}

template <class T, class W>
void def_box_reduce(nb::module_& m) {
  m.def(
      "box_reduce",
      [](In<T, 3> fine, In<W, 2> omega, int64_t k, Out<T, 3> out) {
        require(k >= 1, "box_reduce: k must be at least 1");
        require(fine.shape(2) == out.shape(2), "box_reduce: fine and out differ in channels");
        require(static_cast<int64_t>(fine.shape(0)) >= static_cast<int64_t>(out.shape(0)) * k &&
                    static_cast<int64_t>(fine.shape(1)) >= static_cast<int64_t>(out.shape(1)) * k,
                "box_reduce: fine must be k times out");
        require(omega.shape(0) > 0 || out.shape(0) == 0, "box_reduce: no weights");
        require(omega.shape(1) >= out.shape(1) * static_cast<size_t>(k),
                "box_reduce: omega narrower than fine's blocks");
        sphere::box_reduce(fine.data(), len(fine), static_cast<index_t>(fine.shape(1)),
                           omega.data(), len(omega), static_cast<index_t>(omega.shape(1)), k,
                           out.data(), len(out), static_cast<index_t>(out.shape(1)),
                           static_cast<index_t>(out.shape(2)));
      },
      "fine"_a, "omega"_a, "k"_a, "out"_a.noconvert(), release_gil());
}

template <class T, class W>
void def_peak_stats(nb::module_& m) {
  m.def(
      "peak_stats",
      [](In<T, 2> values, In<W, 1> omega, Out<double, 1> stats, Out<T, 1> peaks) {
        require(len(omega) == len(values) && len(peaks) == len(values),
                "peak_stats: values, omega and peaks differ in length");
        require(len(stats) == 3, "peak_stats: stats must hold 3");
        require(values.shape(1) >= 1 || len(values) == 0, "peak_stats: no channels");
        sphere::peak_stats(values.data(), len(values), static_cast<index_t>(values.shape(1)),
                           omega.data(), stats.data(), peaks.data());
      },
      "values"_a, "omega"_a, "stats"_a.noconvert(), "peaks"_a.noconvert(), release_gil());
}

}  // namespace

void bind_area(nb::module_& m) {
  // --- the matrix (matrix.hpp) ---
  m.def(
      "splat_rows",
      [](In<int32_t, 1> anchor, In<float, 2> wq, In<float, 1> scale, int64_t row,
         In<int64_t, 1> offsets, In<int32_t, 1> taps, In<float, 1> weights, In<float, 1> alpha,
         In<float, 1> inverse, Out<int64_t, 2> cursor, bool fill, Out<int32_t, 1> indices,
         Out<float, 1> values) {
        const index_t n = len(anchor), m = len(alpha);
        require(wq.shape(0) == anchor.shape(0) && wq.shape(1) == 4 && len(scale) == n,
                "splat_rows: anchor, wq (n, 4) and scale differ in length");
        require(len(inverse) == m && static_cast<index_t>(cursor.shape(1)) == m,
                "splat_rows: alpha, inverse and cursor's rows differ in length");
        require(len(cursor) >= 1, "splat_rows: no chunks");
        require(len(taps) == len(weights), "splat_rows: taps and weights differ in length");
        require(len(values) == len(indices), "splat_rows: indices and values differ in length");
        Errors errors;
        sphere::splat_rows(anchor.data(), n, wq.data(), scale.data(), row, offsets.data(),
                           len(offsets), taps.data(), weights.data(), len(taps), alpha.data(),
                           inverse.data(), m, cursor.data(), len(cursor), fill, indices.data(),
                           values.data(), len(indices), errors);
        errors.check();
      },
      "anchor"_a, "wq"_a, "scale"_a, "row"_a, "offsets"_a, "taps"_a, "weights"_a, "alpha"_a,
      "inverse"_a, "cursor"_a.noconvert(), "fill"_a, "indices"_a.noconvert(),
      "values"_a.noconvert(), release_gil());
  m.def(
      "row_starts",
      [](Out<int64_t, 2> cursor, In<int64_t, 1> extra, Out<int64_t, 1> indptr) {
        const index_t m = len(extra);
        require(static_cast<index_t>(cursor.shape(1)) == m && len(indptr) == m + 1,
                "row_starts: cursor (chunks, m), extra (m,) and indptr (m + 1,)");
        sphere::row_starts(cursor.data(), len(cursor), extra.data(), m, indptr.data());
      },
      "cursor"_a.noconvert(), "extra"_a, "indptr"_a.noconvert(), release_gil());
  m.def(
      "bilinear_rows",
      [](In<float, 1> alpha, int64_t row, In<int32_t, 1> base, In<float, 2> frac,
         In<int32_t, 2> taps, In<int64_t, 1> indptr, Out<int64_t, 1> counts, bool fill,
         Out<int32_t, 1> indices, Out<float, 1> values) {
        const index_t m = len(alpha);
        require(len(base) == m && len(counts) == m, "bilinear_rows: alpha, base, counts differ");
        require(frac.shape(1) == 2 && taps.shape(1) == 4,
                "bilinear_rows: frac must be (n, 2) and taps (n, 4)");
        require(!fill || len(indptr) == m + 1, "bilinear_rows: indptr must be (m + 1,)");
        require(len(values) == len(indices), "bilinear_rows: indices and values differ");
        Errors errors;
        sphere::bilinear_rows(alpha.data(), m, row, base.data(), frac.data(), len(frac),
                              taps.data(), len(taps), indptr.data(), counts.data(), fill,
                              indices.data(), values.data(), len(indices), errors);
        errors.check();
      },
      "alpha"_a, "row"_a, "base"_a, "frac"_a, "taps"_a, "indptr"_a, "counts"_a.noconvert(),
      "fill"_a, "indices"_a.noconvert(), "values"_a.noconvert(), release_gil());
  m.def(
      "scale_rows",
      [](In<int64_t, 1> indptr, In<int32_t, 1> indices, Out<float, 1> values,
         In<double, 1> factor) {
        require(len(indptr) >= 1, "scale_rows: indptr must be (rows + 1,)");
        require(len(values) == len(indices), "scale_rows: indices and values differ");
        const index_t rows = len(indptr) - 1;
        const int64_t* ip = indptr.data();
        bool ok = ip[0] >= 0 && ip[rows] <= len(indices);
        for (index_t q = 0; ok && q < rows; ++q) ok = ip[q] <= ip[q + 1];
        require(ok, "scale_rows: indptr out of order or beyond the entries");
        if (len(factor) > 0) {
          const int32_t* ix = indices.data();
          const index_t n = len(factor);
          index_t bad = 0;
          for (index_t e = 0; e < len(indices); ++e) bad += ix[e] < 0 || ix[e] >= n;
          require(bad == 0, "scale_rows: an index beyond the factors");
        }
        sphere::scale_rows(ip, rows, indices.data(), values.data(), factor.data(), len(factor));
      },
      "indptr"_a, "indices"_a, "values"_a.noconvert(), "factor"_a, release_gil());
  m.def(
      "balance_rows",
      [](In<int64_t, 1> indptr, In<int32_t, 1> indices, In<float, 1> values,
         In<double, 1> omega_out, In<double, 1> col, In<int64_t, 1> blocks,
         Out<double, 2> energy) {
        const index_t rows = len(indptr) - 1, n = len(col);
        require(rows >= 0 && len(omega_out) == rows, "balance_rows: omega_out must be (rows,)");
        require(len(values) == len(indices), "balance_rows: indices and values differ");
        require(static_cast<index_t>(energy.shape(1)) == n &&
                    len(energy) >= len(blocks) - 1,
                "balance_rows: energy must be (blocks, n)");
        const int64_t* ip = indptr.data();
        bool ok = ip[0] >= 0 && ip[rows] <= len(indices);
        for (index_t q = 0; ok && q < rows; ++q) ok = ip[q] <= ip[q + 1];
        const int64_t* bl = blocks.data();
        for (index_t t = 0; ok && t < len(blocks); ++t) ok = bl[t] >= 0 && bl[t] <= rows;
        require(ok, "balance_rows: indptr or blocks out of order or beyond the entries");
        sphere::balance_rows(ip, indices.data(), values.data(), omega_out.data(), col.data(), bl,
                             len(blocks) - 1, energy.data(), n);
      },
      "indptr"_a, "indices"_a, "values"_a, "omega_out"_a, "col"_a, "blocks"_a,
      "energy"_a.noconvert(), release_gil());
  m.def(
      "balance_columns",
      [](Out<double, 2> energy, In<double, 1> omega_in, Out<double, 1> col,
         Out<double, 1> step) {
        const index_t n = len(omega_in);
        require(static_cast<index_t>(energy.shape(1)) == n && len(col) == n && len(step) == n,
                "balance_columns: energy (threads, n), omega_in, col, step (n,)");
        return sphere::balance_columns(energy.data(), len(energy), omega_in.data(), n,
                                       col.data(), step.data());
      },
      "energy"_a.noconvert(), "omega_in"_a, "col"_a.noconvert(), "step"_a.noconvert(),
      release_gil());
  m.def(
      "reorder_rows",
      [](In<int64_t, 1> indptr, In<int32_t, 1> indices, In<float, 1> values,
         In<int32_t, 1> order, In<int64_t, 1> out_indptr, Out<int32_t, 1> out_indices,
         Out<float, 1> out_values) {
        const index_t n = len(order), rows = len(indptr) - 1;
        require(rows >= 0 && len(out_indptr) >= n + 1, "reorder_rows: indptr lengths");
        require(len(values) == len(indices) && len(out_values) == len(out_indices),
                "reorder_rows: indices and values differ");
        const int64_t *ip = indptr.data(), *op = out_indptr.data();
        const int32_t* od = order.data();
        bool ok = ip[0] >= 0 && ip[rows] <= len(indices);
        for (index_t q = 0; ok && q < rows; ++q) ok = ip[q] <= ip[q + 1];
        for (index_t p = 0; ok && p < n; ++p)
          ok = od[p] < rows && (od[p] < 0 || (op[p] >= 0 &&
                                              op[p] + (ip[od[p] + 1] - ip[od[p]]) <=
                                                  len(out_indices)));
        require(ok, "reorder_rows: rows beyond the matrices");
        sphere::reorder_rows(ip, indices.data(), values.data(), od, n, op, out_indices.data(),
                             out_values.data());
      },
      "indptr"_a, "indices"_a, "values"_a, "order"_a, "out_indptr"_a,
      "out_indices"_a.noconvert(), "out_values"_a.noconvert(), release_gil());
  def_area_gather<float>(m);
  def_area_gather<double>(m);

  // --- reductions (reduce.hpp) ---
  def_box_reduce<float, double>(m);
  def_box_reduce<double, double>(m);
  def_box_reduce<float, float>(m);
  def_box_reduce<double, float>(m);
  def_peak_stats<float, double>(m);
  def_peak_stats<double, double>(m);
  def_peak_stats<float, float>(m);
  def_peak_stats<double, float>(m);
}
