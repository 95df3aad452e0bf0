"""Tangent-space normal maps as files and as arrays of unit vectors.

A decoded normal map is an ``(H, W, 3)`` float array of unit vectors in the OpenGL tangent frame
of bakeshop (docs/conventions.md): +X along u, +Y along v *up* the picture, +Z out of the surface.
Every other function of :mod:`bakeshop.normals` works on such arrays; this module is the only
place that knows about value ranges, the DirectX green channel and two-channel maps.

Encodings
---------
``"packed"``
    The colour encoding of 8- and 16-bit files (and of most float files written by bakers):
    a stored value v in [0, 1] (read as c / (2^n - 1)) decodes to n = 2v - 1, i.e.
    n = 2c/255 - 1 for 8 bits, then the vector is renormalised. Encoding is v = (n + 1) / 2.
``"signed"``
    Float files that store the components themselves, in [-1, 1].

Conventions
-----------
``"gl"`` (Y+, OpenGL, Blender, Unity, glTF) or ``"dx"`` (Y-, DirectX, Unreal, 3ds Max): the two
differ only by the sign of Y, so converting is exact in both directions.

Channels
--------
``"xyz"`` reads R, G, B; ``"xy"`` reads R and G only (BC5 / two-channel maps) and reconstructs
z = sqrt(1 - x^2 - y^2), as a shader does.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice, with_article

CONVENTIONS = ("gl", "dx")
ENCODINGS = ("packed", "signed")
CHANNELS = ("xyz", "xy")

#: a decoded vector whose length differs from 1 by more than this is reported by the check.
#: 8-bit quantisation alone moves the length by at most sqrt(3) / 255 ~ 0.007.
LENGTH_TOLERANCE = 0.1
#: a file is not read as a normal map when more than this fraction of its texels are far from
#: unit length (or, packed, of its samples are outside [0, 1]): an HDR image, a height map.
IMPLAUSIBLE_FRACTION = 0.5
#: texels examined by :func:`implausible` and :func:`guess_convention` (a sample of the map).
SAMPLE_TEXELS = 1 << 20

__all__ = [
    "CONVENTIONS",
    "ENCODINGS",
    "CHANNELS",
    "decode_normals",
    "encode_normals",
    "normalize",
    "convert_convention",
    "convert_normal_map",
    "check_normals",
    "NormalCheck",
    "implausible",
    "guess_convention",
]


def _float(a: ArrayLike) -> np.ndarray:
    a = np.asarray(a)
    return a if a.dtype in (np.float32, np.float64) else a.astype(np.float32)


def _vectors(normals: ArrayLike, what: str = "normals") -> np.ndarray:
    n = _float(normals)
    if n.ndim < 1 or n.shape[-1] != 3:
        raise ArgumentError(f"{what} must be an array of 3-vectors (..., 3); got shape {n.shape}")
    return n


def normalize(normals: ArrayLike) -> np.ndarray:
    """Scale each vector of ``normals`` to unit length.

    Parameters
    ----------
    normals : (..., 3) float array

    Returns
    -------
    (..., 3) array of the same float dtype (float32 for other input). Vectors of zero length
    or with a NaN or infinite component become the flat normal (0, 0, 1): they carry no
    direction, and flat is the neutral element of every blend.
    """
    n = _vectors(normals)
    length = np.sqrt(np.einsum("...i,...i->...", n, n))
    bad = ~(np.isfinite(length) & (length > 0))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = n / length[..., None]
    if bad.any():
        out[bad] = (0.0, 0.0, 1.0)
    return out


def convert_convention(normals: ArrayLike, source: str, target: str) -> np.ndarray:
    """Convert decoded normals between the OpenGL (Y+) and DirectX (Y-) conventions.

    The two differ only in the sign of the Y component, so the conversion is exact and its own
    inverse. ``normals`` (..., 3) is returned as a new array.
    """
    validate_choice(source, CONVENTIONS, "normal-map convention")
    validate_choice(target, CONVENTIONS, "normal-map convention")
    n = np.array(_vectors(normals))
    if source != target:
        n[..., 1] = -n[..., 1]
    return n


def convert_normal_map(
    image: ArrayLike,
    *,
    source: str,
    target: str,
    encoding: str = "packed",
    channels: str = "xyz",
    renormalize: bool = False,
) -> np.ndarray:
    """Convert a stored normal-map image between the OpenGL (Y+) and DirectX (Y-) conventions.

    Three-channel maps without ``renormalize`` change in the Y channel only, exactly: packed
    values v become 1 - v (an 8-bit value c becomes 255 - c), signed ones -v; every other
    channel is copied, so converting twice gives back the same file. With ``renormalize``, or
    for a two-channel map (``channels="xy"``, z rebuilt), the vectors are decoded, renormalised
    and encoded again (:func:`decode_normals`, :func:`encode_normals`); a fourth (alpha)
    channel is kept.

    Parameters
    ----------
    image : (H, W, C) float array
        Stored values, as :func:`bakeshop.io.read_image` returns them.
    source, target : {"gl", "dx"}
        Conventions of ``image`` and of the result.
    encoding : {"packed", "signed"}
    channels : {"xyz", "xy"}
    renormalize : bool

    Returns
    -------
    (H, W, C') float array of stored values: C' = C for the exact flip, else 3 (4 with alpha).
    """
    validate_choice(source, CONVENTIONS, "normal-map convention")
    validate_choice(target, CONVENTIONS, "normal-map convention")
    validate_choice(encoding, ENCODINGS, "normal-map encoding")
    validate_choice(channels, CHANNELS, "normal-map channels")
    a = _float(image)
    if channels == "xy" or renormalize:
        n = decode_normals(a, convention=source, encoding=encoding, channels=channels)
        values = encode_normals(n, convention=target, encoding=encoding)
        if a.shape[2] == 4:
            values = np.concatenate([values, a[:, :, 3:]], axis=2)
        return values
    if a.ndim != 3 or a.shape[2] < 3:
        raise ArgumentError(
            f"a normal map needs at least three channels (a two-channel map: xy); got shape "
            f"{a.shape}"
        )
    values = a.copy()
    if source != target:
        values[:, :, 1] = -values[:, :, 1] if encoding == "signed" else 1 - values[:, :, 1]
    return values


def _raw(image: ArrayLike, encoding: str, channels: str) -> np.ndarray:
    """The stored components as vectors, before any renormalisation (z rebuilt for "xy")."""
    validate_choice(encoding, ENCODINGS, "normal-map encoding")
    validate_choice(channels, CHANNELS, "normal-map channels")
    a = _float(image)
    if a.ndim != 3 or a.shape[2] < (2 if channels == "xy" else 3):
        raise ArgumentError(
            f"{with_article(channels)} normal map needs an (H, W, C) image with at least "
            f"{len(channels)} channels; got shape {a.shape}"
        )
    k = len(channels)
    v = a[:, :, :k] * a.dtype.type(2) - a.dtype.type(1) if encoding == "packed" else a[:, :, :k]
    if channels == "xyz":
        return np.array(v)
    xy2 = np.einsum("...i,...i->...", v, v)
    z = np.sqrt(np.clip(1 - xy2, 0, None))
    return np.concatenate([v, z[..., None]], axis=2)


def decode_normals(
    image: ArrayLike, *, convention: str = "gl", encoding: str = "packed", channels: str = "xyz"
) -> np.ndarray:
    """Decode a normal-map image into unit vectors in the OpenGL tangent frame.

    Parameters
    ----------
    image : (H, W, C) float array
        As :func:`bakeshop.io.read_image` returns it: 8- and 16-bit files scaled to [0, 1].
        Channels beyond those named by ``channels`` (alpha, or B for two-channel maps) are
        ignored.
    convention : {"gl", "dx"}
        The file's convention; DirectX maps have their Y negated here.
    encoding : {"packed", "signed"}
        ``"packed"``: n = 2 v - 1 (n = 2c/255 - 1 for 8-bit samples c); ``"signed"``: n = v.
    channels : {"xyz", "xy"}
        ``"xy"``: two-channel (BC5) map, z = sqrt(max(0, 1 - x^2 - y^2)).

    Returns
    -------
    normals : (H, W, 3) float32 (float64 for float64 input) unit vectors, OpenGL convention.
        Texels without a direction (zero, NaN, Inf) decode to the flat normal (0, 0, 1); use
        :func:`check_normals` to find them.
    """
    validate_choice(convention, CONVENTIONS, "normal-map convention")
    n = normalize(_raw(image, encoding, channels))
    return convert_convention(n, convention, "gl") if convention == "dx" else n


def encode_normals(
    normals: ArrayLike, *, convention: str = "gl", encoding: str = "packed", channels: str = "xyz"
) -> np.ndarray:
    """Encode unit normals (OpenGL frame) as image values; the inverse of :func:`decode_normals`.

    Parameters
    ----------
    normals : (H, W, 3) float array
        Renormalised here (so blends may hand over unnormalised results).
    convention, encoding, channels
        As for :func:`decode_normals`. ``"xy"`` writes z as 0 in the third channel (packed: the
        blue channel is 0.5), as BC5 sources are commonly stored in three-channel files.

    Returns
    -------
    (H, W, 3) float array: packed values in [0, 1], or signed components in [-1, 1].
    """
    validate_choice(encoding, ENCODINGS, "normal-map encoding")
    validate_choice(channels, CHANNELS, "normal-map channels")
    n = normalize(normals)
    if n.ndim != 3:
        raise ArgumentError(f"normals must be (H, W, 3); got shape {n.shape}")
    if convention != "gl":
        n = convert_convention(n, "gl", convention)
    if channels == "xy":
        n[..., 2] = 0
    if encoding == "packed":
        n += 1
        n *= 0.5
    return n


@dataclass
class NormalCheck:
    """What :func:`check_normals` found in a normal map (all counts are texels).

    Attributes
    ----------
    texels : int
        Texels examined.
    off_unit : int
        Stored vectors whose length differs from 1 by more than ``length_tolerance``
        (for two-channel maps: x^2 + y^2 > 1 + tolerance, which leaves no room for z).
    into_surface : int
        Vectors with z < 0: they point into the surface, which a tangent-space normal never
        does (a two-channel map read as three channels shows up here).
    invalid : int
        Texels with a NaN or infinite component.
    min_length, max_length : float
        Range of the stored lengths over the finite texels.
    worst : list of (row, column, length, z)
        Up to 10 flagged texels, farthest from unit length first.
    """

    texels: int
    off_unit: int
    into_surface: int
    invalid: int
    min_length: float
    max_length: float
    length_tolerance: float
    worst: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when no texel was flagged."""
        return self.off_unit == 0 and self.into_surface == 0 and self.invalid == 0


def check_normals(
    image: ArrayLike,
    *,
    encoding: str = "packed",
    channels: str = "xyz",
    length_tolerance: float = LENGTH_TOLERANCE,
) -> NormalCheck:
    """Report texels of a normal-map image that are far from unit length or point inwards.

    Parameters
    ----------
    image : (H, W, C) float array
        Stored values, as :func:`bakeshop.io.read_image` returns them (not yet decoded).
    encoding, channels
        As for :func:`decode_normals`. The convention does not matter: Y's sign changes neither
        length nor z.
    length_tolerance : float
        Allowed | |n| - 1 | of the stored vectors (default :data:`LENGTH_TOLERANCE`).

    Returns
    -------
    NormalCheck
    """
    if not length_tolerance >= 0:
        raise ArgumentError(f"length tolerance must be >= 0; got {length_tolerance}")
    raw = _raw(image, encoding, channels).astype(np.float64)
    finite = np.isfinite(raw).all(axis=2)
    length = np.sqrt(np.einsum("...i,...i->...", raw, raw))
    if channels == "xy":
        xy = np.sqrt(np.einsum("...i,...i->...", raw[..., :2], raw[..., :2]))
        deviation = np.where(xy > 1, xy - 1, 0.0)
    else:
        deviation = np.abs(length - 1)
    off = finite & (deviation > length_tolerance)
    inward = finite & (raw[..., 2] < 0)
    flagged = off | inward | ~finite
    rows, cols = np.nonzero(flagged)
    order = np.argsort(-np.nan_to_num(deviation[rows, cols], nan=np.inf), kind="stable")[:10]
    worst = [
        (
            int(rows[i]),
            int(cols[i]),
            float(length[rows[i], cols[i]]),
            float(raw[rows[i], cols[i], 2]),
        )
        for i in order
    ]
    lengths = length[finite]
    return NormalCheck(
        texels=int(finite.size),
        off_unit=int(off.sum()),
        into_surface=int(inward.sum()),
        invalid=int((~finite).sum()),
        min_length=float(lengths.min()) if lengths.size else float("nan"),
        max_length=float(lengths.max()) if lengths.size else float("nan"),
        length_tolerance=float(length_tolerance),
        worst=worst,
    )


def implausible(image: ArrayLike, *, encoding: str = "packed", channels: str = "xyz") -> str | None:
    """Why the stored values ``image`` cannot be a normal map in ``encoding``, or None.

    Refused: packed samples outside [0, 1] (by more than 0.01) in more than 1% of the samples,
    which no packed file stores, or vectors far from unit length (:func:`check_normals`) in more
    than :data:`IMPLAUSIBLE_FRACTION` of the texels: an HDR image, a height map or the other
    encoding. Judged on an evenly strided sample of at most :data:`SAMPLE_TEXELS` texels.
    """
    a = _float(image)
    step = (
        max(1, math.ceil(math.sqrt(a.shape[0] * a.shape[1] / SAMPLE_TEXELS))) if a.ndim == 3 else 1
    )
    sample = a[::step, ::step] if a.ndim == 3 else a
    k = len(channels)
    if encoding == "packed":
        stored = sample[..., :k]
        outside = float(np.mean((stored < -0.01) | (stored > 1.01)))
        if outside > 0.01:
            return (
                f"{outside:.0%} of its values are outside [0, 1], where a packed normal map "
                "stores them (an HDR image? --encoding signed reads [-1, 1])"
            )
    report = check_normals(sample, encoding=encoding, channels=channels)
    if report.off_unit + report.invalid > IMPLAUSIBLE_FRACTION * report.texels:
        other = "signed" if encoding == "packed" else "packed"
        share = (report.off_unit + report.invalid) / report.texels
        return (
            f"{share:.0%} of its vectors are far from unit length (an image or a height map? "
            f"or --encoding {other})"
        )
    return None


def guess_convention(normals: ArrayLike) -> tuple[str | None, float]:
    """Guess the green convention of decoded normals from the surface they describe.

    The slopes g = (-x/z, -y/z) of a normal map are the gradient of its height field h, so
    their curl dg_x/dv - dg_y/du vanishes. Read with the wrong green sign, g_y changes sign
    and the curl becomes dg_x/dv + dg_y/du, which does not vanish unless h is separable. With
    R+ and R- the two residuals (per texel, rows downward), the share
    f = |R+|^2 / (|R+|^2 + |R-|^2) is ~0 for normals decoded with their own convention and ~1
    for normals decoded with the other one.

    Parameters
    ----------
    normals : (H, W, 3) float array
        Unit normals as decoded (OpenGL frame), of a central crop of at most
        :data:`SAMPLE_TEXELS` texels.

    Returns
    -------
    (guess, share)
        ``"gl"`` when the normals look decoded with their own convention, ``"dx"`` when their
        green channel looks flipped, None when the map cannot tell (flat, separable, noise);
        ``share`` is f above.
    """
    n = np.asarray(normals, dtype=np.float64)
    side = int(math.sqrt(SAMPLE_TEXELS))
    h, w = n.shape[:2]
    top, left = max(0, (h - side) // 2), max(0, (w - side) // 2)
    n = n[top : top + side, left : left + side]
    if min(n.shape[:2]) < 3:
        return None, 0.5
    z = np.maximum(n[..., 2], 0.05)
    gx, gy = -n[..., 0] / z, -n[..., 1] / z  # slopes along u (columns) and v (up the rows)
    dgx_dr = np.diff(gx, axis=0)[:, :-1]
    dgy_dc = np.diff(gy, axis=1)[:-1, :]
    # dgx/dv = -dgx/dr: the GL residual dgx/dv - dgy/du is -(dgx_dr + dgy_dc)
    same, flipped = np.mean((dgx_dr + dgy_dc) ** 2), np.mean((dgx_dr - dgy_dc) ** 2)
    total = same + flipped
    # 8-bit quantisation adds curl to both alike; a separable relief has none in either
    if not total > 1e-8:
        return None, 0.5
    share = float(same / total)
    if abs(share - 0.5) < 0.25:
        return None, share
    return ("gl" if share < 0.5 else "dx"), share


@overload
def read_normal_map(
    path: str | os.PathLike,
    *,
    convention: str = ...,
    encoding: str = ...,
    channels: str = ...,
    with_bits: Literal[False] = ...,
) -> np.ndarray: ...
@overload
def read_normal_map(
    path: str | os.PathLike,
    *,
    convention: str = ...,
    encoding: str = ...,
    channels: str = ...,
    with_bits: Literal[True],
) -> tuple[np.ndarray, int | None]: ...
def read_normal_map(
    path: str | os.PathLike,
    *,
    convention: str = "gl",
    encoding: str = "packed",
    channels: str = "xyz",
    with_bits: bool = False,
) -> np.ndarray | tuple[np.ndarray, int | None]:
    """A normal-map file as ``(H, W, 3)`` float32 unit vectors in the OpenGL frame
    (:func:`decode_normals` of :func:`bakeshop.io.read_image`); with
    ``with_bits`` also the file's sample depth (8, 16, or None for floats). A file that cannot
    be a normal map (:func:`implausible`: an HDR image, a height map) is refused."""
    from bakeshop.io import read_image, stored_bits

    image, meta = read_image(path, with_metadata=True)
    problem = implausible(image, encoding=encoding, channels=channels)
    if problem is not None:
        raise ArgumentError(f"not a normal map: {problem}", path)
    try:
        normals = decode_normals(image, convention=convention, encoding=encoding, channels=channels)
    except ArgumentError as e:
        raise ArgumentError(e.reason, path) from None
    return (normals, stored_bits(meta)) if with_bits else normals
