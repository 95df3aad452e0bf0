// The area filter's geometry (bakeshop/sphere/area.py drives it; matrix.hpp makes the deposits
// a matrix): source texels' footprints in the destination, their deposits (box overlaps, of
// the whole texel or of its parts) and the blend towards bilinear. The arithmetic is the old JIT
// kernels', operation for operation (float32 where they stored float32).
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/gather.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::sphere {

// The area filter averages (splats) where a destination texel is at least this many source
// texels across, interpolates bilinearly where it is at most one, and blends between.
constexpr double AREA_SPLAT_RATIO = 1.5;
// It averages only where the deposits cover at least this fraction of a destination texel's
// solid angle (blending towards bilinear below).
constexpr double AREA_COVERAGE = 0.75;
// Most parts a source texel is cut into along each of its axes.
constexpr index_t AREA_MAX_PARTS = 2048;
// A texel cut into at most this many parts along each axis, whose image lies in one image (or
// face) within a window of at most AREA_WINDOW x AREA_WINDOW destination texels, is deposited
// through its affine image (window_taps).
constexpr index_t AREA_AFFINE_PARTS = 4;
constexpr index_t AREA_WINDOW = 8;

namespace area_detail {

inline double sq(double v) { return v * v; }

// R d (rot 3x3 row-major): the Python's rotate(rot.T, x, y, z).
inline Vec3 rotate_t(const double* rot, double x, double y, double z) {
  return {rot[0] * x + rot[1] * y + rot[2] * z, rot[3] * x + rot[4] * y + rot[5] * z,
          rot[6] * x + rot[7] * y + rot[8] * z};
}

struct XY {
  double x, y;
};

// Sin and cos of a latlong's longitude at every half texel (rows 0, 1) and of its colatitude
// (rows 2, 3): (4, 2 max(h, w) + 1) row-major.
struct HalfTrig {
  std::vector<double> t;
  index_t m;
  HalfTrig(index_t h, index_t w) : t(4 * (2 * std::max(h, w) + 1)), m(2 * std::max(h, w) + 1) {
    for (index_t k = 0; k < 2 * w + 1; ++k) {
      const double phi = 2 * PI * (static_cast<double>(k) / static_cast<double>(2 * w) - 0.5);
      t[k] = std::sin(phi);
      t[m + k] = std::cos(phi);
    }
    for (index_t k = 0; k < 2 * h + 1; ++k) {
      const double theta = PI * static_cast<double>(k) / static_cast<double>(2 * h);
      t[2 * m + k] = std::sin(theta);
      t[3 * m + k] = std::cos(theta);
    }
  }
  double operator()(int row, index_t k) const { return t[row * m + k]; }
};

// Whether source texel (i, j)'s image may be far from a parallelogram.
inline bool bent(int skind, index_t h, index_t w, index_t i, index_t j, int dkind) {
  if (skind == OCTAHEDRAL || dkind == OCTAHEDRAL) return true;
  if (skind == LATLONG || skind == OPENEXR_LATLONG) return j < 2 || j > h - 3;
  if (skind == ANGULAR || skind == ANGULAR_PHYSICAL || skind == MIRRORBALL ||
      skind == MIRRORBALL_PHYSICAL) {
    const index_t n = h;
    const double nd = static_cast<double>(n);
    const double a = 2 * (static_cast<double>(py_mod(i, n)) + 0.5) / nd - 1;
    const double b = 1 - 2 * (static_cast<double>(j) + 0.5) / nd;
    return a * a + b * b > sq(1 - 4 / nd);
  }
  return false;
}

// The overlap of [c - half, c + half] with texel q ([q, q + 1]) as a fraction of its length.
inline double overlap(double c, double half, index_t q) {
  const double qd = static_cast<double>(q), q1 = static_cast<double>(q + 1);
  if (half < 1e-9) return (qd <= c && c < q1) ? 1.0 : 0.0;
  return std::max(0.0, std::min(q1, c + half) - std::max(qd, c - half)) / (2 * half);
}

inline void box_weights(double c, double half, index_t lo, double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = overlap(c, half, lo + k);
}

// Coordinates of (x, y, z) continued across the seams around the centre (cf, cx, cy).
inline XY local(int kind, index_t h, index_t w, double x, double y, double z, double cf,
                double cx, double cy) {
  if (is_cubic(kind)) {
    const int fi = static_cast<int>(clamp_index(trunc_index(cf), 0, 5));
    const Bases bases = cube_bases(kind);
    const double n = x * bases[fi][0][0] + y * bases[fi][0][1] + z * bases[fi][0][2];
    const double sc = (x * bases[fi][1][0] + y * bases[fi][1][1] + z * bases[fi][1][2]) / n;
    const double tc = (x * bases[fi][2][0] + y * bases[fi][2][1] + z * bases[fi][2][2]) / n;
    const double wd = static_cast<double>(w), hd = static_cast<double>(h);
    if (kind == CUBE) return {(sc + 1) / 2 * wd, (tc + 1) / 2 * hd};
    return {(sc + 1) / 2 * static_cast<double>(w - 1) + 0.5,
            (tc + 1) / 2 * static_cast<double>(h - 1) + 0.5};
  }
  if (kind == DUAL_PARABOLOID) {
    const index_t n = h;
    const double nd = static_cast<double>(n);
    const index_t disk = std::min(std::max(floor_index(cx / nd), index_t{0}), index_t{1});
    const double norm = std::sqrt(x * x + y * y + z * z);
    const double right = disk == 0 ? x / norm : -x / norm;
    const double fwd = disk == 0 ? -z / norm : z / norm;
    const double a = right / (1 + fwd), b = y / norm / (1 + fwd);
    return {(a + 1) / 2 * nd + static_cast<double>(disk * n), (1 - b) / 2 * nd};
  }
  const Coords co = coordinates(kind, h, w, x, y, z);
  const double u = co.x, v = co.y;
  if (kind == LATLONG) {
    const double wd = static_cast<double>(w);
    return {u - wd * std::floor((u - cx) / wd + 0.5), v};
  }
  if (kind == OPENEXR_LATLONG) {
    const double turn = static_cast<double>(w - 1);
    return {u - turn * std::floor((u - cx) / turn + 0.5), v};
  }
  double best_u = u, best_v = v;
  if (kind == OCTAHEDRAL) {
    const index_t n = w;
    for (index_t du = -1; du <= 1; ++du) {
      for (index_t dv = -1; dv <= 1; ++dv) {
        double cu = du == 0 ? u : static_cast<double>((1 + du) * n) - u;
        double cv = dv == 0 ? v : static_cast<double>((1 + dv) * n) - v;
        if (du != 0 && dv == 0) cv = static_cast<double>(n) - v;
        if (dv != 0 && du == 0) cu = static_cast<double>(n) - u;
        if (sq(cu - cx) + sq(cv - cy) < sq(best_u - cx) + sq(best_v - cy)) {
          best_u = cu;
          best_v = cv;
        }
      }
    }
  } else if (kind == ANGULAR || kind == ANGULAR_PHYSICAL) {
    const double nd = static_cast<double>(h);
    const double a = 2 * u / nd - 1, b = 1 - 2 * v / nd;
    const double r = std::hypot(a, b);
    if (r > 0) {
      const double k = (r - 2) / r;
      const double cu = (a * k + 1) / 2 * nd, cv = (1 - b * k) / 2 * nd;
      if (sq(cu - cx) + sq(cv - cy) < sq(u - cx) + sq(v - cy)) {
        best_u = cu;
        best_v = cv;
      }
    }
  }
  return {best_u, best_v};
}

// direction at the half-texel position (u2 / 2, v2 / 2).
inline Vec3 source_direction(int kind, index_t h, index_t w, double f, index_t u2, index_t v2,
                             const HalfTrig& trig) {
  if (kind == LATLONG)
    return {trig(2, v2) * trig(0, u2), trig(3, v2), -trig(2, v2) * trig(1, u2)};
  return direction(kind, h, w, f, static_cast<double>(u2) / 2, static_cast<double>(v2) / 2);
}

inline XY image(int skind, index_t sh, index_t sw, double f, index_t u2, index_t v2,
                const HalfTrig& trig, const double* rot, int dkind, index_t dh, index_t dw,
                double cf, double cx, double cy) {
  const Vec3 s = source_direction(skind, sh, sw, f, u2, v2, trig);
  const Vec3 r = rotate_t(rot, s.x, s.y, s.z);
  return local(dkind, dh, dw, r.x, r.y, r.z, cf, cx, cy);
}

// The band t0 <= theta <= t1's centroid colatitude and its cos t0 - cos t1, from the sines
// and cosines of t0 and t1.
inline XY band_centroid_of(double t0, double t1, double s0, double c0, double s1, double c1) {
  const double band = c0 - c1;
  if (!(band > 1e-300)) return {0.5 * (t0 + t1), 0.0};
  const double moment = s1 - s0 - (t1 * c1 - t0 * c0);
  return {moment / band, band};
}

inline XY band_centroid(double t0, double t1) {
  return band_centroid_of(t0, t1, std::sin(t0), std::cos(t0), std::sin(t1), std::cos(t1));
}

struct Affine {
  double df, cx, cy, ex0, ex1, ey0, ey1;
};

// Source texel (f, i, j)'s locally affine image in destination coordinates.
inline Affine affine_image(int skind, index_t sh, index_t sw, double f, index_t i, index_t j,
                           const HalfTrig& trig, const double* rot, int dkind, index_t dh,
                           index_t dw) {
  const Vec3 s = source_direction(skind, sh, sw, f, 2 * i + 1, 2 * j + 1, trig);
  const Vec3 r = rotate_t(rot, s.x, s.y, s.z);
  const Coords c = coordinates(dkind, dh, dw, r.x, r.y, r.z);
  const XY b = image(skind, sh, sw, f, 2 * i + 2, 2 * j + 1, trig, rot, dkind, dh, dw, c.f, c.x,
                     c.y);
  const XY d = image(skind, sh, sw, f, 2 * i + 1, 2 * j + 2, trig, rot, dkind, dh, dw, c.f, c.x,
                     c.y);
  return {c.f, c.x, c.y, 2 * (b.x - c.x), 2 * (b.y - c.y), 2 * (d.x - c.x), 2 * (d.y - c.y)};
}

// Into how many parts a source texel `extent` destination texels long is cut.
inline index_t parts(double extent) {
  if (!(extent * AREA_SPLAT_RATIO > 1)) return 1;
  const double c = std::ceil(extent * AREA_SPLAT_RATIO);
  return c < static_cast<double>(AREA_MAX_PARTS) ? static_cast<index_t>(c) : AREA_MAX_PARTS;
}

struct Footprint {
  double df, cx, cy, hx, hy, width;
  index_t nx, ny;
};

inline Footprint footprint(int skind, index_t sh, index_t sw, double f, index_t i, index_t j,
                           const HalfTrig& trig, const double* rot, int dkind, index_t dh,
                           index_t dw) {
  const Affine a = affine_image(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw);
  double cx = a.cx, cy = a.cy;
  if (skind == LATLONG) {
    // centred on the texel's centroid
    const double theta = band_centroid(PI * static_cast<double>(j) / static_cast<double>(sh),
                                       PI * static_cast<double>(j + 1) / static_cast<double>(sh))
                             .x;
    const double st = std::sin(theta);
    const Vec3 r = rotate_t(rot, st * trig(0, 2 * i + 1), std::cos(theta), -st * trig(1, 2 * i + 1));
    const XY l = local(dkind, dh, dw, r.x, r.y, r.z, a.df, cx, cy);
    cx = l.x;
    cy = l.y;
  }
  double hx = 0.5 * (std::fabs(a.ex0) + std::fabs(a.ey0));
  double hy = 0.5 * (std::fabs(a.ex1) + std::fabs(a.ey1));
  hx = hx >= 0 ? hx : 0.0;  // NaN at a degenerate point: a point
  hy = hy >= 0 ? hy : 0.0;
  const double length =
      std::sqrt(std::max(a.ex0 * a.ex0 + a.ex1 * a.ex1, a.ey0 * a.ey0 + a.ey1 * a.ey1));
  const double width = length > 0 ? std::fabs(a.ex0 * a.ey1 - a.ex1 * a.ey0) / length : 0.0;
  const index_t nx = parts(std::max(std::fabs(a.ex0), std::fabs(a.ex1)));
  const index_t ny = parts(std::max(std::fabs(a.ey0), std::fabs(a.ey1)));
  return {a.df, cx, cy, std::min(0.5, hx), std::min(0.5, hy), width, nx, ny};
}

struct Part {
  double df, cx, cy, hx, hy, om;
};

// part_footprint from the source directions at the part's centre (x, y, z) and at the
// midpoints of its right (a) and lower (b) edges. (The solid angle is taken with the centre
// already rotated and the edges not yet, as the old JIT kernel did.)
inline Part part_of(double x, double y, double z, double ax, double ay, double az, double bx,
                    double by, double bz, const double* rot, int dkind, index_t dh, index_t dw) {
  const Vec3 r = rotate_t(rot, x, y, z);
  x = r.x;
  y = r.y;
  z = r.z;
  const Coords c = coordinates(dkind, dh, dw, x, y, z);
  const double om = 4 * std::sqrt(sq((ay - y) * (bz - z) - (az - z) * (by - y)) +
                                  sq((az - z) * (bx - x) - (ax - x) * (bz - z)) +
                                  sq((ax - x) * (by - y) - (ay - y) * (bx - x)));
  const Vec3 ra = rotate_t(rot, ax, ay, az);
  const Vec3 rb = rotate_t(rot, bx, by, bz);
  const XY b = local(dkind, dh, dw, ra.x, ra.y, ra.z, c.f, c.x, c.y);
  const XY d = local(dkind, dh, dw, rb.x, rb.y, rb.z, c.f, c.x, c.y);
  double hx = std::fabs(b.x - c.x) + std::fabs(d.x - c.x);
  double hy = std::fabs(b.y - c.y) + std::fabs(d.y - c.y);
  hx = hx >= 0 ? hx : 0.0;
  hy = hy >= 0 ? hy : 0.0;
  return {c.f, c.x, c.y, std::min(0.5, hx), std::min(0.5, hy), om >= 0 ? om : 0.0};
}

inline Part part_footprint(int skind, index_t sh, index_t sw, double f, double u, double v,
                           double du, double dv, const double* rot, int dkind, index_t dh,
                           index_t dw) {
  const Vec3 p = direction(skind, sh, sw, f, u, v);
  const Vec3 a = direction(skind, sh, sw, f, u + du / 2, v);
  const Vec3 b = direction(skind, sh, sw, f, u, v + dv / 2);
  return part_of(p.x, p.y, p.z, a.x, a.y, a.z, b.x, b.y, b.z, rot, dkind, dh, dw);
}

inline Vec3 latlong_unit(double sp, double cp, double st, double ct) {
  const double x = st * sp, y = ct, z = -st * cp;
  const double norm = std::sqrt(x * x + y * y + z * z);
  return {x / norm, y / norm, z / norm};
}

// acc[q] += w values for the 3 x 3 destination texels from flat index b (rows `row` apart),
// w = om x (x weight) x (y weight) from wq (4 float32).
inline void deposit(double* acc, index_t b, index_t row, const float* wq, float om,
                    const double values[2]) {
  const float wx0 = wq[0], wx1 = wq[1], wy0 = wq[2], wy1 = wq[3];
  const double wx2 = std::max(0.0, 1.0 - static_cast<double>(wx0) - wx1);
  for (index_t yb = 0; yb < 3; ++yb) {
    double wy = yb == 0 ? static_cast<double>(wy0)
                        : (yb == 1 ? static_cast<double>(wy1)
                                   : std::max(0.0, 1.0 - static_cast<double>(wy0) - wy1));
    if (wy == 0) continue;
    wy *= om;
    const index_t q0 = b + yb * row;
    for (int c = 0; c < 2; ++c) {
      const double v = wy * values[c];
      acc[2 * q0 + c] += wx0 * v;
      acc[2 * (q0 + 1) + c] += wx1 * v;
      acc[2 * (q0 + 2) + c] += wx2 * v;
    }
  }
}

// Merge the repeated taps of entries o..e-1 and scale their weights to sum om; returns how many
// remain (at o onwards), in increasing tap order.
inline index_t merge_taps(int32_t* taps, float* weights, index_t o, index_t e, double om) {
  index_t n = 0;
  if (e > o) {
    int32_t lo = taps[o], hi = taps[o];
    for (index_t m = o; m < e; ++m) {
      lo = std::min(lo, taps[m]);
      hi = std::max(hi, taps[m]);
    }
    if (e - o > 144 && static_cast<index_t>(hi) - lo < 64 * (e - o)) {
      std::vector<double> dense(static_cast<size_t>(hi - lo) + 1, 0.0);
      for (index_t m = o; m < e; ++m) dense[taps[m] - lo] += weights[m];
      for (index_t c = 0; c < static_cast<index_t>(dense.size()); ++c) {
        if (dense[c] > 0) {
          taps[o + n] = static_cast<int32_t>(lo + c);
          weights[o + n] = static_cast<float>(dense[c]);
          ++n;
        }
      }
    } else {
      if (e - o <= 144) {
        for (index_t m = o; m < e; ++m) {
          const int32_t tq = taps[m];
          const float tw = weights[m];
          index_t c = m;
          while (c > o && taps[c - 1] > tq) {
            taps[c] = taps[c - 1];
            weights[c] = weights[c - 1];
            --c;
          }
          taps[c] = tq;
          weights[c] = tw;
        }
      } else {
        std::vector<index_t> order(static_cast<size_t>(e - o));
        std::iota(order.begin(), order.end(), o);
        std::stable_sort(order.begin(), order.end(),
                         [&](index_t a, index_t b) { return taps[a] < taps[b]; });
        std::vector<int32_t> ts(order.size());
        std::vector<float> ws(order.size());
        for (size_t k = 0; k < order.size(); ++k) {
          ts[k] = taps[order[k]];
          ws[k] = weights[order[k]];
        }
        std::copy(ts.begin(), ts.end(), taps + o);
        std::copy(ws.begin(), ws.end(), weights + o);
      }
      for (index_t m = o; m < e; ++m) {
        if (n > 0 && taps[o + n - 1] == taps[m]) {
          weights[o + n - 1] += weights[m];  // float32, as the old JIT's
        } else {
          taps[o + n] = taps[m];
          weights[o + n] = weights[m];
          ++n;
        }
      }
    }
  }
  double total = 0.0;
  for (index_t m = o; m < o + n; ++m) total += weights[m];
  for (index_t m = o; m < o + n; ++m)
    weights[m] = static_cast<float>(total > 0 ? om * weights[m] / total : 0.0);
  return n;
}

// Source texel (f, i, j)'s merged taps at o onwards through its affine image; -1 where that
// does not apply (see _area_kernels' docstrings in the history: a window crossing a seam or
// larger than AREA_WINDOW or than the 4 nx ny entries of room, a texel that may bend).
inline index_t window_taps(int skind, index_t sh, index_t sw, index_t f, index_t i, index_t j,
                           const HalfTrig& trig, const double* rot, int dkind, index_t dh,
                           index_t dw, index_t nx, index_t ny, double om, index_t o,
                           int32_t* taps, float* weights) {
  if (bent(skind, sh, sw, i, j, dkind)) return -1;
  const Affine a = affine_image(skind, sh, sw, static_cast<double>(f), i, j, trig, rot, dkind,
                                dh, dw);
  const double rx = 0.5 * (std::fabs(a.ex0) + std::fabs(a.ey0));
  const double ry = 0.5 * (std::fabs(a.ex1) + std::fabs(a.ey1));
  if (!(rx < AREA_WINDOW && ry < AREA_WINDOW)) return -1;  // NaN too
  const index_t x0 = floor_index(a.cx - rx), y0 = floor_index(a.cy - ry);
  const index_t wx = floor_index(a.cx + rx) - x0 + 1, wy = floor_index(a.cy + ry) - y0 + 1;
  if (std::max(wx, wy) > AREA_WINDOW || wx * wy > 4 * nx * ny) return -1;
  const index_t base = block(dkind, dh, dw, a.df, x0, y0, std::max(wx, wy));
  if (base < 0) return -1;
  double window[AREA_WINDOW * AREA_WINDOW] = {};
  double col[AREA_WINDOW];
  const double nxd = static_cast<double>(nx), nyd = static_cast<double>(ny);
  const double hx = std::min(0.5, 0.5 * (std::fabs(a.ex0) / nxd + std::fabs(a.ey0) / nyd));
  const double hy = std::min(0.5, 0.5 * (std::fabs(a.ex1) / nxd + std::fabs(a.ey1) / nyd));
  for (index_t b = 0; b < ny; ++b) {
    double share = 1.0;
    const double bd = static_cast<double>(b), jd = static_cast<double>(j);
    if (skind == LATLONG)
      share = std::cos(PI * (jd + bd / nyd) / static_cast<double>(sh)) -
              std::cos(PI * (jd + (bd + 1) / nyd) / static_cast<double>(sh));
    const double fb = (bd + 0.5) / nyd - 0.5;
    for (index_t ai = 0; ai < nx; ++ai) {
      const double fa = (static_cast<double>(ai) + 0.5) / nxd - 0.5;
      const double px = a.cx + fa * a.ex0 + fb * a.ey0, py = a.cy + fa * a.ex1 + fb * a.ey1;
      for (index_t c = 0; c < wx; ++c) col[c] = overlap(px, hx, x0 + c);
      for (index_t r = 0; r < wy; ++r) {
        const double wr = share * overlap(py, hy, y0 + r);
        if (wr > 0)
          for (index_t c = 0; c < wx; ++c) window[r * wx + c] += wr * col[c];
      }
    }
  }
  double total = 0.0;
  for (index_t k = 0; k < wx * wy; ++k) total += window[k];
  index_t n = 0;
  for (index_t r = 0; r < wy; ++r) {
    for (index_t c = 0; c < wx; ++c) {
      if (window[r * wx + c] > 0) {
        taps[o + n] = static_cast<int32_t>(base + r * dw + c);
        weights[o + n] = static_cast<float>(om * window[r * wx + c] / total);
        ++n;
      }
    }
  }
  return n;
}

// Source texel (f, i, j)'s merged taps at o onwards (room up to `end`), part by part; -2 when
// the room is exceeded.
inline index_t part_taps(int skind, index_t sh, index_t sw, index_t f, index_t i, index_t j,
                         const HalfTrig& trig, const double* rot, int dkind, index_t dh,
                         index_t dw, index_t nx, index_t ny, double om_texel, index_t o,
                         index_t end, int32_t* taps, float* weights) {
  double wx[3], wy[3];
  index_t e = o;
  const bool cut_latlong = skind == LATLONG && nx * ny > 1;
  const double nxd = static_cast<double>(nx), nyd = static_cast<double>(ny);
  const double jd = static_cast<double>(j), shd = static_cast<double>(sh);
  double sdt = 0, cdt = 0, sht = 0, cht = 0, sdp = 0, cdp = 0, s1 = 0, c1 = 0;
  double st = 0, ct = 0, st2 = 0, ct2 = 0, se = 0, ce = 0, band = 0;
  if (cut_latlong) {
    const double dt = PI / static_cast<double>(sh * ny), dp = PI / static_cast<double>(sw * nx);
    sdt = std::sin(dt);
    cdt = std::cos(dt);
    sht = std::sin(dt / 2);
    cht = std::cos(dt / 2);
    sdp = std::sin(dp);
    cdp = std::cos(dp);
    s1 = trig(2, 2 * j);
    c1 = trig(3, 2 * j);
  }
  for (index_t b = 0; b < ny; ++b) {
    const double bd = static_cast<double>(b);
    if (cut_latlong) {
      const double s0 = s1, c0 = c1;
      s1 = s0 * cdt + c0 * sdt;
      c1 = c0 * cdt - s0 * sdt;
      const XY tb = band_centroid_of(PI * (jd + bd / nyd) / shd, PI * (jd + (bd + 1) / nyd) / shd,
                                     s0, c0, s1, c1);
      band = tb.y;
      st = std::sin(tb.x);
      ct = std::cos(tb.x);
      st2 = st * cht + ct * sht;
      ct2 = ct * cht - st * sht;
      se = trig(0, 2 * i);  // the texel's left edge
      ce = trig(1, 2 * i);
    }
    for (index_t a = 0; a < nx; ++a) {
      double df, cx, cy, hx, hy, om;
      if (nx * ny == 1) {
        const Footprint fp = footprint(skind, sh, sw, static_cast<double>(f), i, j, trig, rot,
                                       dkind, dh, dw);
        df = fp.df;
        cx = fp.cx;
        cy = fp.cy;
        hx = fp.hx;
        hy = fp.hy;
        om = 1.0;
      } else if (skind == LATLONG) {
        const double sp = se * cdp + ce * sdp, cp = ce * cdp - se * sdp;
        const double sp2 = sp * cdp + cp * sdp, cp2 = cp * cdp - sp * sdp;
        se = sp2;
        ce = cp2;
        const Vec3 p = latlong_unit(sp, cp, st, ct);
        const Vec3 pa = latlong_unit(sp2, cp2, st, ct);
        const Vec3 pb = latlong_unit(sp, cp, st2, ct2);
        const Part pt = part_of(p.x, p.y, p.z, pa.x, pa.y, pa.z, pb.x, pb.y, pb.z, rot, dkind, dh,
                                dw);
        df = pt.df;
        cx = pt.cx;
        cy = pt.cy;
        hx = pt.hx;
        hy = pt.hy;
        om = 2 * PI / static_cast<double>(sw) / nxd * band;
      } else {
        const Part pt = part_footprint(
            skind, sh, sw, static_cast<double>(f),
            static_cast<double>(i) + (static_cast<double>(a) + 0.5) / nxd,
            jd + (bd + 0.5) / nyd, 1 / nxd, 1 / nyd, rot, dkind, dh, dw);
        df = pt.df;
        cx = pt.cx;
        cy = pt.cy;
        hx = pt.hx;
        hy = pt.hy;
        om = pt.om;
      }
      const index_t lx = floor_index(cx - 0.5 - hx), ly = floor_index(cy - 0.5 - hy);
      box_weights(cx, hx, lx, wx);
      box_weights(cy, hy, ly, wy);
      for (index_t yb = 0; yb < 3; ++yb) {
        for (index_t xa = 0; xa < 3; ++xa) {
          const double wt = om * wx[xa] * wy[yb];
          if (wt > 0) {
            const index_t q = resolve(dkind, dh, dw, df, lx + xa, ly + yb, cx);
            if (q >= 0) {
              if (e >= end) return -2;
              taps[e] = static_cast<int32_t>(q);
              weights[e] = static_cast<float>(wt);
              ++e;
            }
          }
        }
      }
    }
  }
  return merge_taps(taps, weights, o, e, om_texel);
}

}  // namespace area_detail

// The area filter's geometry, per source texel p (see bakeshop.sphere.area._splat): anchor[p]
// (the 3 x 3 block's first texel, EXCEPTION, or -1), wq[p] (4 float32 box weights),
// scale[p], width[p], parts[p] (2), and per chunk t the sums of weights and weighted widths
// acc[t, q, :2] (chunks: acc's first axis). rot 3x3 row-major.
inline void splat_plan(int skind, index_t sh, index_t sw, index_t sfaces, const double* omega,
                       int dkind, index_t dh, index_t dw, const double* rot, int32_t* anchor,
                       float* wq, float* scale, float* width, int32_t* parts, double* acc,
                       index_t chunks, index_t m) {
  using namespace area_detail;
  const HalfTrig trig(sh, sw);
  const index_t rows = sfaces * sh;
#pragma omp parallel for schedule(static)
  for (index_t t = 0; t < chunks; ++t) {
    double* acc_t = acc + t * m * 2;
    double values[2] = {1.0, 1.0};
    double wx[3], wy[3];
    for (index_t row = t * rows / chunks; row < (t + 1) * rows / chunks; ++row) {
      const index_t f = row / sh;
      const index_t j = row - f * sh;
      for (index_t i = 0; i < sw; ++i) {
        const index_t p = row * sw + i;
        const double om = omega[p];
        anchor[p] = -1;
        if (om <= 0) continue;
        const Footprint fp =
            footprint(skind, sh, sw, static_cast<double>(f), i, j, trig, rot, dkind, dh, dw);
        parts[2 * p] = static_cast<int32_t>(fp.nx);
        parts[2 * p + 1] = static_cast<int32_t>(fp.ny);
        scale[p] = static_cast<float>(om);
        if (fp.nx * fp.ny > 1) {
          // wider than a destination texel: deposited in parts (splat_exceptions)
          anchor[p] = static_cast<int32_t>(EXCEPTION);
          width[p] = static_cast<float>(std::min(fp.width, 0.5));
          continue;
        }
        const index_t lx = floor_index(fp.cx - 0.5 - fp.hx);
        const index_t ly = floor_index(fp.cy - 0.5 - fp.hy);
        box_weights(fp.cx, fp.hx, lx, wx);
        box_weights(fp.cy, fp.hy, ly, wy);
        width[p] = static_cast<float>(fp.width);
        float* w = wq + 4 * p;
        w[0] = static_cast<float>(wx[0]);
        w[1] = static_cast<float>(wx[1]);
        w[2] = static_cast<float>(wy[0]);
        w[3] = static_cast<float>(wy[1]);
        const index_t b = block(dkind, dh, dw, fp.df, lx, ly, 3);
        anchor[p] = static_cast<int32_t>(b >= 0 ? b : EXCEPTION);
        if (b >= 0) {
          values[1] = width[p];
          deposit(acc_t, b, dw, w, scale[p], values);
        }
      }
    }
  }
}

// Add the EXCEPTION texels' weights and weighted widths to acc[0, q, :2] (one thread, in order).
inline void deposit_exceptions(const int64_t* where, index_t n, const int64_t* offsets,
                               const int32_t* taps, const float* weights, const float* width,
                               double* acc) {
  double values[2] = {1.0, 1.0};
  for (index_t k = 0; k < n; ++k) {
    values[1] = width[where[k]];
    for (int64_t e = offsets[k]; e < offsets[k + 1]; ++e) {
      const index_t q = taps[e];
      const float w = weights[e];
      for (int c = 0; c < 2; ++c) acc[2 * q + c] += w * values[c];
    }
  }
}

// Copy texel k's counts[k] merged entries from at[k] to ends[k] - counts[k] in the outputs.
inline void compact_exceptions(const int64_t* at, const int64_t* counts, index_t n,
                               const int32_t* taps, const float* weights, const int64_t* ends,
                               int32_t* out_taps, float* out_weights) {
#pragma omp parallel for schedule(static)
  for (index_t k = 0; k < n; ++k) {
    const int64_t src = at[k], dst = ends[k] - counts[k];
    for (int64_t m = 0; m < counts[k]; ++m) {
      out_taps[dst + m] = taps[src + m];
      out_weights[dst + m] = weights[src + m];
    }
  }
}

// The blend per destination texel from the splat of ones and of the footprints' widths
// (acc[t, q] = (sum w, sum w width)); inverse = 1 / sum w.
inline void area_alpha(const double* acc, index_t chunks, index_t m, const double* omega,
                       float* alpha, float* inverse) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < m; ++p) {
    double wsum = 0.0, width = 0.0;
    for (index_t t = 0; t < chunks; ++t) {
      wsum += acc[(t * m + p) * 2];
      width += acc[(t * m + p) * 2 + 1];
    }
    double a = 0.0;
    if (wsum > 0) {
      width /= wsum;
      const double ratio = width > 0 ? 1 / width : AREA_SPLAT_RATIO;
      a = std::min(1.0, std::max(0.0, (ratio - 1) / (AREA_SPLAT_RATIO - 1)));
      if (omega[p] > 0) a *= std::min(1.0, wsum / (AREA_COVERAGE * omega[p]));
    }
    alpha[p] = static_cast<float>(a);
    inverse[p] = static_cast<float>(wsum > 0 ? 1 / wsum : 0.0);
  }
}

}  // namespace bakeshop::sphere

namespace bakeshop::sphere {

// A cube source texel's exact overlaps with a latlong destination's texels (cube_latlong.hpp's
// latlong_taps) come from the caller as `latlong(k, f, i, j, om, o, room, taps, weights)` for
// texel k, returning the count or -1 where they do not apply (none: NoLatlongTaps).
struct NoLatlongTaps {
  index_t operator()(index_t, index_t, index_t, index_t, double, index_t, index_t, int32_t*,
                     float*) const {
    return -1;
  }
};

// The explicit taps and weights (summing to omega) of the splat plan's EXCEPTION texels
// `where`: texel k's entries at at[k] onwards (room up to at[k + 1]), counts[k] of them. Through
// latlong (a cube texel cut into parts into a latlong), else through its affine image where it
// is cut into few parts away from seams, else part by part; taps in increasing order.
template <class Latlong = NoLatlongTaps>
inline void splat_exceptions(int skind, index_t sh, index_t sw, const double* omega, int dkind,
                             index_t dh, index_t dw, const double* rot, const int64_t* where,
                             index_t n, const int32_t* parts, const int64_t* at, int32_t* taps,
                             float* weights, int64_t* counts, Errors& errors,
                             const Latlong& latlong = Latlong()) {
  using namespace area_detail;
  const HalfTrig trig(sh, sw);
#pragma omp parallel for schedule(dynamic, 16)
  for (index_t k = 0; k < n; ++k) {
    const index_t p = where[k];
    const index_t f = p / (sh * sw), r = p % (sh * sw);
    const index_t j = r / sw, i = r % sw;
    const index_t nx = parts[2 * p], ny = parts[2 * p + 1];
    const index_t room = at[k + 1] - at[k];
    index_t count = -1;
    if (is_cubic(skind) && dkind == LATLONG && std::max(nx, ny) > 1) {
      count = latlong(k, f, i, j, omega[p], at[k], room, taps, weights);
    } else if (1 < nx * ny && nx <= AREA_AFFINE_PARTS && ny <= AREA_AFFINE_PARTS) {
      count = window_taps(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw, nx, ny, omega[p],
                          at[k], taps, weights);
    }
    if (count < 0)
      count = part_taps(skind, sh, sw, f, i, j, trig, rot, dkind, dh, dw, nx, ny, omega[p],
                        at[k], at[k + 1], taps, weights);
    if (count < 0) {
      errors.fail("splat_exceptions: a texel's deposits beyond its room");
      count = 0;
    }
    counts[k] = count;
  }
}

}  // namespace bakeshop::sphere
