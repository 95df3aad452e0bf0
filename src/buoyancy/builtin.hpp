// The built-in integrator's step (bakeshop/buoyancy/builtin.py): semi-implicit Euler over the
// bodies, in the old JIT's operation order (3x3 products summed over j = 0, 1, 2).
#pragma once

#include <cmath>

#include "buoyancy/state.hpp"
#include "common/kernel.hpp"

namespace bakeshop::buoyancy {

// One step of length dt for B bodies: position, quaternion, velocity, omega (B, 3 | 4) in place
// under force and torque (B, 3), mass (B,), inertia and its inverse (B, 3, 3), gravity g.
inline void builtin_step(double* position, double* quaternion, double* velocity, double* omega,
                         const double* force, const double* torque, const double* mass,
                         const double* inertia, const double* inverse, index_t bodies, double dt,
                         double g) {
  for (index_t b = 0; b < bodies; ++b) {
    double* v = velocity + 3 * b;
    double* w = omega + 3 * b;
    double* x = position + 3 * b;
    double* q = quaternion + 4 * b;
    for (int a = 0; a < 3; ++a) v[a] += dt * force[3 * b + a] / mass[b];
    v[1] -= dt * g;
    const Mat3 r = rotation(q[0], q[1], q[2], q[3]);
    const double* tau = torque + 3 * b;
    const double* in = inertia + 9 * b;
    const double* inv = inverse + 9 * b;
    double wb[3], tb[3], lb[3], gyro[3], d[3];
    for (int i = 0; i < 3; ++i) {  // R^T w, R^T tau
      wb[i] = r[0][i] * w[0] + r[1][i] * w[1] + r[2][i] * w[2];
      tb[i] = r[0][i] * tau[0] + r[1][i] * tau[1] + r[2][i] * tau[2];
    }
    for (int i = 0; i < 3; ++i)
      lb[i] = in[3 * i] * wb[0] + in[3 * i + 1] * wb[1] + in[3 * i + 2] * wb[2];
    gyro[0] = wb[1] * lb[2] - wb[2] * lb[1];
    gyro[1] = wb[2] * lb[0] - wb[0] * lb[2];
    gyro[2] = wb[0] * lb[1] - wb[1] * lb[0];
    for (int i = 0; i < 3; ++i) d[i] = tb[i] - gyro[i];
    double nwb[3];
    for (int i = 0; i < 3; ++i)
      nwb[i] = wb[i] + dt * (inv[3 * i] * d[0] + inv[3 * i + 1] * d[1] + inv[3 * i + 2] * d[2]);
    for (int i = 0; i < 3; ++i) w[i] = r[i][0] * nwb[0] + r[i][1] * nwb[1] + r[i][2] * nwb[2];
    for (int a = 0; a < 3; ++a) x[a] += dt * v[a];
    // q <- dq q with dq the rotation by |w| dt about w
    const double wx = w[0], wy = w[1], wz = w[2];
    const double angle = std::sqrt(wx * wx + wy * wy + wz * wz) * dt;
    if (angle > 0.0) {
      const double s = std::sin(0.5 * angle) / (angle / dt);
      const double d0 = std::cos(0.5 * angle), d1 = wx * s, d2 = wy * s, d3 = wz * s;
      const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
      const double n0 = d0 * q0 - d1 * q1 - d2 * q2 - d3 * q3;
      const double n1 = d0 * q1 + d1 * q0 + d2 * q3 - d3 * q2;
      const double n2 = d0 * q2 - d1 * q3 + d2 * q0 + d3 * q1;
      const double n3 = d0 * q3 + d1 * q2 - d2 * q1 + d3 * q0;
      const double norm = std::sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3);
      q[0] = n0 / norm, q[1] = n1 / norm, q[2] = n2 / norm, q[3] = n3 / norm;
    }
  }
}

}  // namespace bakeshop::buoyancy
