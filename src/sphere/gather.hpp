// The remap plan and gather kernels (bakeshop/sphere/_plans.py): nearest and seam-aware
// bilinear taps, built once per (source, destination, rotation) and applied as one parallel
// gather. The same arithmetic as the old JIT kernels they replace, operation for operation: the
// nearest and bilinear results are bit-identical.
//
// Types: an image's weights are computed in its type T (float32 stays float32) where the old JIT
// computed them so, and in double where the old JIT's int-float promotion made them double (the
// seam/corner blend `bilinear_corner`, the clamped gather).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/kernel.hpp"
#include "sphere/maps.hpp"

namespace bakeshop::sphere {

// A remap plan's base index for a texel whose taps are not a 2x2 block (seams, rims, corners):
// EXCEPTION - k points at row k of the plan's explicit taps.
constexpr index_t EXCEPTION = -2;

// Texels of a layout's flat image (a cube: 6 faces).
inline index_t layout_texels(int kind, index_t h, index_t w) {
  return (is_cubic(kind) ? 6 : 1) * h * w;
}

// The seam-aware bilinear taps of the point at coordinates (f, x, y): index[0..3] the flat
// indices of texels (i0, j0), (i0 + 1, j0), (i0, j0 + 1), (i0 + 1, j0 + 1) (resolve: -1 for a
// cube corner) and frac[0..1] the fractions. The one implementation for taps_of and the
// windows' part taps.
template <class I, class F>
inline void bilinear_taps(int kind, index_t h, index_t w, double f, double x, double y,
                          I* index, F* frac) {
  const double xs = x - 0.5, ys = y - 0.5;
  const double x0 = std::floor(xs), y0 = std::floor(ys);
  frac[0] = static_cast<F>(xs - x0);
  frac[1] = static_cast<F>(ys - y0);
  const index_t i0 = trunc_index(x0), j0 = trunc_index(y0);
  index[0] = static_cast<I>(resolve(kind, h, w, f, i0, j0, x));
  index[1] = static_cast<I>(resolve(kind, h, w, f, i0 + 1, j0, x));
  index[2] = static_cast<I>(resolve(kind, h, w, f, i0, j0 + 1, x));
  index[3] = static_cast<I>(resolve(kind, h, w, f, i0 + 1, j0 + 1, x));
}

// Whether a source coordinate is finite (a NaN or infinite direction has no texel).
inline bool finite_coordinate(double x, double y) {
  return std::fabs(x) < 1e18 && std::fabs(y) < 1e18;
}

// Source taps for sampling layout (kind, h, w) at directions dirs (count, 3): nearest, index
// (count, cols) gets the texel in column 0; bilinear, the four taps and frac (count, 2).
template <class I, class F>
inline void taps_of(int kind, index_t h, index_t w, const double* dirs, index_t count,
                    bool nearest, I* index, index_t cols, F* frac) {
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    const Coords c = coordinates(kind, h, w, dirs[3 * p], dirs[3 * p + 1], dirs[3 * p + 2]);
    I* row = index + p * cols;
    if (!finite_coordinate(c.x, c.y)) {
      for (index_t k = 0; k < cols; ++k) row[k] = -1;
    } else if (nearest) {
      row[0] = static_cast<I>(nearest_texel(kind, h, w, c.f, c.x, c.y));
    } else {
      bilinear_taps(kind, h, w, c.f, c.x, c.y, row, frac + 2 * p);
    }
  }
}

// Flat index of texel (f, i0, j0) when the size x size block from it holds ordinary texels of
// one image (one face, one disk, all valid), else -1: then resolve of block texel (a, b) is
// that index + b w + a.
inline index_t block(int kind, index_t h, index_t w, double f, index_t i0, index_t j0,
                     index_t size) {
  if (i0 < 0 || j0 < 0 || i0 + size > w || j0 + size > h) return -1;
  if (is_cubic(kind)) return (trunc_index(f) * h + j0) * w + i0;
  if (is_disk(kind)) {
    const index_t n = h;
    const index_t li = py_mod(i0, n);
    if (li + size > n) return -1;
    for (index_t dj = 0; dj < size; ++dj) {
      for (index_t di = 0; di < size; ++di) {
        if (!valid(kind, h, w, 0, li + di, j0 + dj)) return -1;
      }
    }
  }
  return j0 * w + i0;
}

// Direction of destination texel (f, i, j)'s centre, rotated into the source's frame (rot 3x3
// row-major; trig: latlong_trig(dh, dw), m = max(dh, dw) its row length, for a latlong).
inline Vec3 plan_direction(int dkind, index_t dh, index_t dw, index_t f, index_t i, index_t j,
                           const double* rot, const double* trig, index_t m) {
  Vec3 d;
  if (dkind == LATLONG) {
    d = {trig[2 * m + j] * trig[i], trig[3 * m + j], -trig[2 * m + j] * trig[m + i]};
  } else {
    d = direction(dkind, dh, dw, static_cast<double>(f), static_cast<double>(i) + 0.5,
                  static_cast<double>(j) + 0.5);
  }
  return rotate(rot, d.x, d.y, d.z);
}

// latlong_trig(h, w) as a vector (4 * max(h, w)).
inline std::vector<double> latlong_table(index_t h, index_t w) {
  std::vector<double> trig(static_cast<size_t>(4 * std::max(h, w)));
  latlong_trig(h, w, trig.data());
  return trig;
}

// The weights (1 - fx)(1 - fy), fx (1 - fy), (1 - fx) fy, fx fy of fractions of type F as
// the old JIT typed them: `1 - fx` is a double (int - float32 promotes), `fx * fy` stays an F.
template <class F>
inline void promoted_weights(F fx, F fy, double w[4]) {
  const double dx = fx, dy = fy;
  w[0] = (1 - dx) * (1 - dy);
  w[1] = dx * (1 - dy);
  w[2] = (1 - dx) * dy;
  w[3] = static_cast<double>(fx * fy);
}

// A cube corner's (or any incomplete block's) blend: the missing texels are the mean of the
// others (OpenGL; divided by 3), in double (promoted_weights).
template <class T>
inline double bilinear_corner(const T* src, index_t nc, index_t i0, index_t i1, index_t i2,
                              index_t i3, T fx, T fy, index_t c) {
  double w[4];
  promoted_weights(fx, fy, w);
  const double w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3];
  if (i0 >= 0 && i1 >= 0 && i2 >= 0 && i3 >= 0) {
    return w0 * src[i0 * nc + c] + w1 * src[i1 * nc + c] + w2 * src[i2 * nc + c] +
           w3 * src[i3 * nc + c];
  }
  double v0 = i0 >= 0 ? static_cast<double>(src[i0 * nc + c]) : 0.0;
  double v1 = i1 >= 0 ? static_cast<double>(src[i1 * nc + c]) : 0.0;
  double v2 = i2 >= 0 ? static_cast<double>(src[i2 * nc + c]) : 0.0;
  double v3 = i3 >= 0 ? static_cast<double>(src[i3 * nc + c]) : 0.0;
  const double m = (v0 + v1 + v2 + v3) / 3;
  v0 = i0 >= 0 ? v0 : m;
  v1 = i1 >= 0 ? v1 : m;
  v2 = i2 >= 0 ? v2 : m;
  v3 = i3 >= 0 ? v3 : m;
  return w0 * v0 + w1 * v1 + w2 * v2 + w3 * v3;
}

// The four taps of plan texel p: base b >= 0 a 2x2 block (rows `row` texels long), else the
// explicit taps' row EXCEPTION - b. False (and an error) when they lie outside the source or
// the taps (a plan read back from a cache file is checked).
inline bool plan_taps(const int32_t* taps, index_t ntaps, index_t n_src, index_t row, index_t b,
                      index_t t[4], Errors& errors) {
  if (b >= 0) {
    t[0] = b;
    t[1] = b + 1;
    t[2] = b + row;
    t[3] = b + row + 1;
  } else {
    const index_t k = EXCEPTION - b;
    if (k >= ntaps) {
      errors.fail("remap plan: an exception row beyond its taps");
      return false;
    }
    for (int q = 0; q < 4; ++q) t[q] = taps[4 * k + q];
  }
  for (int q = 0; q < 4; ++q) {
    if (t[q] < -1 || t[q] >= n_src) {
      errors.fail("remap plan: a tap outside the source image");
      return false;
    }
  }
  return true;
}

// out[p] from the bilinear plan (see plan): 0 for an invalid texel (base -1).
template <class T>
inline void gather_texel(const T* src, index_t n_src, index_t nc, index_t row,
                         const int32_t* base, const float* frac, const int32_t* taps,
                         index_t ntaps, index_t p, T* out, Errors& errors) {
  T* o = out + p * nc;
  const index_t b = base[p];
  if (b == -1) {
    for (index_t c = 0; c < nc; ++c) o[c] = 0;
    return;
  }
  index_t t[4];
  if (!plan_taps(taps, ntaps, n_src, row, b, t, errors)) return;
  const T one = 1;
  const T fx = static_cast<T>(frac[2 * p]), fy = static_cast<T>(frac[2 * p + 1]);
  const T gx = one - fx, gy = one - fy;
  const T w0 = gx * gy, w1 = fx * gy, w2 = gx * fy, w3 = fx * fy;
  if (t[0] >= 0 && t[1] >= 0 && t[2] >= 0 && t[3] >= 0) {
    const T *s0 = src + t[0] * nc, *s1 = src + t[1] * nc, *s2 = src + t[2] * nc,
            *s3 = src + t[3] * nc;
    for (index_t c = 0; c < nc; ++c) o[c] = w0 * s0[c] + w1 * s1[c] + w2 * s2[c] + w3 * s3[c];
  } else {
    for (index_t c = 0; c < nc; ++c) {
      o[c] = static_cast<T>(bilinear_corner(src, nc, t[0], t[1], t[2], t[3], fx, fy, c));
    }
  }
}

// The remap plan of destination texel centres, one destination row at a time: the rows
// first_row onwards (of the faces stacked), count / dw of them (p counts from the first).
// Nearest: base[p] is the source texel (-1: invalid destination texel). Bilinear: base[p] is
// the upper-left tap of an ordinary 2x2 block, EXCEPTION where the taps cross a seam (resolved
// by plan_exceptions) or -1 for an invalid texel; frac[p] the fractions. Unless out is null,
// the plan is also applied to the flat image src (n_src, nc) on the way (the EXCEPTION texels
// are left to gather_at).
template <class T>
inline void plan(int skind, index_t sh, index_t sw, int dkind, index_t dh, index_t dw,
                 const double* rot, bool nearest, int32_t* base, index_t count, float* frac,
                 const T* src, index_t n_src, index_t nc, T* out, index_t first_row) {
  const index_t m = std::max(dh, dw);
  const std::vector<double> table = latlong_table(dh, dw);
  const double* trig = table.data();
  Errors errors;  // no taps are read back here: nothing fails
#pragma omp parallel
  {
    std::vector<double> buf(static_cast<size_t>(5 * dw));
    std::vector<double> sf(static_cast<size_t>(dw));
    double *xs = buf.data(), *ys = xs + dw, *zs = ys + dw, *us = zs + dw, *vs = us + dw;
#pragma omp for schedule(static)
    for (index_t local = 0; local < count / dw; ++local) {
      const index_t row = first_row + local;
      const index_t f = py_div(row, dh);
      const index_t j = row - f * dh;
      if (is_cubic(dkind)) {
        face_row(dkind, dw, f, j, dw, xs, ys, zs);
        for (index_t i = 0; i < dw; ++i) {
          const Vec3 d = rotate(rot, xs[i], ys[i], zs[i]);
          xs[i] = d.x;
          ys[i] = d.y;
          zs[i] = d.z;
        }
      } else {
        for (index_t i = 0; i < dw; ++i) {
          const Vec3 d = plan_direction(dkind, dh, dw, f, i, j, rot, trig, m);
          xs[i] = d.x;
          ys[i] = d.y;
          zs[i] = d.z;
        }
      }
      if (skind == LATLONG) {
        for (index_t i = 0; i < dw; ++i) {
          latlong_xy(sh, sw, xs[i], ys[i], zs[i], us[i], vs[i]);
          sf[i] = 0;
        }
      } else {
        for (index_t i = 0; i < dw; ++i) {
          const Coords c = coordinates(skind, sh, sw, xs[i], ys[i], zs[i]);
          sf[i] = c.f;
          us[i] = c.x;
          vs[i] = c.y;
        }
      }
      for (index_t i = 0; i < dw; ++i) {
        const index_t p = local * dw + i;
        const double sx = us[i], sy = vs[i];
        if (!valid(dkind, dh, dw, static_cast<double>(f), i, j) || !finite_coordinate(sx, sy)) {
          base[p] = -1;
        } else if (nearest) {
          base[p] = static_cast<int32_t>(nearest_texel(skind, sh, sw, sf[i], sx, sy));
        } else {
          const double xf = sx - 0.5, yf = sy - 0.5;
          const double x0 = std::floor(xf), y0 = std::floor(yf);
          frac[2 * p] = static_cast<float>(xf - x0);
          frac[2 * p + 1] = static_cast<float>(yf - y0);
          const index_t b = block(skind, sh, sw, sf[i], trunc_index(x0), trunc_index(y0), 2);
          base[p] = static_cast<int32_t>(b >= 0 ? b : EXCEPTION);
        }
        if (out != nullptr) {
          if (nearest) {
            const index_t b = base[p];
            for (index_t c = 0; c < nc; ++c) out[p * nc + c] = b >= 0 ? src[b * nc + c] : T(0);
          } else if (base[p] != EXCEPTION) {
            gather_texel(src, n_src, nc, sw, base, frac, nullptr, 0, p, out, errors);
          }
        }
      }
    }
  }
  errors.check();
}

// The four seam-aware taps (count, 4) of the plan's EXCEPTION texels `where` (flat indices of
// the destination, faces stacked; -1: a cube corner).
inline void plan_exceptions(int skind, index_t sh, index_t sw, int dkind, index_t dh,
                            index_t dw, const double* rot, const int64_t* where, index_t count,
                            int32_t* taps) {
  const index_t per = dh * dw;
  const index_t m = std::max(dh, dw);
  const std::vector<double> table = latlong_table(dh, dw);
  const double* trig = table.data();
#pragma omp parallel for schedule(static)
  for (index_t k = 0; k < count; ++k) {
    const index_t f = py_div(where[k], per), r = py_mod(where[k], per);
    const index_t j = py_div(r, dw), i = py_mod(r, dw);
    const Vec3 d = plan_direction(dkind, dh, dw, f, i, j, rot, trig, m);
    const Coords c = coordinates(skind, sh, sw, d.x, d.y, d.z);
    const index_t i0 = floor_index(c.x - 0.5), j0 = floor_index(c.y - 0.5);
    int32_t* t = taps + 4 * k;
    t[0] = static_cast<int32_t>(resolve(skind, sh, sw, c.f, i0, j0, c.x));
    t[1] = static_cast<int32_t>(resolve(skind, sh, sw, c.f, i0 + 1, j0, c.x));
    t[2] = static_cast<int32_t>(resolve(skind, sh, sw, c.f, i0, j0 + 1, c.x));
    t[3] = static_cast<int32_t>(resolve(skind, sh, sw, c.f, i0 + 1, j0 + 1, c.x));
  }
}

// The plan of texels `order` (-1: none, an invalid texel); frac null for a nearest plan.
inline void reorder_plan(const int32_t* base, const float* frac, index_t n, const int32_t* order,
                         index_t count, int32_t* out_base, float* out_frac) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    index_t k = order[p];
    if (k >= n) {
      errors.fail("reorder_plan: an order index beyond the plan");
      k = -1;
    }
    out_base[p] = k >= 0 ? base[k] : -1;
    if (out_frac != nullptr) {
      out_frac[2 * p] = k >= 0 ? frac[2 * k] : 0.0f;
      out_frac[2 * p + 1] = k >= 0 ? frac[2 * k + 1] : 0.0f;
    }
  }
  errors.check();
}

// Apply a bilinear remap plan (base, frac, taps (ntaps, 4)) to src (n_src, nc), whose rows are
// `row` texels long, into out (count, nc).
template <class T>
inline void gather_plan(const T* src, index_t n_src, index_t nc, index_t row, const int32_t* base,
                        index_t count, const float* frac, const int32_t* taps, index_t ntaps,
                        T* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    gather_texel(src, n_src, nc, row, base, frac, taps, ntaps, p, out, errors);
  }
  errors.check();
}

// gather_plan for the output texels `where` only.
template <class T>
inline void gather_at(const T* src, index_t n_src, index_t nc, index_t row, const int32_t* base,
                      index_t count, const float* frac, const int32_t* taps, index_t ntaps,
                      const int64_t* where, index_t nwhere, T* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t k = 0; k < nwhere; ++k) {
    if (where[k] < 0 || where[k] >= count) {
      errors.fail("gather_at: a texel beyond the plan");
      continue;
    }
    gather_texel(src, n_src, nc, row, base, frac, taps, ntaps, where[k], out, errors);
  }
  errors.check();
}

// out[p] = src[index[p, 0]] (0 where -1); index (count, cols).
template <class T>
inline void gather_nearest(const T* src, index_t n_src, index_t nc, const int32_t* index,
                           index_t count, index_t cols, T* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    const index_t i = index[p * cols];
    if (i >= n_src || i < -1) {
      errors.fail("gather_nearest: a texel outside the source image");
      continue;
    }
    for (index_t c = 0; c < nc; ++c) out[p * nc + c] = i >= 0 ? src[i * nc + c] : T(0);
  }
  errors.check();
}

// out[p] = bilinear blend of the four taps of index[p] with fractions frac[p] (of the image's
// type); all taps -1: 0 (an invalid texel); one tap -1: a cube corner.
template <class T>
inline void gather_bilinear(const T* src, index_t n_src, index_t nc, const int32_t* index,
                            index_t count, const T* frac, T* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    const int32_t* t = index + 4 * p;
    const index_t i0 = t[0], i1 = t[1], i2 = t[2], i3 = t[3];
    if (std::min(std::min(i0, i1), std::min(i2, i3)) < -1 ||
        std::max(std::max(i0, i1), std::max(i2, i3)) >= n_src) {
      errors.fail("gather_bilinear: a tap outside the source image");
      continue;
    }
    T* o = out + p * nc;
    const T one = 1;
    const T fx = frac[2 * p], fy = frac[2 * p + 1];
    const T gx = one - fx, gy = one - fy;
    const T w0 = gx * gy, w1 = fx * gy, w2 = gx * fy, w3 = fx * fy;
    if (i0 >= 0 && i1 >= 0 && i2 >= 0 && i3 >= 0) {
      const T *s0 = src + i0 * nc, *s1 = src + i1 * nc, *s2 = src + i2 * nc, *s3 = src + i3 * nc;
      for (index_t c = 0; c < nc; ++c) o[c] = w0 * s0[c] + w1 * s1[c] + w2 * s2[c] + w3 * s3[c];
    } else if (i0 < 0 && i1 < 0) {
      for (index_t c = 0; c < nc; ++c) o[c] = 0;
    } else {
      for (index_t c = 0; c < nc; ++c) {
        o[c] = static_cast<T>(bilinear_corner(src, nc, i0, i1, i2, i3, fx, fy, c));
      }
    }
  }
  errors.check();
}

// gather_plan of the source with every value clamped to at most `clamp` (values in double,
// weights as the old JIT promoted them: promoted_weights of the float32 fractions).
template <class T>
inline void gather_plan_clamped(const T* src, index_t n_src, index_t nc, index_t row,
                                const int32_t* base, index_t count, const float* frac,
                                const int32_t* taps, index_t ntaps, double clamp, T* out) {
  Errors errors;
#pragma omp parallel for schedule(static)
  for (index_t p = 0; p < count; ++p) {
    T* o = out + p * nc;
    const index_t b = base[p];
    if (b == -1) {
      for (index_t c = 0; c < nc; ++c) o[c] = 0;
      continue;
    }
    index_t t[4];
    if (!plan_taps(taps, ntaps, n_src, row, b, t, errors)) continue;
    double w[4];
    promoted_weights(frac[2 * p], frac[2 * p + 1], w);
    const double w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3];
    const bool corner = t[0] < 0 || t[1] < 0 || t[2] < 0 || t[3] < 0;
    for (index_t c = 0; c < nc; ++c) {
      double v[4];
      for (int q = 0; q < 4; ++q) {
        if (t[q] >= 0) {
          const double s = src[t[q] * nc + c];
          v[q] = clamp < s ? clamp : s;  // the old JIT's min(s, clamp)
        } else {
          v[q] = 0.0;
        }
      }
      if (corner) {
        // a cube corner: the missing texel is the mean of the other three (OpenGL)
        const double m = (v[0] + v[1] + v[2] + v[3]) / 3;
        for (int q = 0; q < 4; ++q) v[q] = t[q] >= 0 ? v[q] : m;
      }
      o[c] = static_cast<T>(w0 * v[0] + w1 * v[1] + w2 * v[2] + w3 * v[3]);
    }
  }
  errors.check();
}

}  // namespace bakeshop::sphere
