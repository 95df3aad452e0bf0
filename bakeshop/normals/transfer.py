"""Transfer ("unwrap") a tileable detail normal map into a mesh's macro UV layout.

Given the low-poly mesh with its UV set (the layout of the macro normal map) and a detail map
applied through a second UV set or a planar, box or triplanar projection in object space, this
bakes the detail into the macro layout, so it can then be blended with the macro map texel by
texel (:mod:`bakeshop.normals.blend`):

1. **Tangents**: MikkTSpace-compatible per-corner tangents for each UV set
   (:func:`corner_tangents`), so the baked map decodes correctly in engines that reconstruct
   the tangent frame with MikkTSpace (Unreal, Unity, Blender, glTF viewers).
2. **Rasterise** each triangle in macro UV space (:func:`rasterize_uv`): every texel centre
   inside a triangle gets the triangle and its barycentric coordinates.
3. **Detail coordinates and sample**: interpolate the second UV set or project the interpolated
   object-space position; sample the detail bilinearly with wrap-around from its mip chain at
   the level of the triangle's footprint (:mod:`bakeshop.normals.tiling`).
4. **Rotate** the detail normal into the world: through the detail UV set's MikkTSpace frame
   (uv2), or as the surface gradient of the projected height (planar, box, triplanar;
   Mikkelsen 2020), then into the macro tangent frame with the exact inverse of the frame an
   engine reconstructs (:func:`world_to_tangent`).
5. **Dilate** UV islands (:func:`dilate`) so mip levels do not bleed background into seams.

Texture coordinates have v up (OBJ, trimesh, OpenGL): (u, v) lies at column u W and row
(1 - v) H of a W x H map (:func:`bakeshop.io.load_mesh` converts glTF's v-down ones).

References
----------
M. S. Mikkelsen, "Simulation of wrinkled surfaces revisited", MSc thesis, University of
Copenhagen, 2008, and the reference implementation ``mikktspace.c``
(https://github.com/mmikk/MikkTSpace).
M. S. Mikkelsen, "Surface Gradient-Based Bump Mapping Framework", JCGT 9(3), 2020,
https://jcgt.org/published/0009/03/04/.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.io.mesh import Mesh
from bakeshop.normals.encoding import normalize
from bakeshop.normals.tiling import as_pair, mip_chain, trilinear_add

PROJECTIONS = ("uv2", "planar", "box", "triplanar")
AXES = ("x", "y", "z")

#: the (s, t) axes of the planar projection along each object axis, seen from that axis' +
#: side with the other axes right and up: along z (x, y); along x (-z, y); along y (x, -z).
PROJECTION_AXES = {
    "x": (np.array([0.0, 0.0, -1.0]), np.array([0.0, 1.0, 0.0])),
    "y": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0])),
    "z": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])),
}

__all__ = [
    "PROJECTIONS",
    "corner_tangents",
    "rasterize_uv",
    "world_to_tangent",
    "dilate",
    "transfer_detail",
]


# --- tangents ------------------------------------------------------------------------------


def corner_tangents(
    positions: np.ndarray, normals: np.ndarray, uv: np.ndarray, faces: np.ndarray
) -> np.ndarray:
    """MikkTSpace tangents and bitangent signs at the corners of each triangle.

    Follows ``mikktspace.c`` in the common case: each triangle's tangent is the direction of
    increasing u, dP/du = (t31_v d1 - t21_v d2) / (2 * signed UV area) with d1, d2 its edges;
    at each corner it is projected onto the plane of the vertex normal (Gram-Schmidt),
    normalised, weighted by the corner's angle (between its two edges, themselves projected
    onto that plane) and summed over the triangles that share the vertex, where "vertex"
    means the same position, normal and UV, and triangles of opposite UV orientation
    (mirrored islands) are kept apart; the sum is normalised. The sign is +1
    for triangles whose UVs keep their orientation, -1 for mirrored ones; an engine then
    builds the bitangent B = sign * cross(N, T).

    Differences from ``mikktspace.c``: triangles with a degenerate UV or position triangle
    contribute nothing (MikkTSpace gives them the tangent of a neighbour sharing the vertex; a
    corner touched only by degenerate triangles gets the projection of +X, or +Y, here), and
    quads are taken as the two triangles the mesh already holds (MikkTSpace may pick its own
    diagonal for an untriangulated quad). On meshes without such triangles the results agree.

    Parameters
    ----------
    positions, normals : (V, 3) float arrays
    uv : (V, 2) float array
    faces : (F, 3) int array

    Returns
    -------
    (F, 3, 4) float64: unit tangent (x, y, z) and sign w at each corner.
    """
    p = positions[faces]
    t = uv[faces]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    t21, t31 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    area = t21[:, 0] * t31[:, 1] - t21[:, 1] * t31[:, 0]
    sign = np.where(area > 0, 1.0, -1.0)
    vos = t31[:, 1, None] * d1 - t21[:, 1, None] * d2
    length = np.linalg.norm(vos, axis=1)
    ok = (area != 0) & (length > 0)
    vos = np.where(ok[:, None], vos * (sign / np.where(ok, length, 1))[:, None], 0.0)
    # "vertex" = same position, normal and uv; slot = vertex x orientation
    key = np.concatenate([positions, normals, uv], axis=1)
    _, vertex = np.unique(key, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1)
    slots = vertex[faces] * 2 + (sign > 0)[:, None]
    acc = np.zeros((2 * (vertex.max() + 1), 3))
    n = normals[faces]

    def onto_plane(
        v: np.ndarray, normal: np.ndarray
    ) -> np.ndarray:  # unit projection onto the plane of ``normal``, 0 if none
        v = v - np.einsum("ij,ij->i", v, normal)[:, None] * normal
        length = np.linalg.norm(v, axis=1, keepdims=True)
        return np.where(length > 0, v / np.where(length > 0, length, 1), 0.0)

    for k in range(3):
        # the corner's angle between its edges, both projected onto the normal's plane
        a = onto_plane(p[:, (k + 1) % 3] - p[:, k], n[:, k])
        b = onto_plane(p[:, (k + 2) % 3] - p[:, k], n[:, k])
        angle = np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1, 1))
        angle = np.where((a != 0).any(axis=1) & (b != 0).any(axis=1), angle, 0.0)
        np.add.at(acc, slots[:, k], onto_plane(vos, n[:, k]) * angle[:, None])
    tangent = acc[slots]  # (F, 3, 3)
    tl = np.linalg.norm(tangent, axis=2, keepdims=True)
    missing = tl[..., 0] <= 1e-12
    if missing.any():
        nn = n[missing]
        fallback = np.where(np.abs(nn[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        fallback -= np.einsum("ij,ij->i", fallback, nn)[:, None] * nn
        tangent[missing] = fallback
        tl = np.linalg.norm(tangent, axis=2, keepdims=True)
    out = np.empty(faces.shape + (4,))
    out[..., :3] = tangent / tl
    out[..., 3] = sign[:, None]
    return out


# --- rasterisation and dilation -----------------------------------------------------------


@numba.njit(cache=True)
def _rasterize(tex: np.ndarray, faces: np.ndarray, face_map: np.ndarray, bary: np.ndarray) -> None:
    height, width = face_map.shape
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ax, ay, bx, by, cx, cy = tex[a, 0], tex[a, 1], tex[b, 0], tex[b, 1], tex[c, 0], tex[c, 1]
        area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if not (abs(area) > 0) or not math.isfinite(area):
            continue
        eps = -1e-9
        x0 = max(int(math.ceil(min(ax, bx, cx) - 0.5)), 0)
        x1 = min(int(math.floor(max(ax, bx, cx) - 0.5)), width - 1)
        y0 = max(int(math.ceil(min(ay, by, cy) - 0.5)), 0)
        y1 = min(int(math.floor(max(ay, by, cy) - 0.5)), height - 1)
        for j in range(y0, y1 + 1):
            py = j + 0.5
            for i in range(x0, x1 + 1):
                px = i + 0.5
                w0 = ((bx - px) * (cy - py) - (by - py) * (cx - px)) / area
                w1 = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) / area
                w2 = 1.0 - w0 - w1
                if w0 >= eps and w1 >= eps and w2 >= eps:
                    face_map[j, i] = f
                    bary[j, i, 0] = w0
                    bary[j, i, 1] = w1
                    bary[j, i, 2] = w2


def rasterize_uv(
    uv: np.ndarray, faces: np.ndarray, shape: tuple[int, int]
) -> tuple[np.ndarray, np.ndarray]:
    """Which triangle covers each texel centre of a UV layout, and where.

    Parameters
    ----------
    uv : (V, 2) float array
        Texture coordinates, v up; (u, v) lies at column u W, row (1 - v) H.
    faces : (F, 3) int array
    shape : (H, W)

    Returns
    -------
    face : (H, W) int32
        Index of the triangle whose closed interior holds the texel centre, -1 where none
        does. Where UV triangles overlap (stacked or mirrored islands) the later one wins.
    bary : (H, W, 3) float64
        Barycentric coordinates of the texel centre in that triangle (0 where uncovered).
    """
    height, width = (int(s) for s in shape)
    tex = np.empty((len(uv), 2))
    tex[:, 0] = uv[:, 0] * width
    tex[:, 1] = (1 - uv[:, 1]) * height
    face = np.full((height, width), -1, np.int32)
    bary = np.zeros((height, width, 3))
    _rasterize(tex, np.ascontiguousarray(faces, np.int64), face, bary)
    return face, bary


@numba.njit(cache=True)
def _dilate(out: np.ndarray, filled: np.ndarray, rings: int) -> None:
    """Grow the filled region ring by ring (8-neighbours), copying values outwards."""
    height, width = filled.shape
    frontier = np.empty(height * width, np.int64)
    n = 0
    for j in range(height):
        for i in range(width):
            if filled[j, i]:
                frontier[n] = j * width + i
                n += 1
    following = np.empty(height * width, np.int64)
    ring = 0
    while n > 0 and (rings < 0 or ring < rings):
        m = 0
        for k in range(n):
            j, i = frontier[k] // width, frontier[k] % width
            for dj in range(-1, 2):
                for di in range(-1, 2):
                    jj, ii = j + dj, i + di
                    if 0 <= jj < height and 0 <= ii < width and not filled[jj, ii]:
                        filled[jj, ii] = True
                        out[jj, ii] = out[j, i]
                        following[m] = jj * width + ii
                        m += 1
        frontier, following = following, frontier
        n = m
        ring += 1


def dilate(
    image: ArrayLike,
    covered: ArrayLike,
    *,
    pixels: int | None = 16,
    background: ArrayLike = (0.0, 0.0, 1.0),
) -> np.ndarray:
    """Extend UV islands over the empty texels around them (edge padding).

    The islands grow ring by ring, ``pixels`` rings at most: each texel of a new ring copies
    a neighbour (of 8) from the ring before, as bakers' edge padding does; texels farther than
    ``pixels`` steps (chessboard distance) take ``background``. Mip levels then average
    island texels with copies of their own borders instead of the background, so seams do
    not bleed. ``pixels=None`` fills every texel.

    Parameters
    ----------
    image : (H, W, C) array
    covered : (H, W) bool array
    pixels : int or None
    background : sequence of C floats

    Returns
    -------
    (H, W, C) array, a new array of image's dtype.
    """
    out = np.array(image)
    _pad(out, covered, pixels, background)
    return out


def _pad(out: np.ndarray, covered: ArrayLike, pixels: int | None, background: ArrayLike) -> None:
    """:func:`dilate` in place."""
    if pixels is not None and pixels < 0:
        raise ArgumentError(f"padding must be >= 0 texels; got {pixels}")
    filled = np.array(covered, dtype=bool)
    if out.ndim != 3 or out.shape[:2] != filled.shape:
        raise ArgumentError(f"image {out.shape} and coverage {filled.shape} do not match")
    _dilate(out, filled, -1 if pixels is None else int(pixels))
    out[~filled] = background


# --- frames and the per-texel kernel ------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _to_tangent(
    wx: float,
    wy: float,
    wz: float,
    tx: float,
    ty: float,
    tz: float,
    sign: float,
    nx: float,
    ny: float,
    nz: float,
) -> tuple[float, float, float]:
    """[T B N]^-1 w normalised, B = sign * cross(N, T); (0, 0, 1) for a degenerate frame."""
    bx = sign * (ny * tz - nz * ty)
    by = sign * (nz * tx - nx * tz)
    bz = sign * (nx * ty - ny * tx)
    r0x, r0y, r0z = by * nz - bz * ny, bz * nx - bx * nz, bx * ny - by * nx  # B x N
    r1x, r1y, r1z = ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx  # N x T
    r2x, r2y, r2z = ty * bz - tz * by, tz * bx - tx * bz, tx * by - ty * bx  # T x B
    det = tx * r0x + ty * r0y + tz * r0z
    mx = wx * r0x + wy * r0y + wz * r0z
    my = wx * r1x + wy * r1y + wz * r1z
    mz = wx * r2x + wy * r2y + wz * r2z
    length = math.sqrt(mx * mx + my * my + mz * mz)
    if not (abs(det) > 1e-12 and length > 0 and math.isfinite(length)):
        return 0.0, 0.0, 1.0
    scale = math.copysign(1.0, det) / length
    return mx * scale, my * scale, mz * scale


@numba.njit(cache=True, parallel=True)
def _world_to_tangent(
    world: np.ndarray, tangent: np.ndarray, sign: np.ndarray, normal: np.ndarray, out: np.ndarray
) -> None:
    for i in numba.prange(world.shape[0]):
        w, t, n = world[i], tangent[i], normal[i]
        out[i, 0], out[i, 1], out[i, 2] = _to_tangent(
            w[0], w[1], w[2], t[0], t[1], t[2], sign[i], n[0], n[1], n[2]
        )


def world_to_tangent(
    world: ArrayLike, tangent: ArrayLike, sign: ArrayLike, normal: ArrayLike
) -> np.ndarray:
    """Tangent-space normal m that an engine turns back into the world normal ``world``.

    MikkTSpace's pixel shader reconstructs normalize(m_x T + m_y B + m_z N) with the
    interpolated, unnormalised T and N and B = sign * cross(N, T); this is its exact inverse,
    m = normalize([T B N]^-1 world), computed with the cofactors (B x N, N x T, T x B).

    Parameters
    ----------
    world, tangent, normal : (N, 3) float arrays
    sign : (N,) float array of +-1

    Returns
    -------
    (N, 3) float64 unit normals in the tangent frame; (0, 0, 1) where the frame is degenerate.
    """
    arrays = [np.ascontiguousarray(a, np.float64) for a in (world, tangent, sign, normal)]
    out = np.empty((len(arrays[0]), 3))
    _world_to_tangent(*arrays, out)
    return out


@numba.njit(cache=True, inline="always")
def _detail(
    texels: np.ndarray,
    offsets: np.ndarray,
    shapes: np.ndarray,
    s: float,
    t: float,
    lod: float,
    place: np.ndarray,
    acc: np.ndarray,
) -> tuple[float, float, float]:
    """The detail normal at pattern coordinates (s, t): placed (tile, rotation, offset),
    sampled trilinearly with wrap, renormalised, its XY turned with the pattern."""
    a = s * place[0]
    b = t * place[1]
    c, sn = place[4], place[5]
    qu = c * a + sn * b + place[2]
    qv = -sn * a + c * b + place[3]
    acc[0] = 0.0
    acc[1] = 0.0
    acc[2] = 0.0
    trilinear_add(
        texels, offsets, shapes, qu * shapes[0, 1], (1.0 - qv) * shapes[0, 0], lod, True, acc
    )
    length = math.sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2])
    if not length > 0:
        return 0.0, 0.0, 1.0
    dx, dy, dz = acc[0] / length, acc[1] / length, acc[2] / length
    return (c * dx - sn * dy) * place[6], (sn * dx + c * dy) * place[7], dz


_UV2, _PLANAR, _BOX, _TRIPLANAR = 0, 1, 2, 3
#: texels per task of the parallel kernel
_TASK = 4096


@numba.njit(cache=True, parallel=True)
def _shade(
    texels_idx: np.ndarray,
    face_of: np.ndarray,
    bary: np.ndarray,
    faces: np.ndarray,
    normals: np.ndarray,
    positions: np.ndarray,
    uv2: np.ndarray,
    frame: np.ndarray,
    frame2: np.ndarray,
    texels: np.ndarray,
    offsets: np.ndarray,
    shapes: np.ndarray,
    lod: np.ndarray,
    box_axis: np.ndarray,
    mode: int,
    axis: int,
    sharpness: float,
    place: np.ndarray,
    axes: np.ndarray,
    out: np.ndarray,
) -> None:
    n = texels_idx.shape[0]
    for task in numba.prange((n + _TASK - 1) // _TASK):
        acc = np.empty(3)
        wt = np.empty(3)
        for p in range(task * _TASK, min(n, (task + 1) * _TASK)):
            q = texels_idx[p]
            f = face_of[q]
            b0, b1, b2 = bary[q, 0], bary[q, 1], bary[q, 2]
            i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
            nx = b0 * normals[i0, 0] + b1 * normals[i1, 0] + b2 * normals[i2, 0]
            ny = b0 * normals[i0, 1] + b1 * normals[i1, 1] + b2 * normals[i2, 1]
            nz = b0 * normals[i0, 2] + b1 * normals[i1, 2] + b2 * normals[i2, 2]
            tx = b0 * frame[f, 0, 0] + b1 * frame[f, 1, 0] + b2 * frame[f, 2, 0]
            ty = b0 * frame[f, 0, 1] + b1 * frame[f, 1, 1] + b2 * frame[f, 2, 1]
            tz = b0 * frame[f, 0, 2] + b1 * frame[f, 1, 2] + b2 * frame[f, 2, 2]
            if mode == _UV2:
                s = b0 * uv2[i0, 0] + b1 * uv2[i1, 0] + b2 * uv2[i2, 0]
                t = b0 * uv2[i0, 1] + b1 * uv2[i1, 1] + b2 * uv2[i2, 1]
                dx, dy, dz = _detail(texels, offsets, shapes, s, t, lod[f, 0], place, acc)
                ux = b0 * frame2[f, 0, 0] + b1 * frame2[f, 1, 0] + b2 * frame2[f, 2, 0]
                uy = b0 * frame2[f, 0, 1] + b1 * frame2[f, 1, 1] + b2 * frame2[f, 2, 1]
                uz = b0 * frame2[f, 0, 2] + b1 * frame2[f, 1, 2] + b2 * frame2[f, 2, 2]
                s2 = frame2[f, 0, 3]
                vx = s2 * (ny * uz - nz * uy)
                vy = s2 * (nz * ux - nx * uz)
                vz = s2 * (nx * uy - ny * ux)
                wx = dx * ux + dy * vx + dz * nx
                wy = dx * uy + dy * vy + dz * ny
                wz = dx * uz + dy * vz + dz * nz
            else:
                nl = math.sqrt(nx * nx + ny * ny + nz * nz)
                if not nl > 0:
                    continue  # no normal: the texel stays flat
                hx, hy, hz = nx / nl, ny / nl, nz / nl
                px = b0 * positions[i0, 0] + b1 * positions[i1, 0] + b2 * positions[i2, 0]
                py = b0 * positions[i0, 1] + b1 * positions[i1, 1] + b2 * positions[i2, 1]
                pz = b0 * positions[i0, 2] + b1 * positions[i1, 2] + b2 * positions[i2, 2]
                if mode == _TRIPLANAR:
                    wt[0] = abs(hx) ** sharpness
                    wt[1] = abs(hy) ** sharpness
                    wt[2] = abs(hz) ** sharpness
                    total = wt[0] + wt[1] + wt[2]
                    for a in range(3):
                        wt[a] /= total
                else:
                    chosen = box_axis[f] if mode == _BOX else axis
                    for a in range(3):
                        wt[a] = 1.0 if a == chosen else 0.0
                gx = 0.0
                gy = 0.0
                gz = 0.0
                for a in range(3):
                    if wt[a] == 0.0:
                        continue
                    e = axes[a]
                    s = px * e[0, 0] + py * e[0, 1] + pz * e[0, 2]
                    t = px * e[1, 0] + py * e[1, 1] + pz * e[1, 2]
                    dx, dy, dz = _detail(texels, offsets, shapes, s, t, lod[f, a], place, acc)
                    k = -wt[a] / max(dz, 1e-6)
                    gx += k * (dx * e[0, 0] + dy * e[1, 0])
                    gy += k * (dx * e[0, 1] + dy * e[1, 1])
                    gz += k * (dx * e[0, 2] + dy * e[1, 2])
                gn = gx * hx + gy * hy + gz * hz
                wx = hx - (gx - gn * hx)
                wy = hy - (gy - gn * hy)
                wz = hz - (gz - gn * hz)
            m = _to_tangent(wx, wy, wz, tx, ty, tz, frame[f, 0, 3], nx, ny, nz)
            out[q, 0], out[q, 1], out[q, 2] = m


def _face_lod(detail_texels: np.ndarray, macro_texels: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """log2 of each face's footprint: detail texels per macro texel (GPU-style max axis).

    ``detail_texels`` (F, 3, 2) are the detail texel coordinates at the face's corners.
    """
    d = detail_texels
    m = macro_texels[faces]
    dm = np.stack([m[:, 1] - m[:, 0], m[:, 2] - m[:, 0]], axis=2)  # (F, 2, 2) columns
    dd = np.stack([d[:, 1] - d[:, 0], d[:, 2] - d[:, 0]], axis=2)
    det = dm[:, 0, 0] * dm[:, 1, 1] - dm[:, 0, 1] * dm[:, 1, 0]
    ok = np.abs(det) > 1e-300
    inv = (
        np.stack(
            [np.stack([dm[:, 1, 1], -dm[:, 0, 1]], 1), np.stack([-dm[:, 1, 0], dm[:, 0, 0]], 1)], 1
        )
        / np.where(ok, det, 1.0)[:, None, None]
    )
    jac = dd @ inv  # detail texels per macro texel
    footprint = np.maximum(
        np.linalg.norm(jac[:, :, 0], axis=1), np.linalg.norm(jac[:, :, 1], axis=1)
    )
    return np.where(ok, np.log2(np.maximum(footprint, 1.0)), 0.0)


def transfer_detail(
    mesh: Mesh,
    detail: ArrayLike,
    shape: tuple[int, int],
    *,
    projection: str = "uv2",
    tile: float | tuple[float, float] = 1.0,
    offset: tuple[float, float] = (0.0, 0.0),
    rotation: float = 0.0,
    axis: str = "z",
    sharpness: float = 4.0,
    strength: float = 1.0,
    padding: int | None = 16,
) -> tuple[np.ndarray, np.ndarray]:
    """Bake a tileable detail normal map into the mesh's macro UV layout (module notes).

    Parameters
    ----------
    mesh : bakeshop.io.mesh.Mesh
        The low-poly mesh; ``mesh.uv`` is the macro layout.
    detail : (h, w, 3) float array
        Unit normals of one tile of the detail (OpenGL tangent frame).
    shape : (H, W)
        Size of the output (the macro map's).
    projection : {"uv2", "planar", "box", "triplanar"}
        How the detail is applied: through ``mesh.uv2``; projected along ``axis``; per triangle
        along the object axis closest to its normal; or blended over the three axes with
        weights |N_i|^sharpness.
    tile : float or (float, float)
        Repetitions of the detail per unit of uv2, or per object-space unit for projections.
    offset, rotation
        Pattern offset (tiles) and counter-clockwise rotation (degrees), as in
        :func:`bakeshop.normals.tiling.place_detail`.
    axis : {"x", "y", "z"}
        Projection axis of ``"planar"`` (see :data:`PROJECTION_AXES`).
    sharpness : float
        Exponent of the triplanar weights.
    strength : float
        Height scale of the detail: its normals become normalize(s x, s y, z).
    padding : int or None
        Texels of dilation around UV islands (None: fill the whole map).

    Returns
    -------
    normals : (H, W, 3) float32
        The detail in the macro map's tangent frame (MikkTSpace), flat (0, 0, 1) far from
        islands. Blend it onto the macro map with ``tile=1``.
    covered : (H, W) bool
        Texels whose centre lies in a triangle.

    Notes
    -----
    For uv2, the world normal is normalize(d_x T2 + d_y B2 + d_z N) with the MikkTSpace frame
    of the second UV set, as a shader sampling the detail through uv2 computes it. For the
    projections the detail is a height field h(s, t) over the projection plane, displaced
    along the surface normal; its surface gradient is the projection of the volume gradient
    g = h_s e_s + h_t e_t onto the tangent plane, and the world normal is normalize(N - g +
    (g . N) N) (Mikkelsen 2020, section on triplanar projection); triplanar sums the three
    surface gradients with the weights.
    """
    validate_choice(projection, PROJECTIONS, "projection")
    validate_choice(axis, AXES, "projection axis")
    if mesh.uv is None:
        raise ArgumentError("the mesh has no texture coordinates (a macro UV set is needed)")
    if projection == "uv2" and mesh.uv2 is None:
        raise ArgumentError(
            "the mesh has no second UV set (glTF TEXCOORD_1); use a planar, box or "
            "triplanar projection"
        )
    d = np.asarray(detail)
    if d.ndim != 3 or d.shape[2] != 3:
        raise ArgumentError(f"a detail normal map must be (h, w, 3); got shape {d.shape}")
    height, width = (int(s) for s in shape)
    if height < 1 or width < 1 or height * width > 1 << 28:
        raise ArgumentError(f"invalid output size {width}x{height}")
    if not math.isfinite(strength):
        raise ArgumentError(f"strength must be finite; got {strength}")
    if strength != 1:
        d = normalize(d * np.array([strength, strength, 1.0], np.float32))
    if not 0 <= sharpness <= 64:
        raise ArgumentError(f"triplanar sharpness must be in [0, 64]; got {sharpness}")
    tu, tv = as_pair(tile, "tile")
    ou, ov = as_pair(offset, "offset")
    if tu == 0 or tv == 0 or not math.isfinite(rotation):
        raise ArgumentError("tile must be non-zero and rotation finite")
    chain = mip_chain(d)
    th = math.radians(rotation)
    place = np.array(
        [tu, tv, ou, ov, math.cos(th), math.sin(th), math.copysign(1, tu), math.copysign(1, tv)]
    )
    faces = mesh.faces
    assert mesh.normals is not None  # Mesh computes the normals a file lacks
    with progress.step("tangents"):
        frame = corner_tangents(mesh.positions, mesh.normals, mesh.uv, faces)
        frame2 = frame
        if projection == "uv2":
            assert mesh.uv2 is not None  # checked on entry
            frame2 = corner_tangents(mesh.positions, mesh.normals, mesh.uv2, faces)
    with progress.step("rasterising"):
        face_map, bary = rasterize_uv(mesh.uv, faces, (height, width))
    covered = face_map >= 0
    texels = np.flatnonzero(covered)

    # per-face level of detail from the Jacobian of detail texels w.r.t. macro texels
    macro_texels = np.stack([mesh.uv[:, 0] * width, (1 - mesh.uv[:, 1]) * height], axis=1)
    h0, w0 = (int(v) for v in chain.shapes[0])

    def face_lods(st: np.ndarray) -> np.ndarray:  # (F, 3, 2) pattern coordinates at the corners
        a, b = st[..., 0] * tu, st[..., 1] * tv
        qu = place[4] * a + place[5] * b
        qv = -place[5] * a + place[4] * b
        return _face_lod(np.stack([qu * w0, -qv * h0], axis=-1), macro_texels, faces)

    axes = np.array([PROJECTION_AXES[a] for a in AXES])  # (3, 2, 3): e_s, e_t per axis
    corners = mesh.positions[faces]
    if projection == "uv2":
        assert mesh.uv2 is not None  # checked on entry
        lod = face_lods(mesh.uv2[faces])[:, None]
    else:
        lod = np.stack([face_lods(corners @ axes[k].T) for k in range(3)], axis=1)
    face_normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    box_axis = np.argmax(np.abs(face_normal), axis=1)
    out = np.zeros((height * width, 3), np.float32)
    out[:, 2] = 1
    uv2 = mesh.uv2 if mesh.uv2 is not None else mesh.uv
    with progress.step("transferring"):
        _shade(
            texels,
            face_map.reshape(-1),
            bary.reshape(-1, 3),
            faces,
            mesh.normals,
            mesh.positions,
            uv2,
            frame,
            frame2,
            chain.texels,
            chain.offsets,
            chain.shapes,
            np.ascontiguousarray(lod),
            box_axis,
            PROJECTIONS.index(projection),
            AXES.index(axis),
            float(sharpness),
            place,
            axes,
            out,
        )
    normals = out.reshape(height, width, 3)
    _pad(normals, covered, padding, (0.0, 0.0, 1.0))
    return normals, covered
