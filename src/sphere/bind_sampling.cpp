// bakeshop.sphere._native, the sampling half: the layouts' maps (maps.hpp) and the remap
// plans and gathers (gather.hpp, windows.hpp, texels.hpp).
#include <nanobind/stl/tuple.h>

#include <tuple>

#include "common/bind.hpp"
#include "sphere/cube_latlong.hpp"
#include "sphere/gather.hpp"
#include "sphere/maps.hpp"
#include "sphere/texels.hpp"
#include "sphere/windows.hpp"

using namespace bakeshop;

namespace {

void check_kind(int kind, index_t h, index_t w) {
  require(kind >= sphere::LATLONG && kind <= sphere::OPENEXR_CUBE, "unknown layout kind");
  require(h > 0 && w > 0, "a layout's grid must be positive");
}

void check_rot(const In<double, 2>& rot) {
  require(rot.shape(0) == 3 && rot.shape(1) == 3, "rot must be a 3x3 matrix");
}

template <class T>
void bind_gathers(nb::module_& m) {
  m.def(
      "count_nonfinite",
      [](In<T, 1> flat) {
        int64_t nans, infs, first;
        sphere::count_nonfinite<T>(flat.data(), static_cast<index_t>(flat.shape(0)), nans, infs,
                                   first);
        return std::make_tuple(nans, infs, first);
      },
      "flat"_a.noconvert(), release_gil());
  m.def(
      "plan",
      [](int skind, index_t sh, index_t sw, int dkind, index_t dh, index_t dw, index_t faces,
         In<double, 2> rot, bool nearest, Out<int32_t, 1> base, Out<float, 2> frac,
         In<T, 2> src, Out<T, 2> out, index_t first_row) {
        check_kind(skind, sh, sw);
        check_kind(dkind, dh, dw);
        check_rot(rot);
        const index_t count = static_cast<index_t>(base.shape(0));
        require(count % dw == 0 && first_row >= 0 && first_row + count / dw <= faces * dh,
                "plan: base must hold whole destination rows within the faces");
        require(frac.shape(1) == 2 && (nearest || static_cast<index_t>(frac.shape(0)) == count),
                "plan: frac must be (m, 2) for a bilinear plan");
        const bool apply = out.shape(0) > 0;
        if (apply) {
          require(static_cast<index_t>(src.shape(0)) == sphere::layout_texels(skind, sh, sw) &&
                      static_cast<index_t>(out.shape(0)) == count && out.shape(1) == src.shape(1),
                  "plan: src must be the flat source image and out (m, C)");
        }
        sphere::plan<T>(skind, sh, sw, dkind, dh, dw, rot.data(), nearest, base.data(), count,
                        frac.data(), src.data(), static_cast<index_t>(src.shape(0)),
                        static_cast<index_t>(src.shape(1)), apply ? out.data() : nullptr,
                        first_row);
      },
      "skind"_a, "sh"_a, "sw"_a, "dkind"_a, "dh"_a, "dw"_a, "faces"_a, "rot"_a, "nearest"_a,
      "base"_a.noconvert(), "frac"_a.noconvert(), "src"_a, "out"_a.noconvert(), "first_row"_a,
      release_gil());
  m.def(
      "gather_at",
      [](In<T, 2> src, index_t row, In<int32_t, 1> base, In<float, 2> frac, In<int32_t, 2> taps,
         In<int64_t, 1> where, Out<T, 2> out) {
        const index_t count = static_cast<index_t>(base.shape(0));
        require(frac.shape(0) == base.shape(0) && frac.shape(1) == 2 && taps.shape(1) == 4 &&
                    out.shape(0) == base.shape(0) && out.shape(1) == src.shape(1),
                "gather_at: base (m,), frac (m, 2), taps (k, 4) and out (m, C)");
        sphere::gather_at<T>(src.data(), static_cast<index_t>(src.shape(0)),
                             static_cast<index_t>(src.shape(1)), row, base.data(), count,
                             frac.data(), taps.data(), static_cast<index_t>(taps.shape(0)),
                             where.data(), static_cast<index_t>(where.shape(0)), out.data());
      },
      "src"_a, "row"_a, "base"_a, "frac"_a, "taps"_a, "where"_a, "out"_a.noconvert(),
      release_gil());
  m.def(
      "gather_plan",
      [](In<T, 2> src, index_t row, In<int32_t, 1> base, In<float, 2> frac, In<int32_t, 2> taps,
         Out<T, 2> out) {
        const index_t count = static_cast<index_t>(base.shape(0));
        require(frac.shape(0) == base.shape(0) && frac.shape(1) == 2 && taps.shape(1) == 4 &&
                    out.shape(0) == base.shape(0) && out.shape(1) == src.shape(1),
                "gather_plan: base (m,), frac (m, 2), taps (k, 4) and out (m, C)");
        sphere::gather_plan<T>(src.data(), static_cast<index_t>(src.shape(0)),
                               static_cast<index_t>(src.shape(1)), row, base.data(), count,
                               frac.data(), taps.data(), static_cast<index_t>(taps.shape(0)),
                               out.data());
      },
      "src"_a, "row"_a, "base"_a, "frac"_a, "taps"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "gather_plan_clamped",
      [](In<T, 2> src, index_t row, In<int32_t, 1> base, In<float, 2> frac, In<int32_t, 2> taps,
         double clamp, Out<T, 2> out) {
        const index_t count = static_cast<index_t>(base.shape(0));
        require(frac.shape(0) == base.shape(0) && frac.shape(1) == 2 && taps.shape(1) == 4 &&
                    out.shape(0) == base.shape(0) && out.shape(1) == src.shape(1),
                "gather_plan_clamped: base (m,), frac (m, 2), taps (k, 4) and out (m, C)");
        sphere::gather_plan_clamped<T>(src.data(), static_cast<index_t>(src.shape(0)),
                                       static_cast<index_t>(src.shape(1)), row, base.data(),
                                       count, frac.data(), taps.data(),
                                       static_cast<index_t>(taps.shape(0)), clamp, out.data());
      },
      "src"_a, "row"_a, "base"_a, "frac"_a, "taps"_a, "clamp"_a, "out"_a.noconvert(),
      release_gil());
  m.def(
      "gather_nearest",
      [](In<T, 2> src, In<int32_t, 2> index, Out<T, 2> out) {
        require(index.shape(1) >= 1 && out.shape(0) == index.shape(0) &&
                    out.shape(1) == src.shape(1),
                "gather_nearest: index (m, k) and out (m, C)");
        sphere::gather_nearest<T>(src.data(), static_cast<index_t>(src.shape(0)),
                                  static_cast<index_t>(src.shape(1)), index.data(),
                                  static_cast<index_t>(index.shape(0)),
                                  static_cast<index_t>(index.shape(1)), out.data());
      },
      "src"_a, "index"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "gather_bilinear",
      [](In<T, 2> src, In<int32_t, 2> index, In<T, 2> frac, Out<T, 2> out) {
        require(index.shape(1) == 4 && frac.shape(0) == index.shape(0) && frac.shape(1) == 2 &&
                    out.shape(0) == index.shape(0) && out.shape(1) == src.shape(1),
                "gather_bilinear: index (m, 4), frac (m, 2) and out (m, C)");
        sphere::gather_bilinear<T>(src.data(), static_cast<index_t>(src.shape(0)),
                                   static_cast<index_t>(src.shape(1)), index.data(),
                                   static_cast<index_t>(index.shape(0)), frac.data(), out.data());
      },
      "src"_a, "index"_a, "frac"_a, "out"_a.noconvert(), release_gil());
}

}  // namespace

void bind_sampling(nb::module_& m) {
  // --- maps.hpp -------------------------------------------------------------------------------
  m.def(
      "directions_at",
      [](int kind, index_t h, index_t w, In<double, 2> coords, Out<double, 2> out) {
        check_kind(kind, h, w);
        require(coords.shape(1) == 3 && out.shape(0) == coords.shape(0) && out.shape(1) == 3,
                "directions_at: coords and out must be (N, 3)");
        sphere::directions_at(kind, h, w, coords.data(), static_cast<index_t>(coords.shape(0)),
                              out.data());
      },
      "kind"_a, "h"_a, "w"_a, "coords"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "coordinates_of",
      [](int kind, index_t h, index_t w, In<double, 2> dirs, Out<double, 2> out) {
        check_kind(kind, h, w);
        require(dirs.shape(1) == 3 && out.shape(0) == dirs.shape(0) && out.shape(1) == 3,
                "coordinates_of: dirs and out must be (N, 3)");
        sphere::coordinates_of(kind, h, w, dirs.data(), static_cast<index_t>(dirs.shape(0)),
                               out.data());
      },
      "kind"_a, "h"_a, "w"_a, "dirs"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "latlong_directions",
      [](Out<double, 3> out) {
        require(out.shape(2) == 3, "latlong_directions: out must be (H, W, 3)");
        sphere::latlong_directions(static_cast<index_t>(out.shape(0)),
                                   static_cast<index_t>(out.shape(1)), out.data());
      },
      "out"_a.noconvert(), release_gil());
  m.def(
      "latlong_trig",
      [](index_t h, index_t w, Out<double, 2> out) {
        require(h > 0 && w > 0, "latlong_trig: h and w must be positive");
        require(out.shape(0) == 4 && out.shape(1) == static_cast<size_t>(std::max(h, w)),
                "latlong_trig: out must be (4, max(h, w))");
        sphere::latlong_trig(h, w, out.data());
      },
      "h"_a, "w"_a, "out"_a.noconvert(), release_gil());
  // --- gather.hpp -----------------------------------------------------------------------------
  m.attr("EXCEPTION") = sphere::EXCEPTION;
  m.def(
      "taps_of",
      [](int kind, index_t h, index_t w, In<double, 2> dirs, bool nearest, Out<int32_t, 2> index,
         Out<float, 2> frac) {
        check_kind(kind, h, w);
        const index_t count = static_cast<index_t>(dirs.shape(0));
        require(dirs.shape(1) == 3 && static_cast<index_t>(index.shape(0)) == count &&
                    (nearest ? index.shape(1) >= 1 : index.shape(1) == 4),
                "taps_of: dirs (m, 3), index (m, 1) nearest or (m, 4) bilinear");
        require(frac.shape(1) == 2 && (nearest || static_cast<index_t>(frac.shape(0)) == count),
                "taps_of: frac must be (m, 2) for bilinear taps");
        sphere::taps_of(kind, h, w, dirs.data(), count, nearest, index.data(),
                        static_cast<index_t>(index.shape(1)), frac.data());
      },
      "kind"_a, "h"_a, "w"_a, "dirs"_a, "nearest"_a, "index"_a.noconvert(), "frac"_a.noconvert(),
      release_gil());
  m.def(
      "plan_exceptions",
      [](int skind, index_t sh, index_t sw, int dkind, index_t dh, index_t dw, In<double, 2> rot,
         In<int64_t, 1> where, Out<int32_t, 2> taps) {
        check_kind(skind, sh, sw);
        check_kind(dkind, dh, dw);
        check_rot(rot);
        require(taps.shape(0) == where.shape(0) && taps.shape(1) == 4,
                "plan_exceptions: taps must be (k, 4) of where (k,)");
        sphere::plan_exceptions(skind, sh, sw, dkind, dh, dw, rot.data(), where.data(),
                                static_cast<index_t>(where.shape(0)), taps.data());
      },
      "skind"_a, "sh"_a, "sw"_a, "dkind"_a, "dh"_a, "dw"_a, "rot"_a, "where"_a,
      "taps"_a.noconvert(), release_gil());
  m.def(
      "reorder_plan",
      [](In<int32_t, 1> base, In<float, 2> frac, In<int32_t, 1> order, Out<int32_t, 1> out_base,
         Out<float, 2> out_frac) {
        const bool has_frac = out_frac.shape(0) > 0;
        require(out_base.shape(0) == order.shape(0) &&
                    (!has_frac || (out_frac.shape(0) == order.shape(0) && out_frac.shape(1) == 2 &&
                                   frac.shape(0) == base.shape(0) && frac.shape(1) == 2)),
                "reorder_plan: out_base (n,) and out_frac (n, 2) or (0, 2) of order (n,)");
        sphere::reorder_plan(base.data(), has_frac ? frac.data() : nullptr,
                             static_cast<index_t>(base.shape(0)), order.data(),
                             static_cast<index_t>(order.shape(0)), out_base.data(),
                             has_frac ? out_frac.data() : nullptr);
      },
      "base"_a, "frac"_a, "order"_a, "out_base"_a.noconvert(), "out_frac"_a.noconvert(),
      release_gil());
  bind_gathers<float>(m);
  bind_gathers<double>(m);
  // --- windows.hpp ----------------------------------------------------------------------------
  m.def(
      "part_taps",
      [](int skind, index_t sh, index_t sw, int dkind, index_t dh, index_t dw, In<double, 2> rot,
         index_t f, index_t j0, index_t j1, index_t i0, index_t i1, bool nearest,
         Out<int32_t, 2> taps, Out<float, 2> frac) {
        check_kind(skind, sh, sw);
        check_kind(dkind, dh, dw);
        check_rot(rot);
        require(0 <= j0 && j0 <= j1 && j1 <= dh && 0 <= i0 && i0 <= i1 && i1 <= dw &&
                    0 <= f && f < (sphere::is_cubic(dkind) ? 6 : 1),
                "part_taps: the part must lie on a face of the destination");
        const index_t n = (j1 - j0) * (i1 - i0);
        require(static_cast<index_t>(taps.shape(0)) == n &&
                    (nearest ? taps.shape(1) >= 1 : taps.shape(1) == 4) && frac.shape(1) == 2 &&
                    (nearest || static_cast<index_t>(frac.shape(0)) == n),
                "part_taps: taps (n, 1) nearest or (n, 4) and frac (n, 2) bilinear");
        sphere::part_taps(skind, sh, sw, dkind, dh, dw, rot.data(), f, j0, j1, i0, i1, nearest,
                          taps.data(), static_cast<index_t>(taps.shape(1)), frac.data());
      },
      "skind"_a, "sh"_a, "sw"_a, "dkind"_a, "dh"_a, "dw"_a, "rot"_a, "f"_a, "j0"_a, "j1"_a,
      "i0"_a, "i1"_a, "nearest"_a, "taps"_a.noconvert(), "frac"_a.noconvert(), release_gil());
  m.def(
      "latlong_window",
      [](index_t h, index_t w, index_t top, index_t bottom, index_t left, index_t right,
         Out<double, 2> dirs) {
        require(h > 0 && w > 0 && 0 <= top && top <= bottom && bottom <= h && 0 <= left &&
                    left <= right && right <= w,
                "latlong_window: the window must lie in the latlong");
        require(static_cast<index_t>(dirs.shape(0)) == (bottom - top) * (right - left) &&
                    dirs.shape(1) == 3,
                "latlong_window: dirs must be (n, 3)");
        sphere::latlong_window(h, w, top, bottom, left, right, dirs.data());
      },
      "h"_a, "w"_a, "top"_a, "bottom"_a, "left"_a, "right"_a, "dirs"_a.noconvert(),
      release_gil());
  // --- texels.hpp -----------------------------------------------------------------------------
  m.def(
      "row_directions",
      [](int kind, index_t h, index_t w, index_t r0, index_t r1, In<double, 2> trig,
         Out<double, 2> out) {
        check_kind(kind, h, w);
        const index_t rows = (sphere::is_cubic(kind) ? 6 : 1) * h;
        require(0 <= r0 && r0 <= r1 && r1 <= rows, "row_directions: rows outside the layout");
        require(kind != sphere::LATLONG ||
                    (trig.shape(0) == 4 && static_cast<index_t>(trig.shape(1)) >= std::max(h, w)),
                "row_directions: trig must be latlong_trig(h, w)");
        require(static_cast<index_t>(out.shape(0)) == (r1 - r0) * w && out.shape(1) == 3,
                "row_directions: out must be ((r1 - r0) w, 3)");
        sphere::row_directions(kind, h, w, r0, r1, trig.data(),
                               static_cast<index_t>(trig.shape(1)), out.data());
      },
      "kind"_a, "h"_a, "w"_a, "r0"_a, "r1"_a, "trig"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "index_directions",
      [](int kind, index_t h, index_t w, In<int64_t, 1> index, In<double, 2> trig,
         Out<double, 2> out) {
        check_kind(kind, h, w);
        require(kind != sphere::LATLONG ||
                    (trig.shape(0) == 4 && static_cast<index_t>(trig.shape(1)) >= std::max(h, w)),
                "index_directions: trig must be latlong_trig(h, w)");
        require(out.shape(0) == index.shape(0) && out.shape(1) == 3,
                "index_directions: out must be (n, 3)");
        sphere::index_directions(kind, h, w, (sphere::is_cubic(kind) ? 6 : 1) * h, index.data(),
                                 static_cast<index_t>(index.shape(0)), trig.data(),
                                 static_cast<index_t>(trig.shape(1)), out.data());
      },
      "kind"_a, "h"_a, "w"_a, "index"_a, "trig"_a, "out"_a.noconvert(), release_gil());
  m.def(
      "texel_cosines",
      [](int kind, index_t faces, index_t h, index_t w, In<double, 1> up, Out<double, 1> out) {
        check_kind(kind, h, w);
        require(faces == (sphere::is_cubic(kind) ? 6 : 1) && up.shape(0) == 3 &&
                    static_cast<index_t>(out.shape(0)) == faces * h * w,
                "texel_cosines: up (3,) and out (faces h w,)");
        sphere::texel_cosines(kind, faces, h, w, up.data(), out.data());
      },
      "kind"_a, "faces"_a, "h"_a, "w"_a, "up"_a, "out"_a.noconvert(), release_gil());
  // --- cube_latlong.hpp -----------------------------------------------------------------------
  m.def(
      "latlong_taps",
      [](int skind, index_t sh, index_t sw, index_t f, index_t i, index_t j, In<double, 2> rot,
         index_t dh, index_t dw, double om, index_t o, index_t room, Out<int32_t, 1> taps,
         Out<float, 1> weights) {
        check_kind(skind, sh, sw);
        check_kind(sphere::LATLONG, dh, dw);
        check_rot(rot);
        require(sphere::is_cubic(skind) && 0 <= f && f < 6 && 0 <= i && i < sw && 0 <= j &&
                    j < sh,
                "latlong_taps: (f, i, j) must be a texel of a cube source");
        require(0 <= o && 0 <= room && o + room <= static_cast<index_t>(taps.shape(0)) &&
                    o + room <= static_cast<index_t>(weights.shape(0)),
                "latlong_taps: taps and weights must have room from o");
        return sphere::latlong_taps<float>(skind, sh, sw, f, i, j, rot.data(), dh, dw, om, o, room,
                                           taps.data(), weights.data());
      },
      "skind"_a, "sh"_a, "sw"_a, "f"_a, "i"_a, "j"_a, "rot"_a, "dh"_a, "dw"_a, "om"_a, "o"_a,
      "room"_a, "taps"_a.noconvert(), "weights"_a.noconvert(), release_gil());
}
