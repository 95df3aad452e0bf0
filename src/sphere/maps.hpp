// The layouts' maps as scalar inline functions: the one implementation of each formula
// (bit-identical to the JIT functions of bakeshop/sphere/_maps.py they replaced).
//
// A layout is named by a kind number (Kind, bakeshop/sphere/_kinds.py) and two integers (h, w)
// (a cube: h = w = S). Texel coordinates are (face, x, y) with texel i's centre at x = i + 0.5;
// flat layouts have face 0. The gather kernels (gather.hpp), the area filter's and the light
// prefilters call these functions, so a direction is computed the same way everywhere.
//
// The arithmetic is the Python's, operation for operation (the build has -ffp-contract=off), so
// that the results are bit-identical to the old JIT kernels they replace.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/kernel.hpp"

namespace bakeshop::sphere {

// The layouts' kind numbers (bakeshop/sphere/_kinds.py).
enum Kind : int {
  LATLONG = 0,
  ANGULAR = 1,
  MIRRORBALL = 2,
  DUAL_PARABOLOID = 3,
  OCTAHEDRAL = 4,
  CUBE = 5,
  ANGULAR_PHYSICAL = 6,
  MIRRORBALL_PHYSICAL = 7,
  OPENEXR_LATLONG = 8,
  OPENEXR_CUBE = 9,
};

// A disk texel is valid when it reaches this far (in r^2) into the disk.
constexpr double DISK_OVERLAP_EPS = 1e-9;
constexpr double PI = 3.141592653589793;

// (N, U, V) per face: the direction at face coordinates (sc, tc) is N + sc U + tc V
// (bakeshop.sphere.cube.FACE_BASES, OpenGL's table).
constexpr double FACE_BASES[6][3][3] = {
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},    {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
    {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},
};
// OpenEXR's cube environment (bakeshop.sphere.cube.OPENEXR_FACE_BASES).
constexpr double OPENEXR_FACE_BASES[6][3][3] = {
    {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},   {{-1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
    {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {-1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
};
using Bases = const double (*)[3][3];

// A direction (x, y, z) and the coordinates (f, x, y) of a texel point (the Python tuples).
struct Vec3 {
  double x, y, z;
};
struct Coords {
  double f, x, y;
};
// cube_face's (face, sc, tc).
struct Face {
  int f;
  double sc, tc;
};

// --- integer helpers (Python semantics) ------------------------------------------------------

// int(v) of a float: truncation toward 0, saturated (NaN: the most negative index, as x86's
// conversion gives) so that no float input is undefined behaviour.
inline index_t trunc_index(double v) {
  constexpr double lim = 9.2e18;
  if (!(v > -lim)) return -static_cast<index_t>(lim);
  if (v > lim) return static_cast<index_t>(lim);
  return static_cast<index_t>(v);
}
// int(math.floor(v)).
inline index_t floor_index(double v) { return trunc_index(std::floor(v)); }
// Python's a % b (b > 0; the sign of b); 0 for b == 0 as the old JIT's error_model="numpy".
inline index_t py_mod(index_t a, index_t b) {
  if (b == 0) return 0;
  index_t r = a % b;
  return (r != 0 && ((r < 0) != (b < 0))) ? r + b : r;
}
// Python's a // b (floor division); 0 for b == 0.
inline index_t py_div(index_t a, index_t b) {
  if (b == 0) return 0;
  index_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}
inline index_t clamp_index(index_t v, index_t lo, index_t hi) { return std::min(std::max(v, lo), hi); }

inline bool is_disk(int kind) {
  return kind == ANGULAR || kind == MIRRORBALL || kind == DUAL_PARABOLOID ||
         kind == ANGULAR_PHYSICAL || kind == MIRRORBALL_PHYSICAL;
}
inline bool is_cubic(int kind) { return kind == CUBE || kind == OPENEXR_CUBE; }
inline index_t cube_scale(int kind, index_t n) { return kind == CUBE ? n : n - 1; }
inline double cube_offset(int kind) { return kind == CUBE ? 0.0 : 0.5; }
inline Bases cube_bases(int kind) { return kind == CUBE ? FACE_BASES : OPENEXR_FACE_BASES; }

// --- arctangent ------------------------------------------------------------------------------

// math.atan2(y, x) within 2e-14 rad, branch-free (_maps.atan2: the same polynomial and order).
inline double atan2(double y, double x) {
  constexpr double A0 = 0.9999999999999367, A1 = -0.3333333332462878, A2 = 0.19999998048207981,
                   A3 = -0.14285549688091495, A4 = 0.11104470935202516,
                   A5 = -0.0895215121939283, A6 = 0.062219062319738394;
  const double TAN_PI_12 = 2.0 - std::sqrt(3.0);
  const double SQRT3 = std::sqrt(3.0);
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool swap = ay > ax;
  double t = std::min(ax, ay) / std::max(std::max(ax, ay), 1e-300);
  const bool reduce = t > TAN_PI_12;
  t = reduce ? (t * SQRT3 - 1.0) / (t + SQRT3) : t;
  const double q = t * t;
  const double p = (((((A6 * q + A5) * q + A4) * q + A3) * q + A2) * q + A1) * q + A0;
  double r = t * p + (reduce ? PI / 6 : 0.0);
  r = swap ? PI / 2 - r : r;
  r = std::signbit(x) ? PI - r : r;
  return std::copysign(r + (x - x) + (y - y), y);
}

// A latlong's continuous coordinates (x, y) of direction (x, y, z).
inline void latlong_xy(index_t h, index_t w, double x, double y, double z, double& u,
                       double& v) {
  const double phi = sphere::atan2(x, -z);
  const double theta = sphere::atan2(std::sqrt(x * x + z * z), y);
  u = (phi / (2 * PI) + 0.5) * static_cast<double>(w);
  v = theta / PI * static_cast<double>(h);
}

// --- directions at coordinates -----------------------------------------------------------------

inline Vec3 disk_direction(int kind, double a, double b, index_t disk) {
  double r2 = a * a + b * b;
  if (kind == ANGULAR || kind == ANGULAR_PHYSICAL) {
    const double r = std::sqrt(r2);
    const double s = r == 0.0 ? PI : std::sin(PI * r) / r;
    const double c = std::cos(PI * r);
    return {a * s, b * s, kind == ANGULAR_PHYSICAL ? c : -c};
  }
  if (kind == MIRRORBALL || kind == MIRRORBALL_PHYSICAL) {
    r2 = std::min(r2, 1.0);
    const double nz = std::sqrt(1.0 - r2);
    const double c = 1.0 - 2 * r2;
    return {2 * nz * a, 2 * nz * b, kind == MIRRORBALL_PHYSICAL ? c : -c};
  }
  const double k = 1.0 / (1.0 + r2);
  const double side = disk == 0 ? -1.0 : 1.0;
  return {-side * 2 * a * k, 2 * b * k, side * (1.0 - r2) * k};
}

inline Vec3 octahedron_point(double a, double c) {
  const double aa = std::fabs(a), ac = std::fabs(c);
  const double y = 1.0 - aa - ac;
  if (y >= 0) return {a, y, c};
  const double sa = a < 0 ? -1.0 : 1.0;
  const double sc = c < 0 ? -1.0 : 1.0;
  return {sa * (1.0 - ac), y, sc * (1.0 - aa)};
}

// direction at (fi, x, y) of a cube of face edge w: N + sc U + tc V, normalised.
inline Vec3 face_direction(int kind, index_t w, int fi, double x, double y) {
  const double n = static_cast<double>(cube_scale(kind, w));
  const double o = cube_offset(kind);
  const double sc = 2 * (x - o) / n - 1;
  const double tc = 2 * (y - o) / n - 1;
  const double(*b)[3] = cube_bases(kind)[fi];
  const double dx = b[0][0] + sc * b[1][0] + tc * b[2][0];
  const double dy = b[0][1] + sc * b[1][1] + tc * b[2][1];
  const double dz = b[0][2] + sc * b[1][2] + tc * b[2][2];
  const double norm = std::sqrt(dx * dx + dy * dy + dz * dz);
  return {dx / norm, dy / norm, dz / norm};
}

// The disk index of column coordinate x: min(max(floor(x / n), 0), w // n - 1).
inline index_t disk_of(index_t h, index_t w, double x) {
  const index_t n = h;
  return std::min(std::max(floor_index(x / static_cast<double>(n)), index_t{0}),
                  py_div(w, n) - 1);
}

// Unit direction at coordinates (f, x, y). Outside a disk: the disk's nearest point.
inline Vec3 direction(int kind, index_t h, index_t w, double f, double x, double y) {
  const double hd = static_cast<double>(h), wd = static_cast<double>(w);
  if (kind == LATLONG) {
    const double phi = 2 * PI * (x / wd - 0.5);
    const double theta = PI * y / hd;
    const double st = std::sin(theta);
    return {st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
  }
  if (kind == OPENEXR_LATLONG) {
    const double lon = -2 * PI * ((x - 0.5) / static_cast<double>(w - 1) - 0.5);
    const double lat = -PI * ((y - 0.5) / static_cast<double>(h - 1) - 0.5);
    const double cl = std::cos(lat);
    return {std::sin(lon) * cl, std::sin(lat), std::cos(lon) * cl};
  }
  if (is_cubic(kind)) {
    return face_direction(kind, w, static_cast<int>(clamp_index(trunc_index(f), 0, 5)), x, y);
  }
  Vec3 d;
  if (kind == OCTAHEDRAL) {
    d = octahedron_point(2 * x / wd - 1, 2 * y / hd - 1);
  } else {
    const index_t n = h;
    const double nd = static_cast<double>(n);
    const index_t disk = disk_of(h, w, x);
    double a = 2 * (x - static_cast<double>(disk * n)) / nd - 1;
    double b = 1 - 2 * y / nd;
    const double r2 = a * a + b * b;
    if (r2 > 1) {
      const double r = std::sqrt(r2);
      a /= r;
      b /= r;
    }
    d = disk_direction(kind, a, b, disk);
  }
  const double norm = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return {d.x / norm, d.y / norm, d.z / norm};
}

// direction at the centres (i + 0.5, j + 0.5) of cube face f's row j, i < count.
inline void face_row(int kind, index_t w, index_t f, index_t j, index_t count, double* xs,
                     double* ys, double* zs) {
  const int fi = static_cast<int>(clamp_index(f, 0, 5));
  for (index_t i = 0; i < count; ++i) {
    const Vec3 d = face_direction(kind, w, fi, static_cast<double>(i) + 0.5,
                                  static_cast<double>(j) + 0.5);
    xs[i] = d.x;
    ys[i] = d.y;
    zs[i] = d.z;
  }
}

// --- coordinates of directions -----------------------------------------------------------------

// (face, sc, tc) of the face table `bases` by the major axis (ties: x, then y).
inline Face major_face(Bases bases, double x, double y, double z) {
  const double ax = std::fabs(x), ay = std::fabs(y), az = std::fabs(z);
  int f;
  double ma;
  if (ax >= ay && ax >= az) {
    f = x >= 0 ? 0 : 1;
    ma = ax;
  } else if (ay >= az) {
    f = y >= 0 ? 2 : 3;
    ma = ay;
  } else {
    f = z >= 0 ? 4 : 5;
    ma = az;
  }
  if (ma == 0) ma = 1.0;
  const double(*b)[3] = bases[f];
  const double sc = (x * b[1][0] + y * b[1][1] + z * b[1][2]) / ma;
  const double tc = (x * b[2][0] + y * b[2][1] + z * b[2][2]) / ma;
  return {f, sc, tc};
}

// OpenGL's major-axis rule: (face, sc, tc), sc and tc in [-1, 1].
inline Face cube_face(double x, double y, double z) { return major_face(FACE_BASES, x, y, z); }

// Continuous coordinates (f, x, y) of direction (x, y, z) (need not be unit).
inline Coords coordinates(int kind, index_t h, index_t w, double x, double y, double z) {
  const double hd = static_cast<double>(h), wd = static_cast<double>(w);
  if (kind == LATLONG) {
    double u, v;
    latlong_xy(h, w, x, y, z, u, v);
    return {0.0, u, v};
  }
  if (kind == OPENEXR_LATLONG) {
    const double lon = sphere::atan2(x, z);
    const double lat = sphere::atan2(y, std::sqrt(x * x + z * z));
    return {0.0, (0.5 - lon / (2 * PI)) * static_cast<double>(w - 1) + 0.5,
            (0.5 - lat / PI) * static_cast<double>(h - 1) + 0.5};
  }
  if (is_cubic(kind)) {
    const Face fc = major_face(cube_bases(kind), x, y, z);
    const double n = static_cast<double>(cube_scale(kind, w));
    const double o = cube_offset(kind);
    return {static_cast<double>(fc.f), (fc.sc + 1) / 2 * n + o, (fc.tc + 1) / 2 * n + o};
  }
  if (kind == OCTAHEDRAL) {
    double norm1 = std::fabs(x) + std::fabs(y) + std::fabs(z);
    if (norm1 == 0) norm1 = 1.0;
    double px = x / norm1, py = y / norm1, pz = z / norm1;
    if (py < 0) {
      const double sx = px < 0 ? -1.0 : 1.0;
      const double sz = pz < 0 ? -1.0 : 1.0;
      const double nx = sx * (1 - std::fabs(pz)), nz = sz * (1 - std::fabs(px));
      px = nx;
      pz = nz;
    }
    return {0.0, (px + 1) / 2 * wd, (pz + 1) / 2 * hd};
  }
  const double n = hd;
  index_t disk = 0;
  double a, b;
  if (kind != DUAL_PARABOLOID) {
    const double rho = std::sqrt(x * x + y * y);
    // the component along the centre's direction: -z (HDRShop), +z (physical)
    const double zc = (kind == ANGULAR_PHYSICAL || kind == MIRRORBALL_PHYSICAL) ? z : -z;
    double r;
    if (kind == ANGULAR || kind == ANGULAR_PHYSICAL) {
      r = std::atan2(rho, zc) / PI;
    } else {
      const double norm = std::sqrt(rho * rho + zc * zc);
      const double zn = norm > 0 ? zc / norm : 1.0;
      r = std::sqrt(std::min(std::max((1 - zn) / 2, 0.0), 1.0));
    }
    if (rho > 0) {
      a = r * x / rho;
      b = r * y / rho;
    } else {
      a = r;
      b = 0.0;
    }
  } else {
    double norm = std::sqrt(x * x + y * y + z * z);
    if (norm == 0) norm = 1.0;
    double xn = x / norm;
    const double yn = y / norm, zn = z / norm;
    if (zn > 0) {
      disk = 1;
      xn = -xn;
    }
    const double fz = std::fabs(zn);
    a = xn / (1 + fz);
    b = yn / (1 + fz);
  }
  return {0.0, (a + 1) / 2 * n + static_cast<double>(disk * h), (1 - b) / 2 * n};
}

// --- texels ------------------------------------------------------------------------------------

// Whether texel (f, i, j) holds data: disk texels must overlap the open disk.
inline bool valid(int kind, index_t h, index_t w, double f, index_t i, index_t j) {
  if (is_disk(kind)) {
    const index_t n = h;
    const double nd = static_cast<double>(n);
    const index_t li = py_mod(i, n);
    const double ta =
        std::max(std::fabs(2 * (static_cast<double>(li) + 0.5) / nd - 1) - 1 / nd, 0.0);
    const double tb =
        std::max(std::fabs(2 * (static_cast<double>(j) + 0.5) / nd - 1) - 1 / nd, 0.0);
    return ta * ta + tb * tb < 1 - DISK_OVERLAP_EPS;
  }
  return true;
}

// Flat index of integer texel (f, i, j), which may lie one texel outside the image (or the
// disk), as the neighbour of a sample at column coordinate x; -1 for a cube corner.
inline index_t resolve(int kind, index_t h, index_t w, double f, index_t i, index_t j,
                       double x) {
  if (kind == LATLONG) {
    if (0 <= i && i < w && 0 <= j && j < h) return j * w + i;
    if (j < 0 || j >= h) {
      // across a pole: the same row, half a turn away
      i += py_div(w, 2);
      j = clamp_index(j, 0, h - 1);
    }
    return j * w + py_mod(i, w);
  }
  if (kind == OPENEXR_LATLONG) {
    if (0 <= i && i < w && 0 <= j && j < h) return j * w + i;
    const index_t turn = w - 1;  // the last column repeats the first's meridian
    if (j < 0 || j >= h) {
      j = j < 0 ? -j : 2 * (h - 1) - j;
      j = clamp_index(j, 0, h - 1);
      i += py_div(turn, 2);
    }
    return j * w + py_mod(i, turn);
  }
  if (is_cubic(kind)) {
    const index_t s = w;
    const bool out_i = i < 0 || i >= s;
    const bool out_j = j < 0 || j >= s;
    if (!out_i && !out_j) return (trunc_index(f) * s + j) * s + i;
    if (out_i && out_j) return -1;
    const index_t fi = trunc_index(f);
    Bases bases = cube_bases(kind);
    const double n = static_cast<double>(cube_scale(kind, s));
    const double o = cube_offset(kind);
    double sc = 2 * (static_cast<double>(i) + 0.5 - o) / n - 1;
    double tc = 2 * (static_cast<double>(j) + 0.5 - o) / n - 1;
    if (kind == CUBE) {
      // OpenGL's seamless rule: the texel across the edge at the same place along it
      constexpr double eps = 1e-9;
      if (out_i) {
        sc = std::copysign(1 + eps, sc);
      } else {
        tc = std::copysign(1 + eps, tc);
      }
    }
    const double(*b)[3] = bases[fi];
    const double dx = b[0][0] + sc * b[1][0] + tc * b[2][0];
    const double dy = b[0][1] + sc * b[1][1] + tc * b[2][1];
    const double dz = b[0][2] + sc * b[1][2] + tc * b[2][2];
    const Face g = major_face(bases, dx, dy, dz);
    const index_t gi = clamp_index(floor_index((g.sc + 1) / 2 * n + o), 0, s - 1);
    const index_t gj = clamp_index(floor_index((g.tc + 1) / 2 * n + o), 0, s - 1);
    return (g.f * s + gj) * s + gi;
  }
  if (kind == OCTAHEDRAL) {
    const index_t n = w;
    const bool out_i = i < 0 || i >= n;
    const bool out_j = j < 0 || j >= n;
    i = clamp_index(i, 0, n - 1);
    j = clamp_index(j, 0, n - 1);
    // beyond an edge the map folds back mirrored; beyond a corner is the opposite corner
    if (out_j) i = n - 1 - i;
    if (out_i) j = n - 1 - j;
    return j * n + i;
  }
  const index_t n = h;
  const double nd = static_cast<double>(n);
  const index_t disk = disk_of(h, w, x);
  const index_t li = i - disk * n;
  double a = 2 * (static_cast<double>(li) + 0.5) / nd - 1;
  double b = 1 - 2 * (static_cast<double>(j) + 0.5) / nd;
  if (0 <= li && li < n && 0 <= j && j < n && valid(kind, h, w, 0, li, j)) {
    return j * w + li + disk * n;
  }
  const double r = std::hypot(a, b);
  // beyond the rim: the disk texel that looks where this one would (the formula continued);
  // the mirror ball's whole rim looks one way, so there the texel radially inside stands in
  if (kind == MIRRORBALL || kind == MIRRORBALL_PHYSICAL) {
    const double pull = std::max(0.0, 1 - 1.5 / nd) / r;
    a *= pull;
    b *= pull;
  }
  const Vec3 d = disk_direction(kind, a, b, disk);
  const Coords c = coordinates(kind, h, w, d.x, d.y, d.z);
  const index_t ci = clamp_index(floor_index(c.x), 0, w - 1);
  const index_t cj = clamp_index(floor_index(c.y), 0, h - 1);
  return cj * w + ci;
}

// Flat index of the texel containing the point at coordinates (f, x, y); a cube face owns its
// far edges.
inline index_t nearest_texel(int kind, index_t h, index_t w, double f, double x, double y) {
  index_t i = floor_index(x), j = floor_index(y);
  if (is_cubic(kind)) {
    i = std::min(i, w - 1);
    j = std::min(j, h - 1);
  }
  return resolve(kind, h, w, f, i, j, x);
}

// R^T d (rot: 3x3 row-major): what the output shows at d is what the input showed at R^T d.
inline Vec3 rotate(const double* rot, double x, double y, double z) {
  return {rot[0] * x + rot[3] * y + rot[6] * z, rot[1] * x + rot[4] * y + rot[7] * z,
          rot[2] * x + rot[5] * y + rot[8] * z};
}

// Sin and cos of a latlong's longitude at every column centre (rows 0, 1) and of its
// colatitude at every row centre (rows 2, 3) into trig (4, max(h, w)), row-major.
inline void latlong_trig(index_t h, index_t w, double* trig) {
  const index_t m = std::max(h, w);
  for (index_t i = 0; i < w; ++i) {
    const double phi = 2 * PI * ((static_cast<double>(i) + 0.5) / static_cast<double>(w) - 0.5);
    trig[i] = std::sin(phi);
    trig[m + i] = std::cos(phi);
  }
  for (index_t j = 0; j < h; ++j) {
    const double theta = PI * (static_cast<double>(j) + 0.5) / static_cast<double>(h);
    trig[2 * m + j] = std::sin(theta);
    trig[3 * m + j] = std::cos(theta);
  }
}

// --- drivers -----------------------------------------------------------------------------------

// out[p] = direction at coords[p] = (f, x, y), p < count (both (count, 3)).
inline void directions_at(int kind, index_t h, index_t w, const double* coords, index_t count,
                          double* out) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    const Vec3 d = direction(kind, h, w, coords[3 * p], coords[3 * p + 1], coords[3 * p + 2]);
    out[3 * p] = d.x;
    out[3 * p + 1] = d.y;
    out[3 * p + 2] = d.z;
  }
}

// out[p] = coordinates (f, x, y) of dirs[p], p < count (both (count, 3)).
inline void coordinates_of(int kind, index_t h, index_t w, const double* dirs, index_t count,
                           double* out) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    const Coords c = coordinates(kind, h, w, dirs[3 * p], dirs[3 * p + 1], dirs[3 * p + 2]);
    out[3 * p] = c.f;
    out[3 * p + 1] = c.x;
    out[3 * p + 2] = c.y;
  }
}

// out (h, w, 3): the latlong texel-centre directions (sin t_j sin p_i, cos t_j, -sin t_j cos p_i).
inline void latlong_directions(index_t h, index_t w, double* out) {
  const index_t m = std::max(h, w);
  std::vector<double> table(static_cast<size_t>(4 * m));
  const double* trig = table.data();
  latlong_trig(h, w, table.data());
#pragma omp parallel for schedule(static)
  for (index_t j = 0; j < h; ++j) {
    const double st = trig[2 * m + j], ct = trig[3 * m + j];
    double* row = out + j * w * 3;
    for (index_t i = 0; i < w; ++i) {
      row[3 * i] = st * trig[i];
      row[3 * i + 1] = ct;
      row[3 * i + 2] = -st * trig[m + i];
    }
  }
}

}  // namespace bakeshop::sphere
