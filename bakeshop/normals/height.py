"""Height map -> tangent-space normal map.

For a height field h(x, y) in texels, the surface (x, y, s h) has the normal
n = normalize(-s dh/dx, -s dh/dy_up, 1), with x along the columns and y_up *up* the picture
(against the rows), s the strength. The derivatives are central differences,
dh/dx ~ (h[x+1] - h[x-1]) / 2, or the Sobel operator, the central difference smoothed across by
(1, 2, 1) / 4 (less noise, slightly blurred). A tileable height map wraps around its edges; any
other map is clamped (its border texels repeat).

Reference: I. Sobel and G. Feldman, "A 3x3 isotropic gradient operator for image processing",
1968 (in R. Duda and P. Hart, Pattern Classification and Scene Analysis, 1973, pp. 271-272).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.normals.encoding import CONVENTIONS, convert_convention, normalize

DERIVATIVES = ("central", "sobel")

__all__ = ["DERIVATIVES", "height_to_normal"]


def height_to_normal(
    height: ArrayLike,
    *,
    strength: float = 1.0,
    derivative: str = "central",
    convention: str = "gl",
    wrap: bool = True,
) -> np.ndarray:
    """Normal map of a height map.

    Parameters
    ----------
    height : (H, W) or (H, W, 1) float array
        Heights; a multi-channel image is refused (pick its channel first).
    strength : float
        s: the height, in texels, of one unit of ``height`` (for a [0, 1] 8-bit height map,
        the depth of its full range in texels). Negative values invert the relief.
    derivative : {"central", "sobel"}
    convention : {"gl", "dx"}
        Convention of the returned vectors (DirectX negates Y).
    wrap : bool
        True for tileable maps (differences wrap around the edges), False to clamp.

    Returns
    -------
    (H, W, 3) float32 unit normals (float64 for float64 input).
    """
    validate_choice(derivative, DERIVATIVES, "derivative")
    validate_choice(convention, CONVENTIONS, "normal-map convention")
    h = np.asarray(height)
    if h.ndim == 3 and h.shape[2] == 1:
        h = h[:, :, 0]
    if h.ndim != 2 or min(h.shape) < 1:
        raise ArgumentError(
            f"a height map must be (H, W) or (H, W, 1); got shape {np.shape(height)}"
        )
    if not np.isfinite(strength):
        raise ArgumentError(f"strength must be finite; got {strength}")
    dtype = np.float64 if h.dtype == np.float64 else np.float32
    h = np.nan_to_num(h.astype(dtype, copy=False))
    mode = "wrap" if wrap else "nearest"
    central = np.array([-0.5, 0.0, 0.5], dtype)
    smooth = np.array([0.25, 0.5, 0.25], dtype)

    def derivative_along(axis: int) -> np.ndarray:
        d = ndimage.correlate1d(h, central, axis=axis, mode=mode)
        if derivative == "sobel":
            d = ndimage.correlate1d(d, smooth, axis=1 - axis, mode=mode)
        return d

    n = np.empty(h.shape + (3,), dtype)
    n[..., 0] = -strength * derivative_along(1)
    n[..., 1] = strength * derivative_along(0)  # rows grow downwards: dh/dy_up = -dh/drow
    n[..., 2] = 1
    n = normalize(n)
    return convert_convention(n, "gl", convention) if convention == "dx" else n
