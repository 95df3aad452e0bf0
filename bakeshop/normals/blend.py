"""A detail normal map blended onto a macro normal map: every established method, and the exact one.

All functions take decoded unit normals in the OpenGL tangent frame (see
:mod:`bakeshop.normals.encoding`): ``macro`` n1 = (x1, y1, z1), the reference surface, and
``detail`` n2 = (x2, y2, z2), the perturbation, as ``(..., 3)`` arrays of the same shape. They
return unit normals of that shape, float64 if both inputs are float64, else float32.

Strength
--------
``strength`` s scales the detail's *height*, the same way for every method: the detail normal
becomes normalize(s x2, s y2, z2) (its slopes -x2/z2, -y2/z2 times s) before blending. s = 0 is a
flat detail, s < 0 inverts it, and s may be an array broadcastable to the texel shape ``(...)``
(a mask times a strength). Every method returns the macro normal for a flat detail.

Methods
-------
With t = n1 + (0, 0, 1) and u = (-x2, -y2, z2) (unnormalised results are renormalised):

=========  ===========================================================  ======================
method     result                                                        flat macro -> detail
=========  ===========================================================  ======================
linear     n1 + (n2 - (0, 0, 1))                                         yes
overlay    packed p = (n + 1)/2: overlay(p1, p2) on x, y; p1 p2 on z       yes
pd         (x1 z2 + x2 z1, y1 z2 + y2 z1, z1 z2)                         yes
whiteout   (x1 + x2, y1 + y2, z1 z2)                                     yes
udn        (x1 + x2, y1 + y2, z1)                                        no (z of n2 dropped)
rnm        t (t . u) / t_z - u                                           yes
sg         vN - (sg1 + sg2), surface gradients relative to vN = (0,0,1)   yes
exact      (z2 - x2 x1 - y2 y1) n1 + (x2, y2, 0)                         yes
=========  ===========================================================  ======================

``exact`` is derived in docs/normals.md: a detail height field d indexed by the macro map's UVs
and displaced along the macro surface's normal has, up to the macro curvature, the normal
n1 - grad_S d, where grad_S d is d's gradient on the macro surface. For a macro surface that is
a height field over the UV plane, the dual tangent vectors are e_x - x1 n1 and e_y - y1 n1, so
grad_S d = g - (g . n1) n1 with g = -(x2, y2, 0) / z2: the detail's slopes along the fixed UV
axes, projected onto the macro tangent plane (Mikkelsen's "volume gradient" projection with the
bumped normal as the base). It is the default: the most accurate method for a detail that is
unwrapped onto the macro map's UVs, measured in docs/normals.md.

References
----------
C. Barré-Brisebois and S. Hill, "Blending in Detail", 2012,
https://blog.selfshadow.com/publications/blending-in-detail/ (linear, overlay, partial
derivatives, whiteout, UDN, reoriented normal mapping).
M. S. Mikkelsen, "Surface Gradient-Based Bump Mapping Framework", Journal of Computer Graphics
Techniques 9(3), 60-90, 2020, https://jcgt.org/published/0009/03/04/ (surface gradients).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice

#: every blend method, in the order of the docs' tables.
METHODS = ("exact", "rnm", "sg", "pd", "whiteout", "udn", "overlay", "linear")
#: the most accurate method for a detail indexed by the macro map's UVs (docs/normals.md).
DEFAULT_METHOD = "exact"

__all__ = ["METHODS", "DEFAULT_METHOD", "blend"] + [f"blend_{m}" for m in METHODS]


def _check(
    macro: ArrayLike, detail: ArrayLike, strength: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray, type[np.floating]]:
    """Validated (N, 3) float views of the inputs, the strength as (1,) or (N,), the dtype."""
    m, d = np.asarray(macro), np.asarray(detail)
    if m.shape != d.shape or m.ndim < 1 or m.shape[-1] != 3:
        raise ArgumentError(
            "macro and detail must be arrays of 3-vectors of the same shape (..., 3); "
            f"got {m.shape} and {d.shape}"
        )
    dtype = np.float64 if m.dtype == d.dtype == np.float64 else np.float32
    m, d = (a if a.dtype in (np.float32, np.float64) else a.astype(dtype) for a in (m, d))
    s = np.asarray(strength, dtype=dtype)
    if s.ndim == 0:
        s = s.reshape(1)
    else:
        try:
            s = np.ascontiguousarray(np.broadcast_to(s, m.shape[:-1])).reshape(-1)
        except ValueError:
            raise ArgumentError(
                f"strength of shape {s.shape} does not broadcast to the texels {m.shape[:-1]}"
            ) from None
    m = np.ascontiguousarray(m.reshape(-1, 3))
    d = np.ascontiguousarray(d.reshape(-1, 3))
    return m, d, s, dtype


def blend(
    macro: ArrayLike, detail: ArrayLike, *, method: str = DEFAULT_METHOD, strength: ArrayLike = 1.0
) -> np.ndarray:
    """Blend detail normals onto macro normals with the named method (see the module notes).

    Parameters
    ----------
    macro : (..., 3) float array
        Unit normals of the reference surface, OpenGL tangent frame.
    detail : (..., 3) float array
        Unit normals of the detail, same shape, already placed on the macro texels (see
        :mod:`bakeshop.normals.tiling` and :mod:`bakeshop.normals.transfer`).
    method : str
        One of :data:`METHODS`; default :data:`DEFAULT_METHOD`.
    strength : float or (...) array
        Height scale of the detail (0 = no detail); an array acts as a per-texel mask.

    Returns
    -------
    (..., 3) unit normals, float64 if both inputs are float64, else float32. Results without a
    direction (a detail pointing exactly against the surface) become (0, 0, 1).
    """
    validate_choice(method, METHODS, "blend method")
    shape = np.shape(macro)
    m, d, s, dtype = _check(macro, detail, strength)
    out = np.empty(m.shape, dtype)
    from bakeshop.normals import _native  # the formulas' kernel: src/normals/blend.hpp

    _native.blend_texels(METHODS.index(method), m, d, s, out)
    return out.reshape(shape)


def _method_function(name: str, summary: str) -> Callable[..., np.ndarray]:
    def f(macro: ArrayLike, detail: ArrayLike, *, strength: ArrayLike = 1.0) -> np.ndarray:
        return blend(macro, detail, method=name, strength=strength)

    f.__name__ = f.__qualname__ = f"blend_{name}"
    f.__doc__ = (
        f"{summary}\n\n    Same as ``blend(macro, detail, method={name!r}, strength=strength)``; "
        "parameters, shapes and dtypes as for :func:`blend`.\n"
    )
    return f


blend_exact = _method_function(
    "exact",
    "Exact blend for a detail indexed by the macro UVs and displaced along the macro normal:\n"
    "    normalize((z2 - x2 x1 - y2 y1) n1 + (x2, y2, 0)), exact up to the macro curvature "
    "(docs/normals.md).",
)
blend_rnm = _method_function(
    "rnm",
    "Reoriented normal mapping (Barré-Brisebois & Hill 2012): n2 rotated by the rotation that\n"
    "    takes +Z to n1: t = n1 + (0,0,1), u = (-x2, -y2, z2), r = t (t . u) / t_z - u.",
)
blend_sg = _method_function(
    "sg",
    "Surface-gradient blend (Mikkelsen 2020, JCGT 9(3)): the surface gradients of both maps\n"
    "    relative to the vertex normal vN = (0,0,1) are summed and resolved,\n"
    "    normalize(vN - sg1 - sg2) with sg_i = -(x_i, y_i, 0) / z_i. In one shared tangent frame\n"
    "    this equals the partial-derivative blend.",
)
blend_pd = _method_function(
    "pd",
    "Partial-derivative blend: slopes add, normalize(x1 z2 + x2 z1, y1 z2 + y2 z1, z1 z2).\n"
    "    Exact for heights added along the fixed surface normal (Barré-Brisebois & Hill 2012).",
)
blend_whiteout = _method_function(
    "whiteout",
    "Whiteout blend (Barré-Brisebois & Hill 2012): normalize(x1 + x2, y1 + y2, z1 z2).",
)
blend_udn = _method_function(
    "udn",
    "UDN blend (Unreal Developer Network; Barré-Brisebois & Hill 2012):\n"
    "    normalize(x1 + x2, y1 + y2, z1).",
)
blend_overlay = _method_function(
    "overlay",
    "Overlay blend of the packed colours p = (n + 1)/2, as in an image editor: overlay on R and\n"
    "    G (2 a b if a < 0.5 else 1 - 2 (1 - a)(1 - b)), multiply on B, then unpack and normalise.",
)
blend_linear = _method_function(
    "linear",
    "Linear blend, the naive baseline: the detail's offset from flat added to the macro normal,\n"
    "    normalize(n1 + n2 - (0, 0, 1)).",
)
