"""Gerstner wave sums on the patch lattice: the same waves as the FFT, summed directly.

Each lattice mode of an :class:`~bakeshop.water.ocean.Ocean` is a travelling wave
h = A cos(theta), theta = k . x - w t + phi, with A = 2 |h0(k)| and phi = arg h0(k). With the
ocean's choppy displacement D = sum i (k / |k|) h_hat, every wave moves the surface point
horizontally by -l A k_hat sin(theta): the sum of all modes *is* a sum of Gerstner (trochoidal)
waves (GPU Gems ch. 1, eq. 9, with steepness Q = l for every wave). Summed directly, a few
dozen of the strongest waves are cheap to evaluate anywhere (a vertex shader's sum, a probe for
buoyancy) and they tile and loop exactly as the FFT field does, because their wave vectors and
frequencies are the lattice's.

The surface and its exact normal (the cross product of the analytic tangents):

    P(x, t)  = (x - l sum A kx_hat sin(theta), y - l sum A ky_hat sin(theta), sum A cos(theta))
    dP/dx    = (1 - l sum A kx_hat kx cos, -l sum A ky_hat kx cos, -sum A kx sin)
    dP/dy    = (-l sum A kx_hat ky cos, 1 - l sum A ky_hat ky cos, -sum A ky sin)
    n        = dP/dx x dP/dy / |.|

(GPU Gems' eq. 12 drops the cross terms of this product, which is exact for one wave only.)

References
----------
M. Finch, "Effective Water Simulation from Physical Models", GPU Gems, ch. 1, 2004.
F. J. Gerstner, "Theorie der Wellen", Abhandlungen der Koeniglichen Boehmischen Gesellschaft der
Wissenschaften, 1802.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.water import _native
from bakeshop.water.ocean import FIELDS, FOLD_FLOOR, Ocean


@dataclass(frozen=True)
class GerstnerWaves:
    """A set of travelling waves (all arrays (M,), SI units).

    Attributes
    ----------
    amplitude : m.  kx, ky : rad/m.  omega : rad/s.  phase : rad (at t = 0, x = 0).
    cycles : int turns per loop, or None.  size : patch side, m.  loop_period : s or None.
    """

    amplitude: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    omega: np.ndarray
    phase: np.ndarray
    cycles: np.ndarray | None
    size: float
    loop_period: float | None

    @property
    def count(self) -> int:
        """Number of waves."""
        return int(self.amplitude.size)


def gerstner_waves(o: Ocean, count: int | None = None) -> GerstnerWaves:
    """The ``count`` strongest waves of ``o`` (all of them by default), as Gerstner waves.

    The variance they keep is sum A^2 / 2; compare with ``o.report["variance"]``.
    """
    # undo the texel-centre phase: phases are relative to the world origin
    h0 = o.amplitude * np.exp(-0.5j * (o.kx - o.ky) * o.texel)
    live = np.flatnonzero(h0 != 0)
    if count is not None:
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
            raise ArgumentError(f"wave count must be a positive integer, got {count!r}")
        order = np.argsort(-np.abs(h0.flat[live]), kind="stable")
        live = live[order[: int(count)]]
    a = h0.flat[live]
    return GerstnerWaves(
        amplitude=2 * np.abs(a),
        kx=o.kx.flat[live].copy(),
        ky=o.ky.flat[live].copy(),
        omega=o.omega.flat[live].copy(),
        phase=np.angle(a),
        cycles=None if o.cycles is None else o.cycles.flat[live].copy(),
        size=o.size,
        loop_period=o.loop_period,
    )


def _phases(w: GerstnerWaves, t: float, frame: int | None, frames: int | None) -> np.ndarray:
    if frame is not None:
        # a frame index comes with a looping ocean and its frame count
        assert frames is not None and w.cycles is not None
        turns = (w.cycles * (frame % frames)) % frames / frames
        return w.phase - 2 * math.pi * turns
    return w.phase - np.mod(w.omega * t, 2 * math.pi)


def gerstner(
    w: GerstnerWaves,
    x: ArrayLike,
    y: ArrayLike,
    t: float = 0.0,
    *,
    choppiness: float = 0.0,
    frame: int | None = None,
    frames: int | None = None,
) -> dict[str, np.ndarray]:
    """Evaluate the waves at points (x, y), m, at time ``t`` (s), float64.

    ``frame`` and ``frames`` instead of ``t`` put the time on the loop's frame grid exactly
    (t = frame T / frames, phases from integer turns, as the FFT frames are).

    Returns
    -------
    dict with ``position`` (..., 3) (the displaced point: x, y in the plane, height last),
    ``height`` (...), ``slope`` (..., 2), ``displacement`` (..., 2), ``jacobian`` (...) and
    ``normal`` (..., 3), the exact unit normal dP/dx x dP/dy.
    """
    lam = float(choppiness)
    if not (math.isfinite(lam) and lam >= 0):
        raise ArgumentError(f"choppiness must be a finite number >= 0, got {choppiness!r}")
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    shape = np.broadcast(x, y).shape
    xs = np.ascontiguousarray(np.broadcast_to(x, shape)).ravel()
    ys = np.ascontiguousarray(np.broadcast_to(y, shape)).ravel()
    if frame is not None and (w.cycles is None or frames is None):
        raise ArgumentError("frame= needs looping waves and frames=")
    sums = np.empty((xs.size, 8))
    _native.gerstner_sums(w.amplitude, w.kx, w.ky, _phases(w, t, frame, frames), xs, ys, sums)
    return _assemble(sums, xs, ys, lam, shape)


def _assemble(
    sums: np.ndarray, xs: np.ndarray, ys: np.ndarray, lam: float, shape: tuple[int, ...]
) -> dict[str, np.ndarray]:
    h, hx, hy, dx, dy, dxx, dyy, dxy = sums.T
    tx = np.stack([1 + lam * dxx, lam * dxy, hx], -1)
    ty = np.stack([lam * dxy, 1 + lam * dyy, hy], -1)
    n = np.cross(tx, ty)
    n[:, 2] = np.maximum(n[:, 2], FOLD_FLOOR)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return {
        "position": np.stack([xs + lam * dx, ys + lam * dy, h], -1).reshape(shape + (3,)),
        "height": h.reshape(shape),
        "slope": np.stack([hx, hy], -1).reshape(shape + (2,)),
        "displacement": (lam * np.stack([dx, dy], -1)).reshape(shape + (2,)),
        "jacobian": ((1 + lam * dxx) * (1 + lam * dyy) - (lam * dxy) ** 2).reshape(shape),
        "normal": n.reshape(shape + (3,)),
    }


def gerstner_frames(
    w: GerstnerWaves,
    *,
    resolution: int,
    frames: int | None = None,
    times: ArrayLike | None = None,
    fields: Sequence[str] = ("normal",),
    choppiness: float = 0.0,
) -> Iterator[tuple[np.ndarray, dict[str, np.ndarray]]]:
    """Frames of the direct sum on the patch's texel centres, one frame per batch, in the
    format of :func:`bakeshop.water.ocean.ocean_frames` (float32 fields).

    Costs O(N^2 M) per frame against the FFT's O(N^2 log N): worth it for M up to a few
    dozen waves, or to evaluate off the grid.
    """
    for name in fields:
        validate_choice(name, tuple(FIELDS), "ocean field")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)):
        raise ArgumentError(f"resolution must be an integer, got {resolution!r}")
    if resolution < 1:
        raise ArgumentError(f"resolution must be positive, got {resolution}")
    if (frames is None) == (times is None):
        raise ArgumentError("give either frames= (looping waves) or times=")
    if frames is not None and w.cycles is None:
        raise ArgumentError("frames= needs looping waves; pass times= instead")
    n = int(resolution)
    texel = w.size / n
    c = (np.arange(n) + 0.5) * texel
    x, y = np.meshgrid(c, w.size - c)
    stamps = np.ravel(times if times is not None else ())
    count = frames if frames is not None else len(stamps)
    for f in range(count):
        if frames is not None:
            r = gerstner(w, x, y, choppiness=choppiness, frame=f, frames=frames)
        else:
            r = gerstner(w, x, y, float(stamps[f]), choppiness=choppiness)
        yield np.array([f]), {name: r[name][None].astype(np.float32) for name in fields}
