// Buoyancy, fluid friction and the predictive stabiliser per sample point
// (bakeshop/buoyancy/forces.py), one body per loop iteration. The old JIT ran this kernel with
// fastmath (its sums could be reordered); here every sum is taken in the points' order.
#pragma once

#include <algorithm>
#include <cmath>

#include "buoyancy/state.hpp"
#include "common/kernel.hpp"

namespace bakeshop::buoyancy {

// The water's surface height at (x, z) and time t: level plus the wave trains of `waves`
// (W, 6): amplitude, kx, kz, omega, phase, k.
inline double surface(const double* waves, index_t count, double level, double x, double z,
                      double t) {
  double eta = level;
  for (index_t w = 0; w < count; ++w) {
    const double* a = waves + 6 * w;
    eta += a[0] * std::sin(a[1] * x + a[2] * z - a[3] * t + a[4]);
  }
  return eta;
}

struct Fleet {
  const int64_t* offsets;  // (B + 1,), checked monotone and within the points
  const double* points;    // (P, 3)
  const double* volumes;   // (P,)
  const double* heights;   // (P,)
  const double* volume;    // (B,)
  const double* mass;      // (B,)
  const double* inertia;   // (B, 3, 3)
  index_t bodies;
};

struct Motion {
  const double* position;    // (B, 3)
  const double* quaternion;  // (B, 4)
  const double* velocity;    // (B, 3)
  const double* omega;       // (B, 3)
};

struct Model {
  const double* waves;  // (W, 6)
  index_t wave_count;
  double level, t, rho, g;
  int damping;  // 0 team, 1 drag, 2 none
  double c_lin, c_ang, c_drag;
  bool predict;
  double c_predict, m_predict, horizon;
};

// force, torque (B, 3), submerged_points (B,), submerged_volume (B,) written for every body.
inline void point_forces(const Fleet& fleet, const Motion& s, const Model& m, double* force,
                         double* torque, int64_t* submerged_points, double* submerged_volume) {
#pragma omp parallel for schedule(dynamic)
  for (index_t b = 0; b < fleet.bodies; ++b) {
    const double* q = s.quaternion + 4 * b;
    const Mat3 r = rotation(q[0], q[1], q[2], q[3]);
    const double px = s.position[3 * b], py = s.position[3 * b + 1], pz = s.position[3 * b + 2];
    const double vx = s.velocity[3 * b], vy = s.velocity[3 * b + 1], vz = s.velocity[3 * b + 2];
    const double wx = s.omega[3 * b], wy = s.omega[3 * b + 1], wz = s.omega[3 * b + 2];
    const double drag_k = 0.5 * m.rho * m.c_drag / std::pow(fleet.volume[b], 1.0 / 3.0);
    const double density = fleet.mass[b] / fleet.volume[b];
    double fx = 0, fy = 0, fz = 0, tx = 0, ty = 0, tz = 0;
    int64_t count = 0;
    double wet = 0.0;
    for (int64_t i = fleet.offsets[b]; i < fleet.offsets[b + 1]; ++i) {
      const double bx = fleet.points[3 * i], by = fleet.points[3 * i + 1],
                   bz = fleet.points[3 * i + 2];
      const double rx = r[0][0] * bx + r[0][1] * by + r[0][2] * bz;
      const double ry = r[1][0] * bx + r[1][1] * by + r[1][2] * bz;
      const double rz = r[2][0] * bx + r[2][1] * by + r[2][2] * bz;
      const double x = px + rx, y = py + ry, z = pz + rz;
      const double eta = surface(m.waves, m.wave_count, m.level, x, z, m.t);
      double frac = (eta - y) / fleet.heights[i] + 0.5;
      if (frac <= 0.0) continue;
      if (frac > 1.0) frac = 1.0;
      ++count;
      const double v = fleet.volumes[i] * frac;
      wet += v;
      // point velocity v + w x r
      double ux = vx + wy * rz - wz * ry;
      double uy = vy + wz * rx - wx * rz;
      double uz = vz + wx * ry - wy * rx;
      double lift = m.rho * m.g * v;
      if (m.predict) {
        const double ax = x + ux * m.horizon * m.c_predict;
        const double ay = y + uy * m.horizon * m.c_predict;
        const double az = z + uz * m.horizon * m.c_predict;
        if (ay - 0.5 * fleet.heights[i] > surface(m.waves, m.wave_count, m.level, ax, az, m.t))
          lift *= m.m_predict;
      }
      double gx = 0.0, gy = lift, gz = 0.0;
      if (m.damping == 1) {  // drag relative to the water's orbital velocity
        for (index_t w = 0; w < m.wave_count; ++w) {
          const double* a = m.waves + 6 * w;
          const double theta = a[1] * x + a[2] * z - a[3] * m.t + a[4];
          const double k = a[5];
          const double speed = a[0] * a[3] * std::exp(std::min(k * (y - eta), 0.0));
          ux -= speed * std::sin(theta) * a[1] / k;
          uz -= speed * std::sin(theta) * a[2] / k;
          uy += speed * std::cos(theta);
        }
        // never more than stops the point's share of mass within the horizon
        const double sd = std::min(std::sqrt(ux * ux + uy * uy + uz * uz) * drag_k * v,
                                   density * fleet.volumes[i] / m.horizon);
        gx -= sd * ux;
        gy -= sd * uy;
        gz -= sd * uz;
      }
      fx += gx;
      fy += gy;
      fz += gz;
      tx += ry * gz - rz * gy;
      ty += rz * gx - rx * gz;
      tz += rx * gy - ry * gx;
    }
    if (m.damping == 0 && count > 0) {  // team damping
      const int64_t n_all = fleet.offsets[b + 1] - fleet.offsets[b];
      const double sc = std::log(1.0 + static_cast<double>(count)) /
                        std::log(1.0 + static_cast<double>(n_all));
      double k = m.c_lin * sc * fleet.mass[b];
      fx -= k * vx;
      fy -= k * vy;
      fz -= k * vz;
      // world inertia R I R^T applied to w
      const double bw0 = r[0][0] * wx + r[1][0] * wy + r[2][0] * wz;
      const double bw1 = r[0][1] * wx + r[1][1] * wy + r[2][1] * wz;
      const double bw2 = r[0][2] * wx + r[1][2] * wy + r[2][2] * wz;
      const double* in = fleet.inertia + 9 * b;
      const double l0 = in[0] * bw0 + in[1] * bw1 + in[2] * bw2;
      const double l1 = in[3] * bw0 + in[4] * bw1 + in[5] * bw2;
      const double l2 = in[6] * bw0 + in[7] * bw1 + in[8] * bw2;
      k = m.c_ang * sc;
      tx -= k * (r[0][0] * l0 + r[0][1] * l1 + r[0][2] * l2);
      ty -= k * (r[1][0] * l0 + r[1][1] * l1 + r[1][2] * l2);
      tz -= k * (r[2][0] * l0 + r[2][1] * l1 + r[2][2] * l2);
    }
    force[3 * b] = fx, force[3 * b + 1] = fy, force[3 * b + 2] = fz;
    torque[3 * b] = tx, torque[3 * b + 1] = ty, torque[3 * b + 2] = tz;
    submerged_points[b] = count;
    submerged_volume[b] = wet;
  }
}

}  // namespace bakeshop::buoyancy
