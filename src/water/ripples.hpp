// The wave equation of bakeshop/water/ripples.py: one leapfrog step with the 9-point isotropic
// Laplacian, in the old JIT's operation order (a time stepper: the same order keeps the same bits).
#pragma once

#include "common/kernel.hpp"

namespace bakeshop::water {

// v <- (damp_a v + dt (c2 lap(h) + force)) / damp_b over the whole grid, then h <- h + dt v;
// rm/rp (rows) and cm/cp (columns) give each row's and column's neighbours (the edge
// condition), all in [0, rows) and [0, cols) (the caller checks).
inline void laplacian_step(double* h, double* v, index_t rows, index_t cols, double c2,
                           double damp_a, double damp_b, double dt, double dx2,
                           const double* force, const int64_t* rm, const int64_t* rp,
                           const int64_t* cm, const int64_t* cp) {
  const double scale = c2 / (6.0 * dx2);
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (index_t r = 0; r < rows; ++r) {
      const double* up = h + rm[r] * cols;
      const double* down = h + rp[r] * cols;
      const double* row = h + r * cols;
      for (index_t c = 0; c < cols; ++c) {
        const index_t left = cm[c], right = cp[c];
        const double edge = up[c] + down[c] + row[left] + row[right];
        const double corner = up[left] + up[right] + down[left] + down[right];
        const double lap = 4.0 * edge + corner - 20.0 * row[c];
        v[r * cols + c] = (damp_a * v[r * cols + c] + dt * (scale * lap + force[r * cols + c])) /
                          damp_b;
      }
    }
    // (the implicit barrier: every velocity is new before a height moves)
#pragma omp for schedule(static)
    for (index_t r = 0; r < rows; ++r)
      for (index_t c = 0; c < cols; ++c) h[r * cols + c] += dt * v[r * cols + c];
  }
}

}  // namespace bakeshop::water
