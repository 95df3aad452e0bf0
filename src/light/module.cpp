// bakeshop.light._native: the kernels of bakeshop.light (diffuse irradiance, spherical
// harmonics, the sun's texel searches, fresnel, the DFG table, specular prefiltering).
#include <vector>

#include "common/bind.hpp"
#include "light/dfg.hpp"
#include "light/diffuse.hpp"
#include "light/fresnel.hpp"
#include "light/sh/harmonics.hpp"
#include "light/specular.hpp"
#include "light/sun_texels.hpp"

using namespace bakeshop;

namespace {

// An input at any strides (the sun's search reads column slices of an image in place).
template <class T, size_t N>
using Strided = nb::ndarray<const T, nb::numpy, nb::ndim<N>, nb::device::cpu>;

size_t sz(index_t v) { return static_cast<size_t>(v); }

// A 1-D int64 numpy array that owns `values` (called with the GIL held).
nb::ndarray<nb::numpy, int64_t, nb::ndim<1>> owned(std::vector<int64_t>&& values) {
  auto* held = new std::vector<int64_t>(std::move(values));
  nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::vector<int64_t>*>(p); });
  return nb::ndarray<nb::numpy, int64_t, nb::ndim<1>>(held->data(), {held->size()}, owner);
}

light::Cones cones(const In<int64_t, 1>& starts, const In<double, 2>& axes,
                   const In<double, 1>& sin_half, const In<double, 3>& linear, index_t members,
                   const char* what) {
  const size_t g = axes.shape(0);
  require(starts.shape(0) == g + 1 && axes.shape(1) == 3 && sin_half.shape(0) == g &&
              linear.shape(0) == g && linear.shape(1) == 3 && linear.shape(2) == 3,
          what);
  require(light::cones_valid(starts.data(), static_cast<index_t>(g), members), what);
  return {starts.data(), axes.data(), sin_half.data(), linear.data(), static_cast<index_t>(g)};
}

template <class T>
void bind_typed(nb::module_& m) {
  m.def(
      "accumulate",
      [](In<T, 2> values, In<double, 2> dirs, In<double, 1> omega, In<int64_t, 1> subset,
         Out<int64_t, 1> index, index_t n_bins, index_t chunks, int64_t size, index_t colour,
         Out<double, 2> sums) {
        const index_t n = values.shape(0), channels = values.shape(1);
        require(dirs.shape(0) == sz(n) && dirs.shape(1) == 3 && omega.shape(0) == sz(n),
                "accumulate: values, dirs and omega must describe the same texels");
        require(subset.shape(0) == 0 ? index.shape(0) == sz(n) : index.shape(0) == subset.shape(0),
                "accumulate: index must have one entry per texel");
        require(n_bins >= 0 && chunks >= 1 && colour >= 0 && colour <= channels &&
                    size < (int64_t(1) << 28),
                "accumulate: bad bin count, chunk count, bin size or colour");
        require(sums.shape(0) == sz(n_bins) && sums.shape(1) == sz(channels + 5),
                "accumulate: sums must be (n_bins, channels + 5)");
        require(size <= 0 || 6 * size * size <= n_bins, "accumulate: n_bins < 6 size^2");
        light::accumulate(values.data(), channels, n, dirs.data(), omega.data(), subset.data(),
                          static_cast<index_t>(subset.shape(0)), index.data(),
                          static_cast<index_t>(index.shape(0)), n_bins, chunks, size, colour,
                          sums.data());
      },
      "values"_a, "dirs"_a, "omega"_a, "subset"_a, "index"_a.noconvert(), "n_bins"_a,
      "chunks"_a, "size"_a, "colour"_a, "sums"_a.noconvert(), release_gil());

  m.def(
      "energy",
      [](In<T, 2> values, In<double, 1> omega, index_t colour) {
        const index_t n = values.shape(0), channels = values.shape(1);
        require(omega.shape(0) == sz(n), "energy: values and omega must describe the same texels");
        require(colour >= 0 && colour <= channels, "energy: colour must be at most the channels");
        return light::energy(values.data(), channels, n, omega.data(), colour);
      },
      "values"_a, "omega"_a, "colour"_a, release_gil());

  m.def(
      "project",
      [](In<T, 2> values, In<double, 2> dirs, In<double, 1> weights, int order, index_t chunks,
         Out<double, 2> out) {
        const index_t n = values.shape(0), channels = values.shape(1);
        require(order >= 0 && order <= 256 && chunks >= 1, "project: bad order or chunk count");
        require(dirs.shape(0) == sz(n) && dirs.shape(1) == 3 && weights.shape(0) == sz(n),
                "project: values, directions and weights must describe the same texels");
        require(out.shape(0) == sz((order + 1) * (order + 1)) && out.shape(1) == sz(channels),
                "project: out must be ((order + 1)^2, channels)");
        light::sh::project(values.data(), channels, dirs.data(), weights.data(), n, order, chunks,
                           out.data());
      },
      "values"_a, "dirs"_a, "weights"_a, "order"_a, "chunks"_a, "out"_a.noconvert(),
      release_gil());

  m.def(
      "project_order2",
      [](In<T, 2> values, In<double, 2> dirs, In<double, 1> weights, index_t chunks,
         Out<double, 2> out) {
        const index_t n = values.shape(0), channels = values.shape(1);
        require(chunks >= 1, "project_order2: bad chunk count");
        require(dirs.shape(0) == sz(n) && dirs.shape(1) == 3 && weights.shape(0) == sz(n),
                "project_order2: values, directions and weights must describe the same texels");
        require(out.shape(0) == 9 && out.shape(1) == sz(channels),
                "project_order2: out must be (9, channels)");
        light::sh::project_order2(values.data(), channels, dirs.data(), weights.data(), n, chunks,
                                  out.data());
      },
      "values"_a, "dirs"_a, "weights"_a, "chunks"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "apply_reflectance",
      [](In<double, 1> cos, double n, In<T, 2> image, Out<T, 2> out, index_t colour) {
        const index_t p = cos.shape(0), channels = image.shape(1);
        require(image.shape(0) == sz(p) && out.shape(0) == sz(p) && out.shape(1) == sz(channels),
                "apply_reflectance: cos, image and out must describe the same texels");
        require(colour >= 0 && colour <= channels, "apply_reflectance: bad colour count");
        light::apply_reflectance(cos.data(), p, n, image.data(), channels, out.data(), colour);
      },
      "cos"_a, "n"_a, "image"_a, "out"_a.noconvert(), "colour"_a, release_gil());

  m.def(
      "brightest",
      [](Strided<T, 2> values, Strided<T, 1> weights, In<double, 1> omega, In<double, 2> dirs,
         In<double, 1> centre, double cos_limit) {
        const index_t n = values.shape(0), channels = values.shape(1);
        require(channels >= 1 && omega.shape(0) == sz(n),
                "brightest: values and omega must describe the same texels");
        require(channels < 3 || weights.shape(0) >= 3, "brightest: three luminance weights");
        require(dirs.shape(1) == 3 && (cos_limit > 1.0 || dirs.shape(0) == sz(n)),
                "brightest: dirs must be (n, 3) unless cos_limit > 1");
        require(centre.shape(0) == 3, "brightest: centre must be a 3-vector");
        const T w[3] = {weights.shape(0) > 0 ? weights(0) : T(0),
                        weights.shape(0) > 1 ? weights(1) : T(0),
                        weights.shape(0) > 2 ? weights(2) : T(0)};
        return light::brightest(values.data(), values.stride(0), values.stride(1), channels, n, w,
                                omega.data(), dirs.data(), centre.data(), cos_limit);
      },
      "values"_a, "weights"_a, "omega"_a, "dirs"_a, "centre"_a, "cos_limit"_a, release_gil());
}

}  // namespace

NB_MODULE(_native, m) {
  // --- diffuse ---
  m.def(
      "cosine_sum",
      [](In<double, 2> normals, In<double, 2> dirs, In<double, 2> energy,
         In<int64_t, 1> g_starts, In<double, 2> g_axes, In<double, 1> g_sin,
         In<double, 3> g_linear, In<int64_t, 1> s_starts, In<double, 2> s_axes,
         In<double, 1> s_sin, In<double, 3> s_linear, Out<double, 2> out) {
        const index_t m = normals.shape(0), n = dirs.shape(1);
        require(normals.shape(1) == 3 && out.shape(0) == sz(m) && out.shape(1) == 3,
                "cosine_sum: normals and out must be (M, 3)");
        require(dirs.shape(0) == 3 && energy.shape(0) == 3 && energy.shape(1) == sz(n),
                "cosine_sum: dirs and energy must be (3, N)");
        const light::Cones groups = cones(g_starts, g_axes, g_sin, g_linear, n,
                                          "cosine_sum: the groups do not cover the sources");
        const light::Cones supers =
            cones(s_starts, s_axes, s_sin, s_linear, groups.count,
                  "cosine_sum: the large cones do not cover the groups");
        light::cosine_sum(normals.data(), m, dirs.data(), energy.data(), n, groups, supers,
                          out.data());
      },
      "normals"_a, "dirs"_a, "energy"_a, "g_starts"_a, "g_axes"_a, "g_sin"_a, "g_linear"_a,
      "s_starts"_a, "s_axes"_a, "s_sin"_a, "s_linear"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "bins",
      [](In<double, 2> dirs, In<int64_t, 1> subset, int64_t size, Out<int64_t, 1> out) {
        require(dirs.shape(1) == 3, "bins: dirs must be (N, 3)");
        require(size >= 1 && size < (int64_t(1) << 28), "bins: bad bin size");
        require(out.shape(0) == (subset.shape(0) > 0 ? subset.shape(0) : dirs.shape(0)),
                "bins: out must have one entry per texel");
        light::bins(dirs.data(), static_cast<index_t>(dirs.shape(0)), subset.data(),
                    static_cast<index_t>(subset.shape(0)), size, out.data());
      },
      "dirs"_a, "subset"_a, "size"_a, "out"_a.noconvert(), release_gil());

  // --- spherical harmonics ---
  m.def(
      "basis_rows",
      [](In<double, 2> dirs, int order, Out<double, 2> out) {
        require(order >= 0 && order <= 256, "basis_rows: bad order");
        require(dirs.shape(1) == 3 && out.shape(0) == dirs.shape(0) &&
                    out.shape(1) == sz((order + 1) * (order + 1)),
                "basis_rows: dirs must be (N, 3) and out (N, (order + 1)^2)");
        light::sh::basis_rows(dirs.data(), static_cast<index_t>(dirs.shape(0)), order,
                              out.data());
      },
      "dirs"_a, "order"_a, "out"_a.noconvert(), release_gil());

  // --- the sun's texels ---
  m.def(
      "cap",
      [](In<double, 2> dirs, In<double, 1> omega, In<double, 1> centre, double cos_limit) {
        require(dirs.shape(1) == 3 && omega.shape(0) == dirs.shape(0),
                "cap: dirs (n, 3) and omega (n,) must describe the same texels");
        require(centre.shape(0) == 3, "cap: centre must be a 3-vector");
        std::vector<int64_t> index;
        {
          nb::gil_scoped_release release;
          index = light::cap(dirs.data(), omega.data(), static_cast<index_t>(dirs.shape(0)),
                             centre.data(), cos_limit);
        }
        return owned(std::move(index));
      },
      "dirs"_a, "omega"_a, "centre"_a, "cos_limit"_a);

  // --- fresnel ---
  m.def(
      "reflectance",
      [](In<double, 1> c, double n, Out<double, 1> out) {
        require(out.shape(0) == c.shape(0), "reflectance: out must have the shape of c");
        light::reflectance_array(c.data(), static_cast<index_t>(c.shape(0)), n, out.data());
      },
      "c"_a, "n"_a, "out"_a.noconvert(), release_gil());

  // --- DFG ---
  m.def(
      "dfg_terms",
      [](In<double, 1> n_dot_v, In<double, 1> roughness, In<double, 2> xi, bool schlick,
         Out<double, 2> out) {
        const size_t n = n_dot_v.shape(0);
        require(roughness.shape(0) == n && out.shape(0) == n && out.shape(1) == 2,
                "dfg_terms: n_dot_v, roughness (n,) and out (n, 2)");
        require(xi.shape(0) >= 1 && xi.shape(1) == 2, "dfg_terms: xi must be (K >= 1, 2)");
        light::dfg_terms(n_dot_v.data(), roughness.data(), static_cast<index_t>(n), xi.data(),
                         static_cast<index_t>(xi.shape(0)), schlick, out.data());
      },
      "n_dot_v"_a, "roughness"_a, "xi"_a, "schlick"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "dfg_grid",
      [](In<double, 1> n_dot_v, In<double, 1> roughness, In<double, 2> xi, bool schlick,
         Out<double, 2> out) {
        const size_t w = n_dot_v.shape(0), r = roughness.shape(0);
        require(out.shape(0) == w * r && out.shape(1) == 2,
                "dfg_grid: out must be (rows * columns, 2)");
        require(xi.shape(0) >= 1 && xi.shape(1) == 2, "dfg_grid: xi must be (K >= 1, 2)");
        light::dfg_grid(n_dot_v.data(), static_cast<index_t>(w), roughness.data(),
                        static_cast<index_t>(r), xi.data(), static_cast<index_t>(xi.shape(0)),
                        schlick, out.data());
      },
      "n_dot_v"_a, "roughness"_a, "xi"_a, "schlick"_a, "out"_a.noconvert(), release_gil());

  // --- specular ---
  m.def(
      "filter",
      [](In<double, 2> dirs, In<double, 2> samples, In<float, 1> pyramid, In<int64_t, 1> offsets,
         In<int64_t, 1> sizes, double lod_bias, In<double, 1> log2_fit, Out<double, 2> out) {
        require(dirs.shape(1) == 3 && out.shape(0) == dirs.shape(0) && out.shape(1) == 4,
                "filter: dirs must be (n, 3) and out (n, 4)");
        require(samples.shape(1) == 5, "filter: samples must be (K, 5)");
        require(log2_fit.shape(0) >= 1, "filter: an empty log2 fit");
        require(offsets.shape(0) == sizes.shape(0), "filter: one offset per level");
        const light::Pyramid pyr{pyramid.data(), offsets.data(), sizes.data(),
                                 static_cast<index_t>(sizes.shape(0))};
        require(light::pyramid_valid(pyr, static_cast<index_t>(pyramid.shape(0))),
                "filter: a pyramid level lies outside the array");
        light::filter(dirs.data(), static_cast<index_t>(dirs.shape(0)), samples.data(),
                      static_cast<index_t>(samples.shape(0)), pyr, lod_bias, log2_fit.data(),
                      static_cast<index_t>(log2_fit.shape(0)), out.data());
      },
      "dirs"_a, "samples"_a, "pyramid"_a, "offsets"_a, "sizes"_a, "lod_bias"_a, "log2_fit"_a,
      "out"_a.noconvert(), release_gil());

  m.def(
      "lobe",
      [](In<double, 2> dirs, In<double, 2> src_dirs, In<double, 1> src_omega,
         In<double, 2> src_values, bool ggx, double param, double cos_cut, Out<double, 2> acc,
         Out<double, 1> total) {
        const size_t n = dirs.shape(0), m = src_dirs.shape(0), c = src_values.shape(1);
        require(dirs.shape(1) == 3 && src_dirs.shape(1) == 3, "lobe: directions must be (., 3)");
        require(src_omega.shape(0) == m && src_values.shape(0) == m,
                "lobe: the sources' directions, solid angles and values differ in count");
        require(acc.shape(0) == n && acc.shape(1) == c && total.shape(0) == n,
                "lobe: acc must be (n, channels) and total (n,)");
        light::lobe(dirs.data(), static_cast<index_t>(n), src_dirs.data(), src_omega.data(),
                    src_values.data(), static_cast<index_t>(m), static_cast<index_t>(c), ggx,
                    param, cos_cut, acc.data(), total.data());
      },
      "dirs"_a, "src_dirs"_a, "src_omega"_a, "src_values"_a, "ggx"_a, "param"_a, "cos_cut"_a,
      "acc"_a.noconvert(), "total"_a.noconvert(), release_gil());

  bind_typed<float>(m);
  bind_typed<double>(m);
}
