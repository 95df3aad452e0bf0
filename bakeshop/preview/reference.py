"""The preview's shading equations in numpy, at chosen pixels: the reference the GLSL is checked
against.

Nothing here runs the shaders or shares their code: the camera ray, the ray-sphere hit, the
latlong and DFG lookups (bilinear, as OpenGL filters a 2-D texture: texel centres at
(i + 0.5) / N, u repeating, v clamped), the cube lookups (:func:`bakeshop.sphere.sample`, whose
bilinear filter is checked against the driver's seamless cube filtering in
``tests/sphere/test_opengl.py``), the mip blend, the split sum and the sun's GGX term are written
again from their equations, in float64.

>>> from bakeshop.preview import read_bake, View
>>> from bakeshop.preview.reference import shade_balls
>>> bake = read_bake("demo")
>>> colour, ball = shade_balls(bake, View("balls", 1280, 720), rows, cols)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.preview.scene import BALL_KINDS, balls

if TYPE_CHECKING:
    from bakeshop.preview.bake import Bake, Sun
    from bakeshop.preview.render import View

__all__ = [
    "camera_rays",
    "cube_lod",
    "dfg_lookup",
    "hit_balls",
    "latlong_bilinear",
    "shade_balls",
    "sh_irradiance",
    "sky",
    "sun_specular",
]

#: F0 of the dielectric end of the metallic-roughness model.
DIELECTRIC_F0 = 0.04


def camera_rays(view: View, rows: ArrayLike, cols: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Origins and unit directions of the camera rays through pixel centres.

    Parameters
    ----------
    view : View
    rows, cols : (N,) int
        Pixels, row 0 at the top of the picture.

    Returns
    -------
    origin, direction : (N, 3) float64
        The ray from the near plane through the far plane of ``view``'s camera at normalised
        device coordinates x = 2 (col + 1/2) / W - 1, y = 1 - 2 (row + 1/2) / H.
    """
    rows, cols = np.asarray(rows, np.float64), np.asarray(cols, np.float64)
    inv = np.linalg.inv(view.eye.view_projection(view.width / view.height))
    x = 2 * (cols + 0.5) / view.width - 1
    y = 1 - 2 * (rows + 0.5) / view.height
    ends = []
    for z in (-1.0, 1.0):
        p = np.stack([x, y, np.full_like(x, z), np.ones_like(x)], -1) @ inv.T
        ends.append(p[:, :3] / p[:, 3:])
    d = ends[1] - ends[0]
    return ends[0], d / np.linalg.norm(d, axis=1, keepdims=True)


def hit_balls(
    items: list[dict], origin: np.ndarray, direction: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The nearest ball each ray meets in front of its origin.

    Returns
    -------
    index : (N,) int
        Into ``items``; -1 where the ray meets none.
    normal : (N, 3) float64
        The outward unit normal at the hit (0 where there is none).
    """
    n = len(origin)
    best = np.full(n, np.inf)
    index = np.full(n, -1)
    for i, ball in enumerate(items):
        oc = origin - np.asarray(ball["centre"], np.float64)
        b = np.einsum("ij,ij->i", oc, direction)
        c = np.einsum("ij,ij->i", oc, oc) - ball["radius"] ** 2
        disc = b * b - c
        t = -b - np.sqrt(np.where(disc >= 0, disc, np.nan))
        closer = (disc >= 0) & (t > 0) & (t < best)
        best = np.where(closer, t, best)
        index = np.where(closer, i, index)
    normal = np.zeros((n, 3))
    hit = index >= 0
    centres = np.array([b["centre"] for b in items], np.float64).reshape(-1, 3)
    if hit.any():
        p = origin[hit] + direction[hit] * best[hit, None]
        v = p - centres[index[hit]]
        normal[hit] = v / np.linalg.norm(v, axis=1, keepdims=True)
    return index, normal


def _bilinear(image: np.ndarray, u: ArrayLike, v: ArrayLike, *, repeat_u: bool) -> np.ndarray:
    """OpenGL's LINEAR filter of a 2-D texture at (u, v) in [0, 1] (v = 0 is row 0): texel
    centres at (i + 1/2) / N; u wraps or clamps to the edge, v clamps to the edge."""
    h, w = image.shape[:2]
    x = np.asarray(u, np.float64) * w - 0.5
    y = np.asarray(v, np.float64) * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    x0, y0 = x0.astype(int), y0.astype(int)

    def col(i: np.ndarray) -> np.ndarray:
        return np.mod(i, w) if repeat_u else np.clip(i, 0, w - 1)

    def row(j: np.ndarray) -> np.ndarray:
        return np.clip(j, 0, h - 1)

    a = np.asarray(image, np.float64)
    top = a[row(y0), col(x0)] * (1 - fx) + a[row(y0), col(x0 + 1)] * fx
    bottom = a[row(y0 + 1), col(x0)] * (1 - fx) + a[row(y0 + 1), col(x0 + 1)] * fx
    return top * (1 - fy) + bottom * fy


def latlong_bilinear(image: np.ndarray, directions: ArrayLike) -> np.ndarray:
    """A latlong texture (a DIM) looked up as the shaders do: u = atan2(x, -z) / 2 pi + 1/2
    (1/2 straight up or down, where atan2 is undefined), v = acos(y) / pi, bilinear with u
    repeating.

    Parameters
    ----------
    image : (H, 2H, C) float
    directions : (N, 3) unit vectors

    Returns
    -------
    (N, C) float64
    """
    d = np.asarray(directions, np.float64)
    pole = (d[:, 0] == 0) & (d[:, 2] == 0)
    u = np.where(pole, 0.5, np.arctan2(d[:, 0], -d[:, 2]) / (2 * np.pi) + 0.5)
    v = np.arccos(np.clip(d[:, 1], -1, 1)) / np.pi
    return _bilinear(image, u, v, repeat_u=True)


def dfg_lookup(table: np.ndarray, n_dot_v: ArrayLike, roughness: ArrayLike) -> np.ndarray:
    """The split-sum table's (scale, bias) at (n.v, roughness): bilinear, clamped at the edges
    (columns n.v, rows roughness, texel centres at (i + 1/2) / N).

    Returns
    -------
    (N, 2) float64
    """
    return _bilinear(table, n_dot_v, roughness, repeat_u=False)


def cube_lod(levels: list, directions: ArrayLike, lod: ArrayLike) -> np.ndarray:
    """A mip-mapped cube looked up at a level of detail (``textureLod`` with
    LINEAR_MIPMAP_LINEAR): the seamless bilinear lookups of levels floor(lod) and the next,
    blended by the fraction.

    Parameters
    ----------
    levels : list of (6, S_m, S_m, C)
    directions : (N, 3)
    lod : float or (N,) float
        Clamped to [0, len(levels) - 1].

    Returns
    -------
    (N, C) float64
    """
    from bakeshop.sphere import sample

    d = np.asarray(directions, np.float64)
    lod = np.clip(np.broadcast_to(np.asarray(lod, np.float64), (len(d),)), 0, len(levels) - 1)
    low = np.floor(lod).astype(int)
    frac = (lod - low)[:, None]
    out = np.zeros((len(d), levels[0].shape[-1]))
    for m in np.unique(low):
        sel = low == m
        a = sample(levels[m], "cube", d[sel], filter="bilinear").astype(np.float64)
        if m + 1 < len(levels):
            b = sample(levels[m + 1], "cube", d[sel], filter="bilinear").astype(np.float64)
            a = a * (1 - frac[sel]) + b * frac[sel]
        out[sel] = a
    return out


def sky(bake: Bake, directions: ArrayLike, level: float = -1.0) -> np.ndarray:
    """The background along ``directions``: the environment cube (``level < 0``) or that level
    of detail of the specular chain. (N, 3) float64."""
    if level < 0:
        return cube_lod([bake.cube], directions, 0.0)
    return cube_lod(bake.specular, directions, level)


def sh_irradiance(coefficients: ArrayLike, normals: ArrayLike) -> np.ndarray:
    """E/pi from 9 real orthonormal SH coefficients (index l(l+1)+m; Y(1,-1) ~ y, Y(1,0) ~ z,
    Y(1,1) ~ x): the basis written out with its constants sqrt(1/4pi), sqrt(3/4pi),
    sqrt(15/4pi), sqrt(5/16pi), sqrt(15/16pi). (N, 3) float64."""
    x, y, z = (np.asarray(normals, np.float64)[:, k] for k in range(3))
    k0, k1 = np.sqrt(1 / (4 * np.pi)), np.sqrt(3 / (4 * np.pi))
    k2, k3, k4 = np.sqrt(15 / (4 * np.pi)), np.sqrt(5 / (16 * np.pi)), np.sqrt(15 / (16 * np.pi))
    basis = np.stack(
        [
            np.full_like(x, k0),
            k1 * y,
            k1 * z,
            k1 * x,
            k2 * x * y,
            k2 * y * z,
            k3 * (3 * z * z - 1),
            k2 * x * z,
            k4 * (x * x - y * y),
        ],
        -1,
    )
    return basis @ np.asarray(coefficients, np.float64)[:9]


def sun_specular(
    sun: Sun | None,
    normals: ArrayLike,
    views: ArrayLike,
    roughness: ArrayLike,
    f0: float | np.ndarray,
) -> np.ndarray:
    """The sun as a light on a GGX surface: D(h) V(l, v) F(v.h) (n.l) E_sun, with GGX's
    D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2), the height-correlated Smith visibility
    V = 1/2 / (n.l sqrt((n.v)^2 (1 - a^2) + a^2) + n.v sqrt((n.l)^2 (1 - a^2) + a^2)),
    Schlick's F = F0 + (1 - F0)(1 - v.h)^5, and a = max(roughness^2, the sun's angular radius)
    (Karis, "Real Shading in Unreal Engine 4", 2013). (N, 3) float64."""
    n, v = np.asarray(normals, np.float64), np.asarray(views, np.float64)
    if sun is None:
        return np.zeros_like(n)
    l = np.asarray(sun.direction, np.float64)  # noqa: E741 - the light vector's usual name
    nl = n @ l
    nv = np.maximum(np.einsum("ij,ij->i", n, v), 1e-4)
    a = np.maximum(np.asarray(roughness, np.float64) ** 2, sun.radius)
    a2 = a * a
    h = l + v
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    nh = np.maximum(np.einsum("ij,ij->i", n, h), 0)
    d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    vis = 0.5 / (nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2))
    f = f0 + (1 - f0) * (1 - np.maximum(np.einsum("ij,ij->i", v, h), 0))[:, None] ** 5
    out = (d * vis)[:, None] * f * nl[:, None] * np.asarray(sun.irradiance, np.float64)
    return np.where((nl > 0)[:, None], out, 0.0)


def shade_balls(
    bake: Bake, view: View, rows: ArrayLike, cols: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """The linear radiance the balls (or sky) view shows at chosen pixels.

    Per ball kind: Lambertian albedo * sun DIM(n), * shadow DIM(n) or * SH(n); GGX
    (metallic-roughness): (1 - metalness) base * sun DIM(n) + prefiltered(r, roughness (L - 1))
    (F0 A + B) with F0 = mix(0.04, base, metalness), (A, B) = DFG(n.v, roughness), r the mirror
    direction of the view (Karis 2013's split sum), plus :func:`sun_specular` when
    ``view.sun_light``. Where no ball is hit: :func:`sky`.

    Returns
    -------
    colour : (N, 3) float64
    ball : (N,) int
        The ball each pixel shows, -1 for the sky.
    """
    items = balls(len(bake.specular)) if view.scene == "balls" else []
    origin, d = camera_rays(view, rows, cols)
    index, n = hit_balls(items, origin, d)
    out = np.zeros((len(d), 3))
    miss = index < 0
    if miss.any():
        out[miss] = sky(bake, d[miss], view.sky_level)
    if not items or miss.all():
        return out, index
    hit = ~miss
    ns, vs = n[hit], -d[hit]
    table = {
        name: np.array([b[name] for b in items], np.float64)
        for name in ("roughness", "metalness", "colour")
    }
    kinds = np.array([BALL_KINDS[b["kind"]] for b in items])[index[hit]]
    base = table["colour"][index[hit]]
    rough = table["roughness"][index[hit]]
    metal = table["metalness"][index[hit]][:, None]
    colour = np.zeros_like(ns)
    for name, lookup in (
        ("sun-dim", lambda x: latlong_bilinear(bake.sun_dim, x)),
        ("shadow-dim", lambda x: latlong_bilinear(bake.shadow_dim, x)),
        ("sh", lambda x: sh_irradiance(bake.sh, x)),
    ):
        sel = kinds == BALL_KINDS[name]
        if sel.any():
            colour[sel] = base[sel] * lookup(ns[sel])
    sel = kinds == BALL_KINDS["ggx"]
    if sel.any():
        n, v, r0, m, c = ns[sel], vs[sel], rough[sel], metal[sel], base[sel]
        f0 = DIELECTRIC_F0 * (1 - m) + c * m
        nv = np.clip(np.einsum("ij,ij->i", n, v), 0, 1)
        r = 2 * np.einsum("ij,ij->i", n, v)[:, None] * n - v
        pre = cube_lod(bake.specular, r, r0 * (len(bake.specular) - 1))
        ab = dfg_lookup(bake.dfg, nv, r0)
        ggx = (1 - m) * c * latlong_bilinear(bake.sun_dim, n) + pre * (f0 * ab[:, :1] + ab[:, 1:])
        if view.sun_light:
            ggx = ggx + sun_specular(bake.sun, n, v, r0, f0)
        colour[sel] = ggx
    out[hit] = colour
    return out, index
