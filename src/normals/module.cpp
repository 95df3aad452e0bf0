// bakeshop.normals._native: the kernels of bakeshop.normals (blend, tiling samplers, transfer).
#include "common/bind.hpp"
#include "normals/blend.hpp"
#include "normals/tiling.hpp"
#include "normals/transfer.hpp"

using namespace bakeshop;

namespace {

template <class M, class D, class O>
void bind_blend(nb::module_& m) {
  m.def(
      "blend_texels",
      [](int method, In<M, 2> macro, In<D, 2> detail, In<O, 1> strength, Out<O, 2> out) {
        const size_t n = macro.shape(0);
        require(macro.shape(1) == 3 && detail.shape(0) == n && detail.shape(1) == 3 &&
                    out.shape(0) == n && out.shape(1) == 3,
                "blend_texels: macro, detail and out must be (N, 3)");
        require(strength.shape(0) == 1 || strength.shape(0) == n,
                "blend_texels: strength must be (1,) or (N,)");
        require(strength.shape(0) >= 1, "blend_texels: strength is empty");
        normals::blend_texels(method, macro.data(), detail.data(), strength.data(),
                              strength.shape(0) > 1, static_cast<index_t>(n), out.data());
      },
      "method"_a, "macro"_a.noconvert(), "detail"_a.noconvert(), "strength"_a.noconvert(),
      "out"_a.noconvert(), release_gil());
}

// The chain of (texels, offsets, shapes), checked.
normals::Chain chain_of(const In<float, 2>& texels, const In<int64_t, 1>& offsets,
                        const In<int64_t, 2>& shapes) {
  require(shapes.shape(0) == offsets.shape(0) && shapes.shape(1) == 2,
          "a mip chain's shapes must be (L, 2) with its (L,) offsets");
  normals::Chain c{texels.data(), static_cast<index_t>(texels.shape(1)), offsets.data(),
                   shapes.data(), static_cast<index_t>(offsets.shape(0))};
  require(normals::chain_ok(c, static_cast<index_t>(texels.shape(0))),
          "a mip chain's levels must lie within its texels");
  return c;
}

}  // namespace

NB_MODULE(_native, m) {
  bind_blend<float, float, float>(m);
  bind_blend<float, double, float>(m);
  bind_blend<double, float, float>(m);
  bind_blend<double, double, double>(m);

  m.def(
      "sample_points",
      [](In<float, 2> texels, In<int64_t, 1> offsets, In<int64_t, 2> shapes, In<double, 1> xs,
         In<double, 1> ys, In<double, 1> lods, bool wrap, Out<float, 2> out) {
        const normals::Chain c = chain_of(texels, offsets, shapes);
        const size_t n = xs.shape(0);
        require(ys.shape(0) == n && lods.shape(0) == n && out.shape(0) == n &&
                    out.shape(1) == texels.shape(1),
                "sample_points: xs, ys, lods must be (N,) and out (N, C)");
        normals::sample_points(c, xs.data(), ys.data(), lods.data(), static_cast<index_t>(n),
                               wrap, out.data());
      },
      "texels"_a, "offsets"_a, "shapes"_a, "xs"_a, "ys"_a, "lods"_a, "wrap"_a,
      "out"_a.noconvert(), release_gil());

  m.def(
      "place",
      [](In<float, 2> texels, In<int64_t, 1> offsets, In<int64_t, 2> shapes, double lod,
         In<double, 2> affine, double cos_r, double sin_r, double sign_x, double sign_y,
         Out<float, 3> out) {
        const normals::Chain c = chain_of(texels, offsets, shapes);
        require(c.channels == 3 && out.shape(2) == 3, "place: the detail and out must be 3-vectors");
        require(affine.shape(0) == 3 && affine.shape(1) == 3, "place: affine must be (3, 3)");
        normals::place(c, lod, affine.data(), cos_r, sin_r, sign_x, sign_y,
                       static_cast<index_t>(out.shape(0)), static_cast<index_t>(out.shape(1)),
                       out.data());
      },
      "texels"_a, "offsets"_a, "shapes"_a, "lod"_a, "affine"_a, "cos_r"_a, "sin_r"_a,
      "sign_x"_a, "sign_y"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "rasterize",
      [](In<double, 2> tex, In<int64_t, 2> faces, Out<int32_t, 2> face_map, Out<double, 3> bary) {
        const index_t v = tex.shape(0), f = faces.shape(0);
        const index_t h = face_map.shape(0), w = face_map.shape(1);
        require(tex.shape(1) == 2 && faces.shape(1) == 3, "rasterize: tex (V, 2), faces (F, 3)");
        require(bary.shape(0) == static_cast<size_t>(h) && bary.shape(1) == static_cast<size_t>(w) &&
                    bary.shape(2) == 3,
                "rasterize: bary must be (H, W, 3) of face_map (H, W)");
        require(f <= (index_t{1} << 31), "rasterize: too many faces for int32 indices");
        const int64_t* fs = faces.data();
        for (index_t k = 0; k < 3 * f; ++k)
          require(fs[k] >= 0 && fs[k] < v, "rasterize: a face indexes a vertex that does not exist");
        normals::rasterize(tex.data(), fs, f, h, w, face_map.data(), bary.data());
      },
      "tex"_a, "faces"_a, "face_map"_a.noconvert(), "bary"_a.noconvert(), release_gil());

  m.def(
      "dilate",
      [](Out<uint8_t, 3> out, Out<bool, 2> filled, int64_t rings) {
        require(out.shape(0) == filled.shape(0) && out.shape(1) == filled.shape(1),
                "dilate: out (H, W, bytes) and filled (H, W) must match");
        normals::dilate(out.data(), static_cast<index_t>(out.shape(2)), filled.data(),
                        static_cast<index_t>(out.shape(0)), static_cast<index_t>(out.shape(1)),
                        rings);
      },
      "out"_a.noconvert(), "filled"_a.noconvert(), "rings"_a, release_gil());

  m.def(
      "world_to_tangent",
      [](In<double, 2> world, In<double, 2> tangent, In<double, 1> sign, In<double, 2> normal,
         Out<double, 2> out) {
        const size_t n = world.shape(0);
        require(world.shape(1) == 3 && tangent.shape(0) == n && tangent.shape(1) == 3 &&
                    sign.shape(0) == n && normal.shape(0) == n && normal.shape(1) == 3 &&
                    out.shape(0) == n && out.shape(1) == 3,
                "world_to_tangent: world, tangent, normal, out must be (N, 3) and sign (N,)");
        normals::world_to_tangent(world.data(), tangent.data(), sign.data(), normal.data(),
                                  static_cast<index_t>(n), out.data());
      },
      "world"_a, "tangent"_a, "sign"_a, "normal"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "shade",
      [](In<int64_t, 1> texels_idx, In<int32_t, 1> face_of, In<double, 2> bary,
         In<int64_t, 2> faces, In<double, 2> normals_, In<double, 2> positions,
         In<double, 2> uv2, In<double, 3> frame, In<double, 3> frame2, In<float, 2> texels,
         In<int64_t, 1> offsets, In<int64_t, 2> shapes, In<double, 2> lod,
         In<int64_t, 1> box_axis, int mode, int64_t axis, double sharpness,
         In<double, 1> place, In<double, 3> axes, Out<float, 2> out) {
        const size_t f = faces.shape(0), v = normals_.shape(0), t = face_of.shape(0);
        require(faces.shape(1) == 3 && normals_.shape(1) == 3 && positions.shape(0) == v &&
                    positions.shape(1) == 3 && uv2.shape(0) == v && uv2.shape(1) == 2,
                "shade: faces (F, 3), normals and positions (V, 3), uv2 (V, 2)");
        require(frame.shape(0) == f && frame.shape(1) == 3 && frame.shape(2) == 4 &&
                    frame2.shape(0) == f && frame2.shape(1) == 3 && frame2.shape(2) == 4,
                "shade: the frames must be (F, 3, 4)");
        require(bary.shape(0) == t && bary.shape(1) == 3 && out.shape(0) == t &&
                    out.shape(1) == 3,
                "shade: bary and out must be (H W, 3) of face_of (H W,)");
        require(mode >= 0 && mode <= 3, "shade: unknown projection");
        require(lod.shape(0) == f && lod.shape(1) >= (mode == 0 ? 1u : 3u),
                "shade: lod must be (F, 1) for uv2, (F, 3) for the projections");
        require(box_axis.shape(0) == f && place.shape(0) == 8 && axes.shape(0) == 3 &&
                    axes.shape(1) == 2 && axes.shape(2) == 3,
                "shade: box_axis (F,), place (8,), axes (3, 2, 3)");
        const normals::Chain c = chain_of(texels, offsets, shapes);
        require(c.channels == 3, "shade: the detail must be 3-vectors");
        const int64_t* fs = faces.data();
        for (size_t k = 0; k < 3 * f; ++k)
          require(fs[k] >= 0 && static_cast<size_t>(fs[k]) < v,
                  "shade: a face indexes a vertex that does not exist");
        const normals::ShadeInputs in{face_of.data(), bary.data(), static_cast<index_t>(t),
                                      fs, static_cast<index_t>(f), normals_.data(),
                                      positions.data(), uv2.data(), frame.data(), frame2.data(),
                                      c, lod.data(), static_cast<index_t>(lod.shape(1)),
                                      box_axis.data(), mode, axis, sharpness, place.data(),
                                      axes.data()};
        normals::shade(in, texels_idx.data(), static_cast<index_t>(texels_idx.shape(0)),
                       out.data());
      },
      "texels_idx"_a, "face_of"_a, "bary"_a, "faces"_a, "normals"_a, "positions"_a, "uv2"_a,
      "frame"_a, "frame2"_a, "texels"_a, "offsets"_a, "shapes"_a, "lod"_a, "box_axis"_a,
      "mode"_a, "axis"_a, "sharpness"_a, "place"_a, "axes"_a, "out"_a.noconvert(),
      release_gil());
}
