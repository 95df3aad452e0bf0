// bakeshop.buoyancy._native: the kernels of bakeshop.buoyancy (voxelisation, point forces, the
// built-in integrator, the lowest hull points, the quaternion rotation).
#include "buoyancy/builtin.hpp"
#include "buoyancy/forces.hpp"
#include "buoyancy/metrics.hpp"
#include "buoyancy/sampling.hpp"
#include "buoyancy/state.hpp"
#include "common/bind.hpp"

using namespace bakeshop;

namespace {

// offsets (n + 1,) from 0, non-decreasing, ending at or below `total`
bool csr_ok(const int64_t* offsets, size_t n, int64_t total) {
  if (offsets[0] < 0) return false;
  for (size_t i = 0; i < n; ++i)
    if (offsets[i + 1] < offsets[i]) return false;
  return offsets[n] <= total;
}

}  // namespace

NB_MODULE(_native, m) {
  m.def(
      "rotation",
      [](double q0, double q1, double q2, double q3, Out<double, 2> out) {
        require(shape_is(out, {3, 3}), "rotation: out must be (3, 3)");
        const buoyancy::Mat3 r = buoyancy::rotation(q0, q1, q2, q3);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) out.data()[3 * i + j] = r[i][j];
      },
      "q0"_a, "q1"_a, "q2"_a, "q3"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "crossings",
      [](In<double, 3> triangles, double x0, double z0, double step, int64_t nx, int64_t nz,
         Out<int64_t, 1> counts, Out<double, 1> hits_y, Out<int64_t, 1> hits_w,
         In<int64_t, 1> offsets, bool fill) {
        require(triangles.shape(1) == 3 && triangles.shape(2) == 3,
                "crossings: triangles must be (T, 3, 3)");
        require(nx >= 0 && nz >= 0 && counts.shape(0) == static_cast<size_t>(nx * nz),
                "crossings: counts must hold nx * nz rays");
        require(hits_w.shape(0) == hits_y.shape(0), "crossings: hits_y and hits_w differ");
        if (fill) {
          require(offsets.shape(0) == static_cast<size_t>(nx * nz + 1) &&
                      csr_ok(offsets.data(), nx * nz, hits_y.shape(0)),
                  "crossings: offsets must be the rays' CSR offsets into the hits");
          for (int64_t r = 0; r < nx * nz; ++r)
            require(counts.data()[r] == 0, "crossings: the filling pass starts from zero counts");
        }
        buoyancy::crossings(triangles.data(), triangles.shape(0), x0, z0, step, nx, nz,
                            counts.data(), hits_y.data(), hits_w.data(),
                            fill ? offsets.data() : nullptr, hits_y.shape(0), fill);
      },
      "triangles"_a, "x0"_a, "z0"_a, "step"_a, "nx"_a, "nz"_a, "counts"_a.noconvert(),
      "hits_y"_a.noconvert(), "hits_w"_a.noconvert(), "offsets"_a, "fill"_a, release_gil());

  m.def(
      "accumulate",
      [](In<double, 1> hits_y, In<int64_t, 1> hits_w, In<int64_t, 1> offsets, double x0,
         double y0, double z0, double cell, In<int64_t, 1> shape, int64_t sub,
         Out<double, 1> volume, Out<double, 2> moment, Out<double, 1> area) {
        require(shape.shape(0) == 3 && sub >= 1, "accumulate: shape (3,) and sub >= 1");
        const int64_t nx = shape.data()[0], ny = shape.data()[1], nz = shape.data()[2];
        require(nx >= 0 && ny >= 0 && nz >= 0, "accumulate: the shape must not be negative");
        const size_t cells = static_cast<size_t>(nx * ny * nz);
        const size_t rays = static_cast<size_t>(nx * sub * nz * sub);
        require(volume.shape(0) == cells && area.shape(0) == cells &&
                    shape_is(moment, {cells, 3}),
                "accumulate: volume, area (n,) and moment (n, 3) of the n cells");
        require(hits_w.shape(0) == hits_y.shape(0) && offsets.shape(0) == rays + 1 &&
                    csr_ok(offsets.data(), rays, hits_y.shape(0)),
                "accumulate: offsets must be the rays' CSR offsets into the hits");
        buoyancy::accumulate(hits_y.data(), hits_w.data(), offsets.data(), x0, y0, z0, cell, nx,
                             ny, nz, sub, volume.data(), moment.data(), area.data());
      },
      "hits_y"_a, "hits_w"_a, "offsets"_a, "x0"_a, "y0"_a, "z0"_a, "cell"_a, "shape"_a, "sub"_a,
      "volume"_a.noconvert(), "moment"_a.noconvert(), "area"_a.noconvert(), release_gil());

  m.def(
      "point_forces",
      [](In<int64_t, 1> offsets, In<double, 2> points, In<double, 1> volumes,
         In<double, 1> heights, In<double, 1> body_volume, In<double, 1> mass,
         In<double, 3> inertia, In<double, 2> position, In<double, 2> quaternion,
         In<double, 2> velocity, In<double, 2> omega, In<double, 2> waves, double level,
         double t, double rho, double g, int damping, double c_lin, double c_ang, double c_drag,
         bool predict, double c_predict, double m_predict, double horizon, Out<double, 2> force,
         Out<double, 2> torque, Out<int64_t, 1> submerged_points,
         Out<double, 1> submerged_volume) {
        require(offsets.shape(0) >= 1, "point_forces: offsets must be (B + 1,)");
        const size_t b = offsets.shape(0) - 1, p = points.shape(0);
        require(points.shape(1) == 3 && volumes.shape(0) == p && heights.shape(0) == p,
                "point_forces: points (P, 3), volumes and heights (P,)");
        require(csr_ok(offsets.data(), b, static_cast<int64_t>(p)),
                "point_forces: offsets must split the points among the bodies");
        require(body_volume.shape(0) == b && mass.shape(0) == b && shape_is(inertia, {b, 3, 3}),
                "point_forces: volume, mass (B,) and inertia (B, 3, 3)");
        require(shape_is(position, {b, 3}) && shape_is(quaternion, {b, 4}) &&
                    shape_is(velocity, {b, 3}) && shape_is(omega, {b, 3}),
                "point_forces: position, velocity, omega (B, 3) and quaternion (B, 4)");
        require(waves.shape(1) == 6, "point_forces: waves must be (W, 6)");
        require(shape_is(force, {b, 3}) && shape_is(torque, {b, 3}) &&
                    submerged_points.shape(0) == b && submerged_volume.shape(0) == b,
                "point_forces: force, torque (B, 3), submerged_points and _volume (B,)");
        const buoyancy::Fleet fleet{offsets.data(), points.data(), volumes.data(),
                                    heights.data(), body_volume.data(), mass.data(),
                                    inertia.data(), static_cast<index_t>(b)};
        const buoyancy::Motion motion{position.data(), quaternion.data(), velocity.data(),
                                      omega.data()};
        const buoyancy::Model model{waves.data(), static_cast<index_t>(waves.shape(0)),
                                    level, t, rho, g, damping, c_lin, c_ang, c_drag, predict,
                                    c_predict, m_predict, horizon};
        buoyancy::point_forces(fleet, motion, model, force.data(), torque.data(),
                               submerged_points.data(), submerged_volume.data());
      },
      "offsets"_a, "points"_a, "volumes"_a, "heights"_a, "body_volume"_a, "mass"_a,
      "inertia"_a, "position"_a, "quaternion"_a, "velocity"_a, "omega"_a, "waves"_a, "level"_a,
      "t"_a, "rho"_a, "g"_a, "damping"_a, "c_lin"_a, "c_ang"_a, "c_drag"_a, "predict"_a,
      "c_predict"_a, "m_predict"_a, "horizon"_a, "force"_a.noconvert(), "torque"_a.noconvert(),
      "submerged_points"_a.noconvert(), "submerged_volume"_a.noconvert(), release_gil());

  m.def(
      "lowest_points",
      [](In<double, 2> hull, In<double, 2> quaternion, In<double, 2> position,
         Out<double, 2> out) {
        const size_t s = quaternion.shape(0);
        require(hull.shape(1) == 3 && hull.shape(0) > 0, "lowest_points: hull must be (V, 3)");
        require(quaternion.shape(1) == 4 && shape_is(position, {s, 3}) && shape_is(out, {s, 3}),
                "lowest_points: quaternion (S, 4), position and out (S, 3)");
        buoyancy::lowest_points(hull.data(), hull.shape(0), quaternion.data(), position.data(),
                                s, out.data());
      },
      "hull"_a, "quaternion"_a, "position"_a, "out"_a.noconvert(), release_gil());

  m.def(
      "builtin_step",
      [](Out<double, 2> position, Out<double, 2> quaternion, Out<double, 2> velocity,
         Out<double, 2> omega, In<double, 2> force, In<double, 2> torque, In<double, 1> mass,
         In<double, 3> inertia, In<double, 3> inverse, double dt, double g) {
        const size_t b = position.shape(0);
        require(position.shape(1) == 3 && shape_is(quaternion, {b, 4}) &&
                    shape_is(velocity, {b, 3}) && shape_is(omega, {b, 3}) &&
                    shape_is(force, {b, 3}) && shape_is(torque, {b, 3}) && mass.shape(0) == b &&
                    shape_is(inertia, {b, 3, 3}) && shape_is(inverse, {b, 3, 3}),
                "builtin_step: (B, 3) position, velocity, omega, force, torque; (B, 4) "
                "quaternion; (B,) mass; (B, 3, 3) inertia and inverse");
        buoyancy::builtin_step(position.data(), quaternion.data(), velocity.data(),
                               omega.data(), force.data(), torque.data(), mass.data(),
                               inertia.data(), inverse.data(), b, dt, g);
      },
      "position"_a.noconvert(), "quaternion"_a.noconvert(), "velocity"_a.noconvert(),
      "omega"_a.noconvert(), "force"_a, "torque"_a, "mass"_a, "inertia"_a, "inverse"_a, "dt"_a,
      "g"_a, release_gil());
}
