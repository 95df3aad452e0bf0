"""Engine textures from wave fields: normal maps (three- and two-channel), heights, foam,
flipbook atlases, mip chains, previews and the JSON sidecar. Arrays in, arrays out.

Normal maps follow bakeshop's convention (DESIGN, docs/conventions.md): tangent space, +X along
u, +Y along v up the picture ("OpenGL", flip green for DirectX), +Z out; packed values
v = (n + 1) / 2, so an 8-bit texel c decodes as n = 2c/255 - 1. The two-channel variant keeps
(x, y) only: a shader rebuilds z = sqrt(1 - x^2 - y^2), and it is the input that BC5 (RGTC2)
compresses, channel by channel.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.water import _native

#: Foam defaults: foam starts where the Jacobian falls below FOAM_START and is full at FOAM_FULL
#: (J < 0: the surface folds over; Tessendorf 2001, sec. 4.4).
FOAM_START = 0.5
FOAM_FULL = 0.0


def pack_normals(normals: ArrayLike, *, channels: str = "xyz") -> np.ndarray:
    """Unit normals ``(..., 3)`` -> packed texel values (n + 1) / 2 in [0, 1], float32.

    ``channels="xy"`` keeps the first two components only (``(..., 2)``): BC5-ready data whose
    z a shader rebuilds as sqrt(max(0, 1 - x^2 - y^2)).
    """
    n = np.asarray(normals, dtype=np.float32)
    if n.shape[-1] != 3:
        raise ArgumentError(f"normals must end in 3 components, got shape {n.shape}")
    if channels not in ("xyz", "xy"):
        raise ArgumentError(f"channels must be 'xyz' or 'xy', got {channels!r}")
    k = 3 if channels == "xyz" else 2
    return (n[..., :k] + np.float32(1)) * np.float32(0.5)


def unpack_normals(values: ArrayLike, *, channels: str = "xyz") -> np.ndarray:
    """Packed texel values -> unit normals, as a shader decodes them (float64).

    ``channels="xy"`` rebuilds z = sqrt(max(0, 1 - x^2 - y^2)); "xyz" renormalises.
    """
    v = np.asarray(values, dtype=np.float64)
    n = v * 2 - 1
    if channels == "xy":
        z = np.sqrt(np.clip(1 - n[..., 0] ** 2 - n[..., 1] ** 2, 0, None))
        n = np.concatenate([n[..., :2], z[..., None]], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def quantise(values: ArrayLike, bits: int) -> np.ndarray:
    """Values in [0, 1] -> unsigned integers of ``bits`` (8 or 16), round to nearest, clipped;
    what the PNG and container writers store."""
    if bits not in (8, 16):
        raise ArgumentError(f"bits must be 8 or 16, got {bits!r}")
    top = (1 << bits) - 1
    v = np.clip(np.nan_to_num(np.asarray(values, dtype=np.float64)), 0, 1)
    return np.rint(v * top).astype(np.uint8 if bits == 8 else np.uint16)


def angle_between(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """Angle between unit-ish vectors, radians, accurate for tiny angles (atan2 of |a x b| and
    a . b, in float64)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), (a * b).sum(-1))


def foam(jacobian: ArrayLike, *, start: float = FOAM_START, full: float = FOAM_FULL) -> np.ndarray:
    """Instantaneous foam coverage in [0, 1]: 0 where J >= start, 1 where J <= full, linear
    between (float32, shape of ``jacobian``)."""
    if not (math.isfinite(start) and math.isfinite(full) and start > full):
        raise ArgumentError(f"foam start ({start!r}) must be above full ({full!r})")
    j = np.asarray(jacobian, dtype=np.float32)
    return np.clip((np.float32(start) - j) / np.float32(start - full), 0, 1)


def persistent_foam(coverage: ArrayLike, *, frame_time: float, decay: float) -> np.ndarray:
    """Foam that lingers: f(t) = max over s <= t of coverage(s) exp(-(t - s) / decay), made
    exactly periodic.

    For a coverage that repeats with the loop (F frames), the maximum over all the past equals
    the maximum over the last loop (an older frame repeats a newer one with a smaller weight),
    so one warm-up pass over the loop gives the state that the second pass continues: the
    result loops with the animation, frame F being frame 0.

    Parameters
    ----------
    coverage : (F, H, W) float
        Instantaneous foam of every frame of one loop (:func:`foam`).
    frame_time : float
        Seconds between frames (T / F).
    decay : float
        Seconds for lingering foam to fade to 1/e (> 0).
    """
    c = np.asarray(coverage, dtype=np.float32)
    if c.ndim != 3:
        raise ArgumentError(f"coverage must be (F, H, W), got shape {c.shape}")
    if not (math.isfinite(decay) and decay > 0 and math.isfinite(frame_time) and frame_time > 0):
        raise ArgumentError("decay and frame_time must be positive seconds")
    fade = np.float32(math.exp(-frame_time / decay))
    state = np.zeros(c.shape[1:], np.float32)
    for f in range(c.shape[0]):  # warm-up loop
        state = np.maximum(c[f], state * fade)
    out = np.empty_like(c)
    for f in range(c.shape[0]):
        state = np.maximum(c[f], state * fade)
        out[f] = state
    return out


def height_range(height: ArrayLike) -> tuple[float, float]:
    """(low, high), m, of a height stack, for encoding heights in unsigned integers."""
    h = np.asarray(height)
    return float(h.min()), float(h.max())


def encode_heights(height: ArrayLike, low: float, high: float) -> np.ndarray:
    """Heights (m) -> (h - low) / (high - low) in [0, 1]; decode h = low + v (high - low)."""
    if not (high > low):
        raise ArgumentError(f"height range must have high > low, got {low!r}, {high!r}")
    return ((np.asarray(height, dtype=np.float64) - low) / (high - low)).astype(np.float32)


def atlas_shape(frames: int, columns: int | None = None) -> tuple[int, int]:
    """(rows, columns) of a flipbook of ``frames``: ``columns`` given, or the most square
    layout with rows <= columns."""
    if columns is None:
        columns = math.ceil(math.sqrt(frames))
    if not (isinstance(columns, (int, np.integer)) and columns >= 1):
        raise ArgumentError(f"atlas columns must be a positive integer, got {columns!r}")
    return math.ceil(frames / columns), int(columns)


def flipbook(
    frames: ArrayLike, *, columns: int | None = None, gutter: int = 0
) -> tuple[np.ndarray, dict]:
    """Lay frames out in one atlas image, left to right then top to bottom (row-major from
    the top left, the order of Unreal's SubUV and Unity's texture-sheet animation).

    Parameters
    ----------
    frames : (F, N, N[, C])
        Tileable frames.
    columns : int, optional
        Frames per row (default: the most square layout).
    gutter : int
        Texels of wrapped border around each frame (the frame's own opposite edge), so that
        bilinear filtering and small mips at a frame's edge see its tiling neighbour, not the
        next frame.

    Returns
    -------
    atlas : (rows * (N + 2 g), columns * (N + 2 g)[, C])
    layout : dict
        ``rows``, ``columns``, ``cell`` (texels per cell side), ``gutter``, ``frames`` and
        ``inner`` (the frame's own texels in a cell: offset and size).
    """
    a = np.asarray(frames)
    if a.ndim not in (3, 4) or a.shape[1] != a.shape[2]:
        raise ArgumentError(f"frames must be (F, N, N[, C]), got shape {a.shape}")
    count, n = a.shape[0], a.shape[1]
    if not (isinstance(gutter, (int, np.integer)) and 0 <= gutter <= n):
        raise ArgumentError(f"gutter must be 0 to {n} texels, got {gutter!r}")
    rows, cols = atlas_shape(count, columns)
    cell = n + 2 * gutter
    atlas = np.zeros((rows * cell, cols * cell) + a.shape[3:], a.dtype)
    for f in range(count):
        r, c = divmod(f, cols)
        padded = np.pad(a[f], [(gutter, gutter), (gutter, gutter)] + [(0, 0)] * (a.ndim - 3),
                        mode="wrap")  # fmt: skip
        atlas[r * cell : (r + 1) * cell, c * cell : (c + 1) * cell] = padded
    layout = {
        "rows": rows,
        "columns": cols,
        "cell": cell,
        "gutter": int(gutter),
        "frames": count,
        "inner": {"offset": int(gutter), "size": n},
        "order": "row-major from the top left",
    }
    return atlas, layout


def normal_mips(normals: ArrayLike) -> list[np.ndarray]:
    """Mip chain of a tileable normal map ``(..., N, N, 3)`` (N a power of two): each level
    the 2x2 mean of the previous, renormalised; down to 1x1."""
    n = np.asarray(normals, dtype=np.float32)
    side = n.shape[-2]
    if side & (side - 1) or n.shape[-3] != side:
        raise ArgumentError(f"mips need square power-of-two maps, got shape {n.shape}")
    levels = [n]
    while levels[-1].shape[-2] > 1:
        p = levels[-1]
        m = 0.25 * (p[..., 0::2, 0::2, :] + p[..., 1::2, 0::2, :] + p[..., 0::2, 1::2, :]
                    + p[..., 1::2, 1::2, :])  # fmt: skip
        length = np.linalg.norm(m, axis=-1, keepdims=True)
        levels.append(m / np.maximum(length, 1e-12))
    return levels


def box_mips(values: ArrayLike) -> list[np.ndarray]:
    """Mip chain of a tileable map ``(..., N, N[, C])`` by 2x2 means (heights, foam)."""
    v = np.asarray(values, dtype=np.float32)
    squeeze = False
    if v.ndim >= 2 and v.shape[-1] == v.shape[-2] and v.ndim in (2, 3):
        v = v[..., None]
        squeeze = True
    side = v.shape[-2]
    if side & (side - 1):
        raise ArgumentError(f"mips need power-of-two maps, got shape {v.shape}")
    levels = [v]
    while levels[-1].shape[-2] > 1:
        p = levels[-1]
        levels.append(0.25 * (p[..., 0::2, 0::2, :] + p[..., 1::2, 0::2, :]
                              + p[..., 0::2, 1::2, :] + p[..., 1::2, 1::2, :]))  # fmt: skip
    return [level[..., 0] for level in levels] if squeeze else levels


# --- previews ---------------------------------------------------------------------------------


def shade(
    normals: ArrayLike, *, view: ArrayLike = (0.0, -0.8, 0.6), sun: ArrayLike = (0.05, 0.83, 0.55)
) -> np.ndarray:
    """A quick picture of a normal map ``(H, W, 3)`` for previews: the map seen obliquely
    (``view``, towards the eye, tangent frame), fresnel-weighted reflection of a sky that is
    pale at the horizon, a sun's glint, deep water below; linear RGB, about 0 to 1. Slopes
    show, and so would any seam. Not a water shader."""
    n = np.ascontiguousarray(np.asarray(normals, dtype=np.float32))
    if n.ndim != 3 or n.shape[2] != 3:
        raise ArgumentError(f"normals must be (H, W, 3), got shape {n.shape}")
    view = np.asarray(view, dtype=np.float32)
    sun = np.asarray(sun, dtype=np.float32)
    out = np.empty(n.shape, np.float32)
    _native.shade(n, view / np.linalg.norm(view), sun / np.linalg.norm(sun), out)
    return out


def tile(image: ArrayLike, times: int = 2) -> np.ndarray:
    """``image`` repeated ``times`` x ``times`` (the seam check of a tileable texture)."""
    a = np.asarray(image)
    return np.tile(a, (times, times) + (1,) * (a.ndim - 2))


def grid(
    frames: ArrayLike, *, columns: int | None = None, border: int = 2, fill: ArrayLike = 1.0
) -> np.ndarray:
    """Frames side by side in rows with a ``border`` of ``fill`` between them (previews)."""
    a = np.asarray(frames)
    count, h, w = a.shape[:3]
    rows, cols = atlas_shape(count, columns)
    out = np.full(
        (rows * h + (rows + 1) * border, cols * w + (cols + 1) * border) + a.shape[3:],
        fill,
        a.dtype,
    )
    for f in range(count):
        r, c = divmod(f, cols)
        y = border + r * (h + border)
        x = border + c * (w + border)
        out[y : y + h, x : x + w] = a[f]
    return out


def seam_error(field: ArrayLike) -> dict:
    """How the jump across a tiled texture's edges compares with the jumps inside it.

    For each edge (last column -> first column, bottom row -> top row), the largest absolute
    difference of neighbouring texels across the seam, and the largest over the interior in the
    same direction. A seamless texture has seam jumps no larger than its interior ones.
    """
    a = np.asarray(field, dtype=np.float64)
    if a.ndim == 2:
        a = a[..., None]
    inner_x = np.abs(np.diff(a, axis=1)).max()
    inner_y = np.abs(np.diff(a, axis=0)).max()
    return {
        "seam_u": float(np.abs(a[:, 0] - a[:, -1]).max()),
        "inner_u": float(inner_x),
        "seam_v": float(np.abs(a[0] - a[-1]).max()),
        "inner_v": float(inner_y),
    }


def sidecar(
    *,
    kind: str,
    size: float,
    resolution: int,
    loop_period: float | None,
    frames: int,
    files: Sequence[dict],
    parameters: dict,
    report: dict | None = None,
    layout: dict | None = None,
) -> dict:
    """The JSON sidecar describing a water texture set, in SI units.

    ``frame_rate`` (1/s) is frames / loop_period: play the frames at that rate and the loop
    closes; an engine that blends neighbouring frames interpolates between them.
    """
    doc = {
        "generator": "bakeshop water",
        "kind": kind,
        "units": "SI (m, s, rad); normal maps: tangent space, +X along u, +Y along v up "
        "(OpenGL), packed (n + 1) / 2",
        "tile_size_m": size,
        "resolution": resolution,
        "texel_size_m": size / resolution,
        "loop_period_s": loop_period,
        "frames": frames,
        "frame_rate_hz": (frames / loop_period) if loop_period else None,
        "files": list(files),
        "parameters": parameters,
    }
    if report is not None:
        doc["report"] = report
    if layout is not None:
        doc["layout"] = layout
    return doc
