// The lowest hull points of bakeshop/buoyancy/metrics.py (clearance).
#pragma once

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
    index_t best = 0;
    double low = std::numeric_limits<double>::infinity();
    for (index_t v = 0; v < vertices; ++v) {
      const double* p = hull + 3 * v;
      const double y = r[1][0] * p[0] + r[1][1] * p[1] + r[1][2] * p[2];
      if (y < low) best = v, low = y;
    }
    const double* p = hull + 3 * best;
    for (int a = 0; a < 3; ++a)
      out[3 * s + a] = position[3 * s + a] + (r[a][0] * p[0] + r[a][1] * p[1] + r[a][2] * p[2]);
  }
}

}  // namespace bakeshop::buoyancy
