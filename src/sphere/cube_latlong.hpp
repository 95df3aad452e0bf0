// The area filter's exact deposits of a cube texel into a latlong's texels: its overlaps with
// them, integrated (the area filter's splat_exceptions calls
// latlong_taps for every texel of a cube cut into parts on its way to a latlong). The same
// arithmetic as the old JIT functions it replaces, operation for operation.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::sphere {

// A cube texel's overlaps are integrated when every corner is in one hemisphere, at least this
// far from the equator (|y|).
constexpr double AREA_EXACT_Y = 0.02;

// Python's float a % b (the sign of b).
inline double py_fmod(double a, double b) {
  double mod = std::fmod(a, b);
  if (mod != 0.0) {
    if ((b < 0) != (mod < 0)) mod += b;
  } else {
    mod = std::copysign(0.0, b);
  }
  return mod;
}

namespace cube_latlong_detail {

constexpr double INF = std::numeric_limits<double>::infinity();

// Where the ray from the origin towards (cp, sp) is inside the convex quadrilateral (px, py;
// orient the sign of its area): its distances (lo, hi), lo >= hi if nowhere.
inline void chord(const double* px, const double* py, double orient, double cp, double sp,
                  double& lo, double& hi) {
  lo = 0.0;
  hi = INF;
  for (int k = 0; k < 4; ++k) {
    const double ex = px[(k + 1) % 4] - px[k], ey = py[(k + 1) % 4] - py[k];
    const double alpha = orient * (ex * sp - ey * cp);
    const double beta = orient * (ex * py[k] - ey * px[k]);
    if (alpha > 0) {
      lo = std::max(lo, beta / alpha);
    } else if (alpha < 0) {
      hi = std::min(hi, beta / alpha);
    } else if (beta > 0) {
      lo = hi = 0.0;
      return;
    }
  }
}

// Distance from the origin to the segment from (ax, ay) to (bx, by).
inline double segment_distance(double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double t = std::min(1.0, std::max(0.0, -(ax * ex + ay * ey) / (ex * ex + ey * ey)));
  return std::hypot(ax + t * ex, ay + t * ey);
}

// The longitude of point (x, y) of the tangent plane in the turn of the columns: within pi of
// centre unless around (in (-pi, pi] then).
inline double longitude(double x, double y, bool around, double centre) {
  const double phi = std::atan2(y, x);
  return around ? phi : centre + py_fmod(phi - centre + PI, 2 * PI) - PI;
}

// Append to breaks[n:] the longitudes where the segment from (ax, ay) to (bx, by) crosses the
// circle of radius; returns the new count.
inline index_t crossings(double ax, double ay, double bx, double by, double radius, bool around,
                         double centre, double* breaks, index_t n) {
  const double ex = bx - ax, ey = by - ay;
  const double ee = ex * ex + ey * ey, ae = ax * ex + ay * ey;
  const double disc = ae * ae - ee * (ax * ax + ay * ay - radius * radius);
  if (!(disc > 0 && ee > 0)) return n;
  const double ts[2] = {(-ae - std::sqrt(disc)) / ee, (-ae + std::sqrt(disc)) / ee};
  for (double t : ts) {
    if (0 < t && t < 1) {
      breaks[n] = longitude(ax + t * ex, ay + t * ey, around, centre);
      n += 1;
    }
  }
  return n;
}

// Add to out[r] (r < rows) the solid angle of the quadrilateral's part between longitudes
// a < b and radii radii[r] to radii[r + 1], piece by piece between breaks (sorted), each piece
// by 2-point Gauss-Legendre.
inline void overlaps(const double* px, const double* py, double orient, const double* breaks,
                     index_t nbreaks, double a, double b, const double* radii, index_t rows,
                     double* out) {
  const double node = std::sqrt(1.0 / 3);
  const double gauss[2] = {-node, node};
  double lo_end = a;
  for (index_t k = 0; k < nbreaks + 1; ++k) {
    const double hi_end = k == nbreaks ? b : std::min(b, breaks[k]);
    if (hi_end > lo_end) {
      const double mid = 0.5 * (lo_end + hi_end), half = 0.5 * (hi_end - lo_end);
      for (int g = 0; g < 2; ++g) {
        const double phi = mid + half * gauss[g];
        double lo, hi;
        chord(px, py, orient, std::cos(phi), std::sin(phi), lo, hi);
        if (hi > lo) {
          for (index_t r = 0; r < rows; ++r) {
            const double near = std::max(lo, radii[r]), far = std::min(hi, radii[r + 1]);
            if (far > near) {
              out[r] += half * (1 / std::sqrt(1 + near * near) - 1 / std::sqrt(1 + far * far));
            }
          }
        }
      }
      lo_end = hi_end;
    }
  }
}

}  // namespace cube_latlong_detail

// Source cube texel (f, i, j)'s overlaps with the texels of a latlong destination (dh x dw) at
// taps[o:] / weights[o:], at most room of them, in increasing order, weights scaled to sum om;
// -1 where it does not apply (its corners not all in one hemisphere, AREA_EXACT_Y from the
// equator, or more overlaps than room). rot: 3x3 row-major (the remap's rotation).
template <class W>
inline index_t latlong_taps(int skind, index_t sh, index_t sw, index_t f, index_t i, index_t j,
                            const double* rot, index_t dh, index_t dw, double om, index_t o,
                            index_t room, int32_t* taps, W* weights) {
  using namespace cube_latlong_detail;
  double px[4], py[4], corners[4];
  double sign = 0.0;
  for (int k = 0; k < 4; ++k) {
    const index_t corner_x = (k == 1 || k == 2) ? i + 1 : i;
    const Vec3 d0 = direction(skind, sh, sw, static_cast<double>(f),
                              static_cast<double>(corner_x),
                              static_cast<double>(k >= 2 ? j + 1 : j));
    // rotate(rot.T, d): rot d
    const double x = rot[0] * d0.x + rot[1] * d0.y + rot[2] * d0.z;
    const double y = rot[3] * d0.x + rot[4] * d0.y + rot[5] * d0.z;
    const double z = rot[6] * d0.x + rot[7] * d0.y + rot[8] * d0.z;
    if (!(std::fabs(y) >= AREA_EXACT_Y) || y * sign < 0) return -1;
    sign = y > 0 ? 1.0 : -1.0;
    px[k] = -z / std::fabs(y);
    py[k] = x / std::fabs(y);
  }
  double area = 0.0;
  for (int k = 0; k < 4; ++k) area += px[k] * py[(k + 1) % 4] - px[(k + 1) % 4] * py[k];
  const double orient = area > 0 ? 1.0 : -1.0;
  double r_min = INF, r_max = 0.0;
  bool around = true;
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    r_max = std::max(r_max, std::hypot(px[k], py[k]));
    r_min = std::min(r_min, segment_distance(px[k], py[k], px[n], py[n]));
    around = around && (orient * (px[n] - px[k]) * py[k] - orient * (py[n] - py[k]) * px[k] <= 0);
  }
  double centre = 0.0;
  if (!around) {
    centre = std::atan2(0.0 + py[0] + py[1] + py[2] + py[3], 0.0 + px[0] + px[1] + px[2] + px[3]);
  }
  for (int k = 0; k < 4; ++k) corners[k] = longitude(px[k], py[k], around, centre);
  index_t c0, count;
  if (around) {
    r_min = 0.0;
    c0 = 0;
    count = dw;
  } else {
    double cmin = corners[0], cmax = corners[0];
    for (int k = 1; k < 4; ++k) {
      cmin = std::min(cmin, corners[k]);
      cmax = std::max(cmax, corners[k]);
    }
    const double dwd = static_cast<double>(dw);
    c0 = floor_index((cmin / (2 * PI) + 0.5) * dwd);
    count = std::min(dw, floor_index((cmax / (2 * PI) + 0.5) * dwd) - c0 + 1);
  }
  // the rows between those radii: colatitude atan r from the north pole, pi - atan r south
  const double dhd = static_cast<double>(dh);
  double t0 = std::atan(r_min) / PI * dhd, t1 = std::atan(r_max) / PI * dhd;
  if (sign < 0) {
    const double n0 = dhd - t1, n1 = dhd - t0;
    t0 = n0;
    t1 = n1;
  }
  const index_t j0 = std::max(index_t{0}, floor_index(t0));
  const index_t j1 = std::min(dh - 1, floor_index(t1));
  const index_t rows = j1 - j0 + 1;
  if (rows < 1 || count < 1 || rows * count > room) return -1;
  std::vector<double> radii(static_cast<size_t>(rows + 1));
  std::vector<double> breaks(static_cast<size_t>(8 * rows + 12));
  std::vector<double> window(static_cast<size_t>(count * rows), 0.0);
  for (int k = 0; k < 4; ++k) breaks[k] = corners[k];
  index_t found = 4;
  for (index_t r = 0; r < rows + 1; ++r) {
    const double a =
        PI * static_cast<double>(sign > 0 ? j0 + r : dh - j1 - 1 + r) / dhd;
    radii[r] = a < 0.5 * PI ? std::tan(a) : INF;
    for (int k = 0; k < 4; ++k) {
      found = crossings(px[k], py[k], px[(k + 1) % 4], py[(k + 1) % 4], radii[r], around, centre,
                        breaks.data(), found);
    }
  }
  // (NaNs last, as numpy sorts them)
  std::sort(breaks.begin(), breaks.begin() + found,
            [](double u, double v) { return u < v || (v != v && u == u); });
  const double dphi = 2 * PI / static_cast<double>(dw);
  for (index_t m = 0; m < count; ++m) {
    const double phi = dphi * static_cast<double>(c0 + m) - PI;
    overlaps(px, py, orient, breaks.data(), found, phi, phi + dphi, radii.data(), rows,
             window.data() + m * rows);
  }
  // column c0 + m is texel (c0 + m) % dw: increasing from m = dw - (c0 % dw), then from 0
  const index_t start = dw - py_mod(c0, dw);
  index_t n = 0;
  double total = 0.0;
  for (index_t row = j0; row < j1 + 1; ++row) {
    const index_t r = sign > 0 ? row - j0 : j1 - row;
    const index_t ranges[2][2] = {{start, count}, {0, std::min(start, count)}};
    for (const auto& range : ranges) {
      for (index_t m = range[0]; m < range[1]; ++m) {
        const double w = window[m * rows + r];
        if (w > 0) {
          taps[o + n] = static_cast<int32_t>(row * dw + py_mod(c0 + m, dw));
          weights[o + n] = static_cast<W>(w);
          total += w;
          n += 1;
        }
      }
    }
  }
  if (!(total > 0)) return -1;
  for (index_t e = o; e < o + n; ++e) {
    weights[e] = static_cast<W>(static_cast<double>(weights[e]) * (om / total));
  }
  return n;
}

}  // namespace bakeshop::sphere
