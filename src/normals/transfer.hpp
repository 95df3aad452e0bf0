// The kernels of bakeshop/normals/transfer.py: UV rasterisation, island dilation, the exact
// inverse of an engine's tangent frame, and the per-texel transfer of a detail map.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/kernel.hpp"
#include "normals/tiling.hpp"

namespace bakeshop::normals {

// face_map[j, i] = the last face whose closed interior holds texel centre (i + 0.5, j + 0.5) of
// the texel-space coordinates `tex` (V, 2), bary[j, i] its barycentric coordinates. In face
// order (a later face wins), so not parallel. The faces index `tex` (checked by the caller).
inline void rasterize(const double* tex, const int64_t* faces, index_t n_faces, index_t height,
                      index_t width, int32_t* face_map, double* bary) {
  for (index_t f = 0; f < n_faces; ++f) {
    const int64_t a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
    const double ax = tex[2 * a], ay = tex[2 * a + 1], bx = tex[2 * b], by = tex[2 * b + 1],
                 cx = tex[2 * c], cy = tex[2 * c + 1];
    const double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (!(std::fabs(area) > 0) || !std::isfinite(area)) continue;
    const double eps = -1e-9;
    const int64_t x0 = std::max<int64_t>(ceil_int(std::min(std::min(ax, bx), cx) - 0.5), 0);
    const int64_t x1 = std::min<int64_t>(floor_int(std::max(std::max(ax, bx), cx) - 0.5), width - 1);
    const int64_t y0 = std::max<int64_t>(ceil_int(std::min(std::min(ay, by), cy) - 0.5), 0);
    const int64_t y1 = std::min<int64_t>(floor_int(std::max(std::max(ay, by), cy) - 0.5), height - 1);
    for (int64_t j = y0; j <= y1; ++j) {
      const double py = static_cast<double>(j) + 0.5;
      for (int64_t i = x0; i <= x1; ++i) {
        const double px = static_cast<double>(i) + 0.5;
        const double w0 = ((bx - px) * (cy - py) - (by - py) * (cx - px)) / area;
        const double w1 = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 >= eps && w1 >= eps && w2 >= eps) {
          face_map[j * width + i] = static_cast<int32_t>(f);
          double* o = bary + (j * width + i) * 3;
          o[0] = w0;
          o[1] = w1;
          o[2] = w2;
        }
      }
    }
  }
}

// Grow the filled region of an (H, W) image of `bytes`-byte texels ring by ring (8-neighbours,
// `rings` rings, all when negative), each new texel copying the one it grew from.
inline void dilate(uint8_t* out, index_t bytes, bool* filled, index_t height, index_t width,
                   int64_t rings) {
  std::vector<int64_t> frontier, following;
  frontier.reserve(static_cast<size_t>(height * width));
  for (index_t j = 0; j < height; ++j)
    for (index_t i = 0; i < width; ++i)
      if (filled[j * width + i]) frontier.push_back(j * width + i);
  int64_t ring = 0;
  while (!frontier.empty() && (rings < 0 || ring < rings)) {
    following.clear();
    for (const int64_t at : frontier) {
      const int64_t j = at / width, i = at % width;
      for (int64_t dj = -1; dj < 2; ++dj)
        for (int64_t di = -1; di < 2; ++di) {
          const int64_t jj = j + dj, ii = i + di;
          if (0 <= jj && jj < height && 0 <= ii && ii < width && !filled[jj * width + ii]) {
            filled[jj * width + ii] = true;
            std::memcpy(out + (jj * width + ii) * bytes, out + at * bytes,
                        static_cast<size_t>(bytes));
            following.push_back(jj * width + ii);
          }
        }
    }
    frontier.swap(following);
    ++ring;
  }
}

// [T B N]^-1 w normalised, B = sign * cross(N, T); (0, 0, 1) for a degenerate frame.
inline void to_tangent(double wx, double wy, double wz, double tx, double ty, double tz,
                       double sign, double nx, double ny, double nz, double& ox, double& oy,
                       double& oz) {
  const double bx = sign * (ny * tz - nz * ty);
  const double by = sign * (nz * tx - nx * tz);
  const double bz = sign * (nx * ty - ny * tx);
  const double r0x = by * nz - bz * ny, r0y = bz * nx - bx * nz, r0z = bx * ny - by * nx;  // BxN
  const double r1x = ny * tz - nz * ty, r1y = nz * tx - nx * tz, r1z = nx * ty - ny * tx;  // NxT
  const double r2x = ty * bz - tz * by, r2y = tz * bx - tx * bz, r2z = tx * by - ty * bx;  // TxB
  const double det = tx * r0x + ty * r0y + tz * r0z;
  const double mx = wx * r0x + wy * r0y + wz * r0z;
  const double my = wx * r1x + wy * r1y + wz * r1z;
  const double mz = wx * r2x + wy * r2y + wz * r2z;
  const double length = std::sqrt(mx * mx + my * my + mz * mz);
  if (!(std::fabs(det) > 1e-12 && length > 0 && std::isfinite(length))) {
    ox = 0.0, oy = 0.0, oz = 1.0;
    return;
  }
  const double scale = std::copysign(1.0, det) / length;
  ox = mx * scale, oy = my * scale, oz = mz * scale;
}

inline void world_to_tangent(const double* world, const double* tangent, const double* sign,
                             const double* normal, index_t n, double* out) {
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < n; ++i) {
    const double *w = world + 3 * i, *t = tangent + 3 * i, *nn = normal + 3 * i;
    to_tangent(w[0], w[1], w[2], t[0], t[1], t[2], sign[i], nn[0], nn[1], nn[2], out[3 * i],
               out[3 * i + 1], out[3 * i + 2]);
  }
}

// The detail normal at pattern coordinates (s, t): placed by `place` (tile u, v, offset u, v,
// cos, sin, sign u, sign v), sampled trilinearly with wrap, renormalised, its XY turned.
inline void detail_at(const Chain& c, double s, double t, double lod, const double* place,
                      double& dx, double& dy, double& dz) {
  const double a = s * place[0];
  const double b = t * place[1];
  const double co = place[4], sn = place[5];
  const double qu = co * a + sn * b + place[2];
  const double qv = -sn * a + co * b + place[3];
  double acc[3] = {0.0, 0.0, 0.0};
  trilinear_add(c, qu * static_cast<double>(c.shapes[1]), (1.0 - qv) * static_cast<double>(c.shapes[0]),
                lod, true, acc);
  const double length = std::sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]);
  if (!(length > 0)) {
    dx = 0.0, dy = 0.0, dz = 1.0;
    return;
  }
  const double ux = acc[0] / length, uy = acc[1] / length, uz = acc[2] / length;
  dx = (co * ux - sn * uy) * place[6];
  dy = (sn * ux + co * uy) * place[7];
  dz = uz;
}

enum Projection { uv2_mode = 0, planar_mode = 1, box_mode = 2, triplanar_mode = 3 };

// What shade() reads: the mesh (faces (F, 3), normals, positions (V, 3), uv2 (V, 2)), its
// corner frames (F, 3, 4) for the macro and the detail UV sets, the face of each texel and its
// barycentric coordinates, the detail's chain and levels (F, lod_stride), the box axis of each
// face (F,), the projection axes e_s, e_t of each object axis (3, 2, 3).
struct ShadeInputs {
  const int32_t* face_of;
  const double* bary;
  index_t n_texels_total;
  const int64_t* faces;
  index_t n_faces;
  const double* normals;
  const double* positions;
  const double* uv2;
  const double* frame;
  const double* frame2;
  Chain chain;
  const double* lod;
  index_t lod_stride;
  const int64_t* box_axis;
  int mode;
  int64_t axis;
  double sharpness;
  const double* place;
  const double* axes;
};

// out[q] (float32, 3 per texel) = the detail in the macro tangent frame at each texel q of
// `texels`; a texel without a normal (planar, box, triplanar) is left as it is.
inline void shade(const ShadeInputs& in, const int64_t* texels, index_t n, float* out) {
  Errors errors;
#pragma omp parallel for schedule(dynamic, 4096)
  for (index_t p = 0; p < n; ++p) {
    if (errors.failed()) continue;
    const int64_t q = texels[p];
    if (q < 0 || q >= in.n_texels_total) {
      errors.fail("transfer: a texel index outside the map");
      continue;
    }
    const int64_t f = in.face_of[q];
    if (f < 0 || f >= in.n_faces) {
      errors.fail("transfer: a covered texel without a face");
      continue;
    }
    const double b0 = in.bary[3 * q], b1 = in.bary[3 * q + 1], b2 = in.bary[3 * q + 2];
    const int64_t i0 = in.faces[3 * f], i1 = in.faces[3 * f + 1], i2 = in.faces[3 * f + 2];
    const double* nm = in.normals;
    const double nx = b0 * nm[3 * i0] + b1 * nm[3 * i1] + b2 * nm[3 * i2];
    const double ny = b0 * nm[3 * i0 + 1] + b1 * nm[3 * i1 + 1] + b2 * nm[3 * i2 + 1];
    const double nz = b0 * nm[3 * i0 + 2] + b1 * nm[3 * i1 + 2] + b2 * nm[3 * i2 + 2];
    const double* fr = in.frame + 12 * f;  // (3 corners, 4)
    const double tx = b0 * fr[0] + b1 * fr[4] + b2 * fr[8];
    const double ty = b0 * fr[1] + b1 * fr[5] + b2 * fr[9];
    const double tz = b0 * fr[2] + b1 * fr[6] + b2 * fr[10];
    double wx, wy, wz;
    if (in.mode == uv2_mode) {
      const double* uv = in.uv2;
      const double s = b0 * uv[2 * i0] + b1 * uv[2 * i1] + b2 * uv[2 * i2];
      const double t = b0 * uv[2 * i0 + 1] + b1 * uv[2 * i1 + 1] + b2 * uv[2 * i2 + 1];
      double dx, dy, dz;
      detail_at(in.chain, s, t, in.lod[f * in.lod_stride], in.place, dx, dy, dz);
      const double* f2 = in.frame2 + 12 * f;
      const double ux = b0 * f2[0] + b1 * f2[4] + b2 * f2[8];
      const double uy = b0 * f2[1] + b1 * f2[5] + b2 * f2[9];
      const double uz = b0 * f2[2] + b1 * f2[6] + b2 * f2[10];
      const double s2 = f2[3];
      const double vx = s2 * (ny * uz - nz * uy);
      const double vy = s2 * (nz * ux - nx * uz);
      const double vz = s2 * (nx * uy - ny * ux);
      wx = dx * ux + dy * vx + dz * nx;
      wy = dx * uy + dy * vy + dz * ny;
      wz = dx * uz + dy * vz + dz * nz;
    } else {
      const double nl = std::sqrt(nx * nx + ny * ny + nz * nz);
      if (!(nl > 0)) continue;  // no normal: the texel stays flat
      const double hx = nx / nl, hy = ny / nl, hz = nz / nl;
      const double* ps = in.positions;
      const double px = b0 * ps[3 * i0] + b1 * ps[3 * i1] + b2 * ps[3 * i2];
      const double py = b0 * ps[3 * i0 + 1] + b1 * ps[3 * i1 + 1] + b2 * ps[3 * i2 + 1];
      const double pz = b0 * ps[3 * i0 + 2] + b1 * ps[3 * i1 + 2] + b2 * ps[3 * i2 + 2];
      double wt[3];
      if (in.mode == triplanar_mode) {
        wt[0] = std::pow(std::fabs(hx), in.sharpness);
        wt[1] = std::pow(std::fabs(hy), in.sharpness);
        wt[2] = std::pow(std::fabs(hz), in.sharpness);
        const double total = wt[0] + wt[1] + wt[2];
        for (int a = 0; a < 3; ++a) wt[a] /= total;
      } else {
        const int64_t chosen = in.mode == box_mode ? in.box_axis[f] : in.axis;
        for (int a = 0; a < 3; ++a) wt[a] = a == chosen ? 1.0 : 0.0;
      }
      double gx = 0.0, gy = 0.0, gz = 0.0;
      for (int a = 0; a < 3; ++a) {
        if (wt[a] == 0.0) continue;
        const double* e = in.axes + 6 * a;  // e_s = e[0:3], e_t = e[3:6]
        const double s = px * e[0] + py * e[1] + pz * e[2];
        const double t = px * e[3] + py * e[4] + pz * e[5];
        double dx, dy, dz;
        detail_at(in.chain, s, t, in.lod[f * in.lod_stride + a], in.place, dx, dy, dz);
        const double k = -wt[a] / py_max(dz, 1e-6);
        gx += k * (dx * e[0] + dy * e[3]);
        gy += k * (dx * e[1] + dy * e[4]);
        gz += k * (dx * e[2] + dy * e[5]);
      }
      const double gn = gx * hx + gy * hy + gz * hz;
      wx = hx - (gx - gn * hx);
      wy = hy - (gy - gn * hy);
      wz = hz - (gz - gn * hz);
    }
    double mx, my, mz;
    to_tangent(wx, wy, wz, tx, ty, tz, fr[3], nx, ny, nz, mx, my, mz);
    out[3 * q] = static_cast<float>(mx);
    out[3 * q + 1] = static_cast<float>(my);
    out[3 * q + 2] = static_cast<float>(mz);
  }
  errors.check();
}

}  // namespace bakeshop::normals
