// A part of a remap from a window of its source (bakeshop/sphere/windows.py): the taps of a
// rectangle of the destination, computed as the whole remap's plan computes them (gather.hpp:
// the same maps, the same bilinear_taps), so that a remap made part by part is bit-identical.
#pragma once

#include <cmath>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/gather.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::sphere {

// Source taps (and fractions, bilinear) of destination texels rows j0..j1 x columns i0..i1 of
// face f: taps ((j1 - j0) (i1 - i0), cols), frac (same, 2) unless nearest.
inline void part_taps(int skind, index_t sh, index_t sw, int dkind, index_t dh, index_t dw,
                      const double* rot, index_t f, index_t j0, index_t j1, index_t i0,
                      index_t i1, bool nearest, int32_t* taps, index_t cols, float* frac) {
  const index_t m = std::max(dh, dw);
  const std::vector<double> table = latlong_table(dh, dw);
  const double* trig = table.data();
  const index_t nw = i1 - i0;
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < j1 - j0; ++r) {
    const index_t j = j0 + r;
    for (index_t c = 0; c < nw; ++c) {
      const index_t i = i0 + c;
      const index_t p = r * nw + c;
      const Vec3 d = plan_direction(dkind, dh, dw, f, i, j, rot, trig, m);
      double sf = 0, sx, sy;
      if (skind == LATLONG) {
        latlong_xy(sh, sw, d.x, d.y, d.z, sx, sy);
      } else {
        const Coords s = coordinates(skind, sh, sw, d.x, d.y, d.z);
        sf = s.f;
        sx = s.x;
        sy = s.y;
      }
      int32_t* t = taps + p * cols;
      if (!valid(dkind, dh, dw, static_cast<double>(f), i, j) || !finite_coordinate(sx, sy)) {
        for (index_t k = 0; k < cols; ++k) t[k] = -1;
      } else if (nearest) {
        // (resolve of the texel containing the point, as the old JIT's _part_taps did: unlike
        // nearest_texel, a cube face does not own its far edges here)
        t[0] = static_cast<int32_t>(resolve(skind, sh, sw, sf, floor_index(sx), floor_index(sy), sx));
      } else {
        bilinear_taps(skind, sh, sw, sf, sx, sy, t, frac + 2 * p);
      }
    }
  }
}

// Flat directions (n, 3) of the latlong (h, w) texels rows top..bottom x columns left..right.
inline void latlong_window(index_t h, index_t w, index_t top, index_t bottom, index_t left,
                           index_t right, double* dirs) {
  const index_t m = std::max(h, w);
  const std::vector<double> table = latlong_table(h, w);
  const double* trig = table.data();
  const index_t nw = right - left;
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < bottom - top; ++r) {
    const double st = trig[2 * m + top + r], ct = trig[3 * m + top + r];
    for (index_t c = 0; c < nw; ++c) {
      double* d = dirs + 3 * (r * nw + c);
      d[0] = st * trig[left + c];
      d[1] = ct;
      d[2] = -st * trig[m + left + c];
    }
  }
}

}  // namespace bakeshop::sphere
