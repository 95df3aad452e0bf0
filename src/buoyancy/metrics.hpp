// The lowest hull points of bakeshop/buoyancy/metrics.py (clearance).
#pragma once

#include <algorithm>
#include <limits>

#include "buoyancy/state.hpp"
#include "common/kernel.hpp"

namespace bakeshop::buoyancy {

// out[s] = world position of the hull vertex (V, 3) lowest in y at recorded step s, from the
// step's quaternion (S, 4) and position (S, 3).
inline void lowest_points(const double* hull, index_t vertices, const double* quaternion,
                          const double* position, index_t steps, double* out) {
  for (index_t s = 0; s < steps; ++s) {
    const double* q = quaternion + 4 * s;
    const Mat3 r = rotation(q[0], q[1], q[2], q[3]);
    // blocks of vertex heights (a loop that vectorises), each block's lowest through four
    // independent minima (a single running minimum is a chain of dependent instructions), then
    // the block's first vertex at that height: the first lowest vertex, as a scan in order
    // with a strict `<` finds it
    constexpr index_t kBlock = 256;
    const double inf = std::numeric_limits<double>::infinity();
    double ys[kBlock];
    index_t best = 0;
    double low = inf;
    for (index_t start = 0; start < vertices; start += kBlock) {
      const index_t count = std::min(kBlock, vertices - start);
      const double* p = hull + 3 * start;
      for (index_t v = 0; v < count; ++v)
        ys[v] = r[1][0] * p[3 * v] + r[1][1] * p[3 * v + 1] + r[1][2] * p[3 * v + 2];
      double m[4] = {inf, inf, inf, inf};
      index_t v = 0;
      for (; v + 4 <= count; v += 4)
        for (int lane = 0; lane < 4; ++lane)
          m[lane] = ys[v + lane] < m[lane] ? ys[v + lane] : m[lane];
      for (; v < count; ++v) m[0] = ys[v] < m[0] ? ys[v] : m[0];
      double lowest = m[0];
      for (int lane = 1; lane < 4; ++lane) lowest = m[lane] < lowest ? m[lane] : lowest;
      if (lowest < low) {
        index_t first = 0;
        while (!(ys[first] == lowest)) ++first;
        best = start + first;
        low = ys[first];
      }
    }
    const double* p = hull + 3 * best;
    for (int a = 0; a < 3; ++a)
      out[3 * s + a] = position[3 * s + a] + (r[a][0] * p[0] + r[a][1] * p[1] + r[a][2] * p[2]);
  }
}

}  // namespace bakeshop::buoyancy
