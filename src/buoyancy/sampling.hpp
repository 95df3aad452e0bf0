// Voxelisation of a closed mesh into buoyancy sample points (bakeshop/buoyancy/sampling.py):
// vertical rays crossed with the triangles (CSR lists of hits per ray), then the inside
// intervals of every ray integrated into the cells.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::buoyancy {

namespace detail {

// max(ceil(v), 0) as an index, or `past` (an empty range) when it lies beyond `last`.
inline index_t first_index(double v, index_t last) {
  const double c = std::ceil(v);
  if (!(c > 0)) return 0;
  return c > static_cast<double>(last) ? last + 1 : static_cast<index_t>(c);
}

// min(floor(v), last) as an index, -1 (an empty range) below 0.
inline index_t last_index(double v, index_t last) {
  const double f = std::floor(v);
  if (!(f >= 0)) return -1;
  return f >= static_cast<double>(last) ? last : static_cast<index_t>(f);
}

}  // namespace detail

// Intersect every vertical ray (i, k) at (x0 + (i + 0.5) step, z0 + (k + 0.5) step), i < nx,
// k < nz, with the triangles (T, 3, 3). Without `fill` only counts[ray] += 1 per hit; with it,
// also the hit's height and winding sign (+1 entering the solid going up, -1 leaving) at
// offsets[ray] + counts[ray] (the caller's CSR from the counting pass; a slot past the lists is
// refused). Triangles with a coordinate that is not finite cross no ray.
inline void crossings(const double* triangles, index_t count, double x0, double z0, double step,
                      index_t nx, index_t nz, int64_t* counts, double* hits_y, int64_t* hits_w,
                      const int64_t* offsets, index_t hits, bool fill) {
  for (index_t t = 0; t < count; ++t) {
    const double* p = triangles + 9 * t;
    bool finite = true;
    for (int j = 0; j < 9; ++j) finite = finite && std::isfinite(p[j]);
    if (!finite) continue;
    const double ax = p[0], ay = p[1], az = p[2];
    const double bx = p[3], by = p[4], bz = p[5];
    const double cx = p[6], cy = p[7], cz = p[8];
    // y component of (b - a) x (c - a): sign tells up- or down-facing.
    const double ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az);
    if (ny == 0.0) continue;
    const int64_t sign = ny > 0 ? -1 : 1;
    const index_t i0 = detail::first_index((std::min({ax, bx, cx}) - x0) / step - 0.5, nx - 1);
    const index_t i1 = detail::last_index((std::max({ax, bx, cx}) - x0) / step - 0.5, nx - 1);
    const index_t k0 = detail::first_index((std::min({az, bz, cz}) - z0) / step - 0.5, nz - 1);
    const index_t k1 = detail::last_index((std::max({az, bz, cz}) - z0) / step - 0.5, nz - 1);
    for (index_t i = i0; i <= i1; ++i) {
      const double px = x0 + (static_cast<double>(i) + 0.5) * step;
      for (index_t k = k0; k <= k1; ++k) {
        const double pz = z0 + (static_cast<double>(k) + 0.5) * step;
        // Barycentric weights of (px, pz) in the projected triangle.
        const double wa = ((bz - pz) * (cx - px) - (bx - px) * (cz - pz)) / ny;
        const double wb = ((cz - pz) * (ax - px) - (cx - px) * (az - pz)) / ny;
        const double wc = 1.0 - wa - wb;
        if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
        const index_t ray = i * nz + k;
        if (fill) {
          const int64_t j = offsets[ray] + counts[ray];
          if (j < offsets[ray] || j >= offsets[ray + 1] || j >= hits)
            throw std::invalid_argument("crossings: more hits than the counting pass found");
          hits_y[j] = wa * ay + wb * by + wc * cy;
          hits_w[j] = sign;
        }
        counts[ray] += 1;
      }
    }
  }
}

// Integrate the inside intervals of every ray into the cells (shape nx, ny, nz; `sub` rays per
// cell side; one thread per cell column): volume, first moments (n, 3) and the horizontal
// area of rays that meet solid in the cell. offsets (nx sub * nz sub + 1) are checked by the
// caller.
inline void accumulate(const double* hits_y, const int64_t* hits_w, const int64_t* offsets,
                       double x0, double y0, double z0, double cell, index_t nx, index_t ny,
                       index_t nz, index_t sub, double* volume, double* moment, double* area) {
  std::vector<int64_t> last_ray(static_cast<size_t>(nx * ny * nz), -1);
  const double step = cell / static_cast<double>(sub);
  const double ray_area = step * step;
  // heights in ascending order, NaN last (a strict weak order even then)
  const auto below = [hits_y](int64_t a, int64_t b) {
    const double ya = hits_y[a], yb = hits_y[b];
    return ya < yb || (!std::isnan(ya) && std::isnan(yb));
  };
#pragma omp parallel
  {
    std::vector<int64_t> order;
#pragma omp for schedule(static)
    for (index_t c = 0; c < nx * nz; ++c) {
      const index_t ci = c / nz, ck = c % nz;
      for (index_t si = 0; si < sub; ++si) {
        const index_t i = ci * sub + si;
        const double px = x0 + (static_cast<double>(i) + 0.5) * step;
        for (index_t sk = 0; sk < sub; ++sk) {
          const index_t k = ck * sub + sk;
          const double pz = z0 + (static_cast<double>(k) + 0.5) * step;
          const int64_t ray = i * (nz * sub) + k;
          const int64_t start = offsets[ray], stop = offsets[ray + 1];
          if (stop - start < 2) continue;
          order.resize(static_cast<size_t>(stop - start));
          for (int64_t h = start; h < stop; ++h) order[h - start] = h;
          std::sort(order.begin(), order.end(), below);
          int64_t winding = 0;
          for (size_t h = 0; h + 1 < order.size(); ++h) {
            winding += hits_w[order[h]];
            if (winding <= 0) continue;
            const double ya = hits_y[order[h]];
            const double yb = hits_y[order[h + 1]];
            // int() truncates toward zero, as the old JIT did
            const double ta = std::trunc((ya - y0) / cell), tb = std::trunc((yb - y0) / cell);
            const index_t ja =
                ta > 0 ? (ta >= static_cast<double>(ny) ? ny : static_cast<index_t>(ta)) : 0;
            const index_t jb = !(tb >= 0) ? -1
                               : tb >= static_cast<double>(ny - 1) ? ny - 1
                                                                   : static_cast<index_t>(tb);
            for (index_t j = ja; j <= jb; ++j) {
              const double lo = std::max(ya, y0 + static_cast<double>(j) * cell);
              const double hi = std::min(yb, y0 + static_cast<double>(j + 1) * cell);
              if (hi <= lo) continue;
              const double v = (hi - lo) * ray_area;
              const index_t cell_index = (ci * ny + j) * nz + ck;
              if (last_ray[cell_index] != ray) {
                last_ray[cell_index] = ray;
                area[cell_index] += ray_area;
              }
              volume[cell_index] += v;
              moment[3 * cell_index] += v * px;
              moment[3 * cell_index + 1] += v * 0.5 * (lo + hi);
              moment[3 * cell_index + 2] += v * pz;
            }
          }
        }
      }
    }
  }
}

}  // namespace bakeshop::buoyancy
