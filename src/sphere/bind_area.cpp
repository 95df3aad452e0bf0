// bakeshop.sphere._native, the area filter's part: its matrix (src/sphere/matrix.hpp), the
// exact reductions and the supersampling (src/sphere/reduce.hpp), its geometry
// (src/sphere/area.hpp). Python: bakeshop/sphere/area.py, bakeshop/sphere/reductions.py.
#include "common/bind.hpp"
#include "sphere/area.hpp"
#include "sphere/cube_latlong.hpp"
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


void require_rotation(const In<double, 2>& rot) {
  require(rot.shape(0) == 3 && rot.shape(1) == 3, "the rotation must be 3 x 3");
}

bool is_cubic_kind(int kind) { return sphere::is_cubic(kind); }

void require_grid(int kind, int64_t h, int64_t w, const char* what) {
  require(kind >= 0 && kind <= 9 && h >= 1 && w >= 1, what);
}

template <class T>
void def_supersample_cube(nb::module_& m) {
  m.def(
      "_supersample_cube",
      [](int skind, int64_t sh, int64_t sw, In<T, 2> src, double clamp, int64_t size, int64_t k,
         In<double, 2> rot, Out<T, 3> out) {
        require_grid(skind, sh, sw, "_supersample_cube: a bad source grid");
        require_rotation(rot);
        require(size >= 1 && k >= 1, "_supersample_cube: size and k must be positive");
        require(static_cast<int64_t>(out.shape(0)) == 6 * size &&
                    static_cast<int64_t>(out.shape(1)) == size && out.shape(2) == src.shape(1),
                "_supersample_cube: out must be (6 size, size, C)");
        Errors errors;
        sphere::supersample_cube(skind, sh, sw, src.data(), len(src),
                                 static_cast<index_t>(src.shape(1)), clamp, size, k, rot.data(),
                                 out.data(), errors);
        errors.check();
      },
      "skind"_a, "sh"_a, "sw"_a, "src"_a, "clamp"_a, "size"_a, "k"_a, "rot"_a,
      "out"_a.noconvert(), release_gil());
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

  // --- the geometry (area.hpp) ---
  m.def(
      "splat_plan",
      [](int skind, int64_t sh, int64_t sw, int64_t sfaces, In<double, 1> omega, int dkind,
         int64_t dh, int64_t dw, In<double, 2> rot, Out<int32_t, 1> anchor, Out<float, 2> wq,
         Out<float, 1> scale, Out<float, 1> width, Out<int32_t, 2> parts, Out<double, 3> acc) {
        require_grid(skind, sh, sw, "splat_plan: a bad source grid");
        require_grid(dkind, dh, dw, "splat_plan: a bad destination grid");
        require_rotation(rot);
        const index_t n = sfaces * sh * sw;
        require(sfaces >= 1 && len(omega) == n && len(anchor) == n && len(wq) == n &&
                    wq.shape(1) == 4 && len(scale) == n && len(width) == n &&
                    len(parts) == n && parts.shape(1) == 2,
                "splat_plan: the per-texel arrays must hold the source's texels");
        const index_t faces = is_cubic_kind(dkind) ? 6 : 1;
        const index_t m_ = static_cast<index_t>(acc.shape(1));
        require(len(acc) >= 1 && m_ == faces * dh * dw && acc.shape(2) == 2,
                "splat_plan: acc must be (chunks, destination texels, 2)");
        sphere::splat_plan(skind, sh, sw, sfaces, omega.data(), dkind, dh, dw, rot.data(),
                           anchor.data(), wq.data(), scale.data(), width.data(), parts.data(),
                           acc.data(), len(acc), m_);
      },
      "skind"_a, "sh"_a, "sw"_a, "sfaces"_a, "omega"_a, "dkind"_a, "dh"_a, "dw"_a, "rot"_a,
      "anchor"_a.noconvert(), "wq"_a.noconvert(), "scale"_a.noconvert(), "width"_a.noconvert(),
      "parts"_a.noconvert(), "acc"_a.noconvert(), release_gil());
  m.def(
      "splat_exceptions",
      [](int skind, int64_t sh, int64_t sw, In<double, 1> omega, int dkind, int64_t dh,
         int64_t dw, In<double, 2> rot, In<int64_t, 1> where, In<int32_t, 2> parts,
         In<int64_t, 1> offsets, Out<int32_t, 1> taps, Out<float, 1> weights,
         Out<int64_t, 1> counts) {
        require_grid(skind, sh, sw, "splat_exceptions: a bad source grid");
        require_grid(dkind, dh, dw, "splat_exceptions: a bad destination grid");
        require_rotation(rot);
        const index_t n = len(where), texels = len(omega);
        require(len(parts) == texels && parts.shape(1) == 2,
                "splat_exceptions: parts must be (source texels, 2)");
        require(len(offsets) == n + 1 && len(counts) == n,
                "splat_exceptions: offsets (n + 1,) and counts (n,) for n texels");
        require(len(weights) == len(taps), "splat_exceptions: taps and weights differ");
        const int64_t *wh = where.data(), *at = offsets.data();
        const int32_t* pa = parts.data();
        bool ok = n == 0 || (at[0] >= 0 && at[n] <= len(taps));
        for (index_t k = 0; ok && k < n; ++k) {
          const int64_t p = wh[k];
          ok = p >= 0 && p < texels && pa[2 * p] >= 1 && pa[2 * p + 1] >= 1 &&
               at[k + 1] - at[k] >= 4 * static_cast<int64_t>(pa[2 * p]) * pa[2 * p + 1];
        }
        require(ok, "splat_exceptions: texels, parts or room out of range");
        Errors errors;
        const double* r = rot.data();
        // a cube's texels cut into parts into a latlong: their exact overlaps (cube_latlong.hpp)
        auto latlong = [=](index_t, index_t f, index_t i, index_t j, double om, index_t o,
                           index_t room, int32_t* t, float* w) -> index_t {
          return sphere::latlong_taps(skind, sh, sw, f, i, j, r, dh, dw, om, o, room, t, w);
        };
        sphere::splat_exceptions(skind, sh, sw, omega.data(), dkind, dh, dw, r, wh, n, pa, at,
                                 taps.data(), weights.data(), counts.data(), errors, latlong);
        errors.check();
      },
      "skind"_a, "sh"_a, "sw"_a, "omega"_a, "dkind"_a, "dh"_a, "dw"_a, "rot"_a, "where"_a,
      "parts"_a, "offsets"_a, "taps"_a.noconvert(), "weights"_a.noconvert(),
      "counts"_a.noconvert(), release_gil());
  m.def(
      "compact_exceptions",
      [](In<int64_t, 1> at, In<int64_t, 1> counts, In<int32_t, 1> taps, In<float, 1> weights,
         In<int64_t, 1> ends, Out<int32_t, 1> out_taps, Out<float, 1> out_weights) {
        const index_t n = len(counts);
        require(len(at) >= n && len(ends) == n, "compact_exceptions: at, counts, ends differ");
        require(len(taps) == len(weights) && len(out_taps) == len(out_weights),
                "compact_exceptions: taps and weights differ");
        const int64_t *a = at.data(), *c = counts.data(), *e = ends.data();
        bool ok = true;
        for (index_t k = 0; ok && k < n; ++k)
          ok = c[k] >= 0 && a[k] >= 0 && a[k] + c[k] <= len(taps) && e[k] - c[k] >= 0 &&
               e[k] <= len(out_taps);
        require(ok, "compact_exceptions: entries beyond the buffers");
        sphere::compact_exceptions(a, c, n, taps.data(), weights.data(), e, out_taps.data(),
                                   out_weights.data());
      },
      "at"_a, "counts"_a, "taps"_a, "weights"_a, "ends"_a, "out_taps"_a.noconvert(),
      "out_weights"_a.noconvert(), release_gil());
  m.def(
      "deposit_exceptions",
      [](In<int64_t, 1> where, In<int64_t, 1> offsets, In<int32_t, 1> taps,
         In<float, 1> weights, In<float, 1> width, Out<double, 3> acc) {
        const index_t n = len(where), m_ = static_cast<index_t>(acc.shape(1));
        require(len(offsets) == n + 1 && len(taps) == len(weights) && acc.shape(2) == 2 &&
                    len(acc) >= 1,
                "deposit_exceptions: offsets (n + 1,), acc (chunks, m, 2)");
        const int64_t *wh = where.data(), *o = offsets.data();
        const int32_t* t = taps.data();
        bool ok = n == 0 || (o[0] >= 0 && o[n] <= len(taps));
        for (index_t k = 0; ok && k < n; ++k) ok = wh[k] >= 0 && wh[k] < len(width) && o[k] <= o[k + 1];
        for (index_t e = 0; ok && e < len(taps); ++e) ok = t[e] >= 0 && t[e] < m_;
        require(ok, "deposit_exceptions: entries beyond the buffers");
        sphere::deposit_exceptions(wh, n, o, t, weights.data(), width.data(), acc.data());
      },
      "where"_a, "offsets"_a, "taps"_a, "weights"_a, "width"_a, "acc"_a.noconvert(),
      release_gil());
  m.def(
      "area_alpha",
      [](In<double, 3> acc, In<double, 1> omega, Out<float, 1> alpha, Out<float, 1> inverse) {
        const index_t m_ = static_cast<index_t>(acc.shape(1));
        require(acc.shape(2) == 2 && len(omega) == m_ && len(alpha) == m_ && len(inverse) == m_,
                "area_alpha: acc (chunks, m, 2), omega, alpha, inverse (m,)");
        sphere::area_alpha(acc.data(), len(acc), m_, omega.data(), alpha.data(), inverse.data());
      },
      "acc"_a, "omega"_a, "alpha"_a.noconvert(), "inverse"_a.noconvert(), release_gil());
  def_supersample_cube<float>(m);
  def_supersample_cube<double>(m);
}
