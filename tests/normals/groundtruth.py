"""Ground truth for the blend methods: analytic surfaces whose true normals are known.

The macro surface is a height field over the macro map's UV square, S(u, v) = (u, v, H(u, v)),
with Gaussian bumps and grooves, so its tangent-space normal map (relative to the flat low-poly
plane) is n1 = normalize(-H_u, -H_v, 1). The micro detail is a tileable height field d(s, t)
whose flat normal map is n2(s, t) = normalize(-d_s, -d_t, 1). Three constructions combine them:

(a) ``"axis"``: heights added along the fixed axis z: P = (u, v, H + d(u, v)).
(b) ``"uv"``: d indexed by the macro UVs and displaced along the macro normal N:
    P = S(u, v) + d(u, v) N(u, v). The team's case (the detail unwrapped onto the macro UVs).
(c) ``"arclength"``: as (b) but indexed by arc length on the macro surface: the detail advances
    by the arc length along the u and v lines, ds = |S_u| du and dt = |S_v| dv. No indexing can
    do that everywhere on a surface with Gaussian curvature (integrating ds along u drags a
    shear behind every bump), so it is defined around each sample point (u0, v0):
    (s, t) = (s0, t0) + (|S_u| (u - u0), |S_v| (v - v0)), with (s0, t0) the arc lengths from the
    border along each line (the phase of the pattern there).

The true normal of each P is normalize(P_u x P_v) with P_u, P_v by central differences of the
analytic P (step 1e-5, error ~1e-9); the arc lengths of (c) by 128-point Gauss-Legendre
quadrature. Nothing here uses a blend formula: it is an independent reference for them.
"""

from __future__ import annotations

import numpy as np

CONSTRUCTIONS = ("axis", "uv", "arclength")

#: (centre u, centre v, amplitude, width) of the Gaussian bumps (amplitude > 0) and pits.
_BUMPS = ((0.3, 0.32, 0.10, 0.09), (0.72, 0.66, 0.08, 0.07), (0.25, 0.78, -0.06, 0.08))
#: (point u, point v, angle, depth, width) of the straight grooves (Gaussian cross-section).
_GROOVES = ((0.5, 0.5, 0.35, 0.035, 0.03), (0.62, 0.2, 1.9, 0.025, 0.025))

_STEP = 1e-5
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(128)


def macro_height(u, v):
    """H(u, v) and its derivatives (H, H_u, H_v) in macro-UV units."""
    h = np.zeros_like(u)
    hu = np.zeros_like(u)
    hv = np.zeros_like(u)
    for cu, cv, a, w in _BUMPS:
        g = a * np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * w * w))
        h += g
        hu += -g * (u - cu) / (w * w)
        hv += -g * (v - cv) / (w * w)
    for pu, pv, angle, depth, w in _GROOVES:
        nu, nv = -np.sin(angle), np.cos(angle)  # normal of the groove's line
        r = (u - pu) * nu + (v - pv) * nv
        g = -depth * np.exp(-(r * r) / (2 * w * w))
        h += g
        hu += -g * r / (w * w) * nu
        hv += -g * r / (w * w) * nv
    return h, hu, hv


def detail_height(s, t, *, tiles: int = 24, slope: float = 0.6):
    """A tileable detail height d(s, t) (period 1/tiles) and its derivatives (d, d_s, d_t).

    A few oblique waves, so the slopes point in every direction; ``slope`` is the largest
    slope of one wave (the sum reaches about twice that).
    """
    k = 2 * np.pi * tiles
    waves = ((1, 0, 1.0, 0.0), (0, 1, 0.8, 1.0), (1, 1, 0.5, 2.0), (2, -1, 0.35, 0.5))
    d = np.zeros_like(s)
    ds = np.zeros_like(s)
    dt = np.zeros_like(s)
    for a, b, amp, phase in waves:
        freq = k * np.hypot(a, b)
        c = slope * amp / freq
        arg = k * (a * s + b * t) + phase
        d += c * np.sin(arg)
        ds += c * k * a * np.cos(arg)
        dt += c * k * b * np.cos(arg)
    return d, ds, dt


def _unit(x, y, z):
    n = np.stack([x, y, z], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def _arclength(u, v):
    """(s, t): arc length along u from u = 0 at fixed v, and along v from v = 0 at fixed u."""
    x = (_NODES + 1) * 0.5
    w = _WEIGHTS * 0.5
    uu = u[..., None] * x
    _, hu, _ = macro_height(uu, np.broadcast_to(v[..., None], uu.shape))
    s = u * (np.sqrt(1 + hu * hu) @ w)
    vv = v[..., None] * x
    _, _, hv = macro_height(np.broadcast_to(u[..., None], vv.shape), vv)
    t = v * (np.sqrt(1 + hv * hv) @ w)
    return s, t


def _coordinates(construction, u, v):
    return _arclength(u, v) if construction == "arclength" else (u, v)


def _surface(construction, u, v, around, **detail):
    """P at (u, v); for "arclength", with the detail coordinates linearised at ``around``."""
    h, hu, hv = macro_height(u, v)
    if construction == "arclength":
        (s0, t0), (u0, v0), (ju, jv) = around
        s, t = s0 + ju * (u - u0), t0 + jv * (v - v0)
    else:
        s, t = u, v
    d, _, _ = detail_height(s, t, **detail)
    if construction == "axis":
        return np.stack([u, v, h + d], axis=-1)
    n = _unit(-hu, -hv, np.ones_like(u))
    return np.stack([u, v, h], axis=-1) + d[..., None] * n


def maps(construction: str, size: int = 128, **detail):
    """The macro and detail normal maps a renderer would blend, and the true normals.

    Parameters
    ----------
    construction : {"axis", "uv", "arclength"}
    size : int
        Evaluated at the centres of a ``size`` x ``size`` grid over the UV square.
    **detail
        ``tiles`` and ``slope`` of :func:`detail_height`.

    Returns
    -------
    macro, detail, truth : (size, size, 3) float64 unit normals (tangent frame of the flat
        low-poly plane: x along u, y along v, z up).
    """
    c = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(c, c[::-1])
    _, hu, hv = macro_height(u, v)
    macro = _unit(-hu, -hv, np.ones_like(u))
    s, t = _coordinates(construction, u, v)
    _, ds, dt = detail_height(s, t, **detail)
    detail_map = _unit(-ds, -dt, np.ones_like(u))
    _, hu, hv = macro_height(u, v)
    around = ((s, t), (u, v), (np.sqrt(1 + hu * hu), np.sqrt(1 + hv * hv)))
    h = _STEP
    pu = _surface(construction, u + h, v, around, **detail)
    pu -= _surface(construction, u - h, v, around, **detail)
    pv = _surface(construction, u, v + h, around, **detail)
    pv -= _surface(construction, u, v - h, around, **detail)
    truth = np.cross(pu, pv)
    truth /= np.linalg.norm(truth, axis=-1, keepdims=True)
    return macro, detail_map, truth


def angular_error(a, b) -> np.ndarray:
    """Angle in degrees between unit vectors ``a`` and ``b`` (..., 3), robust near 0."""
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    dot = np.einsum("...i,...i->...", a, b)
    return np.degrees(np.arctan2(cross, dot))
