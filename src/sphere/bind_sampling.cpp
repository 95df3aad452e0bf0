// bakeshop.sphere._native, the sampling half: the layouts' maps (maps.hpp) and the remap
// plans and gathers (gather.hpp, windows.hpp, texels.hpp).
#include <nanobind/stl/tuple.h>

#include <tuple>

#include "common/bind.hpp"
#include "sphere/maps.hpp"

using namespace bakeshop;

namespace {

void check_kind(int kind, index_t h, index_t w) {
  require(kind >= sphere::LATLONG && kind <= sphere::OPENEXR_CUBE, "unknown layout kind");
  require(h > 0 && w > 0, "a layout's grid must be positive");
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
  // the scalar maps, for Python (bakeshop.sphere.kernels)
  m.def(
      "direction",
      [](int kind, index_t h, index_t w, double f, double x, double y) {
        check_kind(kind, h, w);
        const sphere::Vec3 d = sphere::direction(kind, h, w, f, x, y);
        return std::make_tuple(d.x, d.y, d.z);
      },
      "kind"_a, "h"_a, "w"_a, "f"_a, "x"_a, "y"_a);
  m.def(
      "coordinates",
      [](int kind, index_t h, index_t w, double x, double y, double z) {
        check_kind(kind, h, w);
        const sphere::Coords c = sphere::coordinates(kind, h, w, x, y, z);
        return std::make_tuple(c.f, c.x, c.y);
      },
      "kind"_a, "h"_a, "w"_a, "x"_a, "y"_a, "z"_a);
  m.def(
      "cube_face",
      [](double x, double y, double z) {
        const sphere::Face c = sphere::cube_face(x, y, z);
        return std::make_tuple(c.f, c.sc, c.tc);
      },
      "x"_a, "y"_a, "z"_a);
  m.def(
      "valid",
      [](int kind, index_t h, index_t w, double f, index_t i, index_t j) {
        check_kind(kind, h, w);
        return sphere::valid(kind, h, w, f, i, j);
      },
      "kind"_a, "h"_a, "w"_a, "f"_a, "i"_a, "j"_a);
}
