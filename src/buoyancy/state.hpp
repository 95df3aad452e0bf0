// The rotation of a unit quaternion (bakeshop/buoyancy/state.py), shared by the buoyancy kernels.
#pragma once

namespace bakeshop::buoyancy {

struct Mat3 {
  double m[3][3];
  const double* operator[](int i) const { return m[i]; }
};

// Rotation matrix of a unit quaternion (w, x, y, z).
inline Mat3 rotation(double q0, double q1, double q2, double q3) {
  Mat3 r;
  r.m[0][0] = 1 - 2 * (q2 * q2 + q3 * q3);
  r.m[0][1] = 2 * (q1 * q2 - q0 * q3);
  r.m[0][2] = 2 * (q1 * q3 + q0 * q2);
  r.m[1][0] = 2 * (q1 * q2 + q0 * q3);
  r.m[1][1] = 1 - 2 * (q1 * q1 + q3 * q3);
  r.m[1][2] = 2 * (q2 * q3 - q0 * q1);
  r.m[2][0] = 2 * (q1 * q3 - q0 * q2);
  r.m[2][1] = 2 * (q2 * q3 + q0 * q1);
  r.m[2][2] = 1 - 2 * (q1 * q1 + q2 * q2);
  return r;
}

}  // namespace bakeshop::buoyancy
