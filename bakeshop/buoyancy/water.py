"""The water surface: a flat plane or a sum of directional sine waves.

The surface height is ``eta(x, z, t) = level + sum_i A_i sin(k_i . (x, z) - w_i t + phi_i)``
with wave number ``|k_i| = 2 pi / wavelength_i`` along the wave's direction and angular frequency
``w_i = |k_i| c_i``. Without a given speed, ``c_i`` is the deep-water phase speed
``sqrt(g / |k_i|)`` (linear wave theory). The water's own velocity (used by the drag model) is the
linear-theory orbital velocity, decaying as ``exp(|k| (y - eta))`` below the surface.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.buoyancy.hydrostatics import GRAVITY
from bakeshop.errors import ArgumentError


@dataclass(frozen=True)
class Wave:
    """One directional sine wave.

    Attributes
    ----------
    amplitude : float
        Metres (half the crest-to-trough height).
    wavelength : float
        Metres.
    direction : float
        Direction of travel in degrees, measured in the XZ plane from +X towards +Z.
    speed : float or None
        Phase speed in m/s; ``None`` for the deep-water speed ``sqrt(g * wavelength / (2 pi))``.
    phase : float
        Radians.
    """

    amplitude: float
    wavelength: float
    direction: float = 0.0
    speed: float | None = None
    phase: float = 0.0

    def __post_init__(self) -> None:
        values = [self.amplitude, self.wavelength, self.direction, self.phase]
        if self.speed is not None:
            values.append(self.speed)
        if not all(np.isfinite(values)):
            raise ArgumentError(f"wave parameters must be finite: {self}")
        if self.wavelength <= 0 or self.amplitude < 0:
            raise ArgumentError(
                f"a wave needs a positive wavelength and a non-negative amplitude: {self}"
            )
        if self.amplitude * 2 * np.pi / self.wavelength > 1.0:
            raise ArgumentError(
                f"wave steepness k*A = {self.amplitude * 2 * np.pi / self.wavelength:.2f} "
                "exceeds 1 (waves that steep break)"
            )

    @classmethod
    def parse(cls, text: str) -> Wave:
        """Parse ``'AMPLITUDE:WAVELENGTH[:DIRECTION_DEG[:SPEED]]'``, e.g. ``'0.2:8:30'``."""
        try:
            parts = [float(p) for p in text.split(":")]
        except ValueError:
            parts = []
        if not 2 <= len(parts) <= 4:
            raise ArgumentError(
                f"invalid wave {text!r}: expected AMPLITUDE:WAVELENGTH[:DIRECTION_DEG[:SPEED]]"
            )
        return cls(*parts)


@dataclass(frozen=True)
class Water:
    """Still water at ``level`` (metres, +Y up) with optional :class:`Wave` trains on top."""

    level: float = 0.0
    waves: tuple[Wave, ...] = field(default_factory=tuple)
    gravity: float = GRAVITY

    @cached_property
    def table(self) -> np.ndarray:
        """(W, 6) float64 rows ``(amplitude, kx, kz, omega, phase, |k|)`` for the force
        kernels."""
        rows = []
        for w in self.waves:
            k = 2 * np.pi / w.wavelength
            speed = np.sqrt(self.gravity / k) if w.speed is None else w.speed
            angle = np.radians(w.direction)
            rows.append((w.amplitude, k * np.cos(angle), k * np.sin(angle), k * speed, w.phase, k))
        return np.array(rows, dtype=np.float64).reshape(-1, 6)

    def height(self, x: ArrayLike, z: ArrayLike, t: ArrayLike = 0.0) -> np.ndarray:
        """Surface height (m) at horizontal positions ``x``, ``z`` (any matching shapes) and
        time ``t`` (s)."""
        x, z = np.asarray(x, dtype=np.float64), np.asarray(z, dtype=np.float64)
        eta = np.full(np.broadcast(x, z).shape, self.level)
        for a, kx, kz, w, phi, _ in self.table:
            eta = eta + a * np.sin(kx * x + kz * z - w * t + phi)
        return eta
