"""Disk layouts: Debevec's angular map and the mirror ball (as HDRShop reads them and as
photographed) and the dual paraboloid."""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

from bakeshop.errors import ArgumentError, with_article
from bakeshop.sphere import _kinds
from bakeshop.sphere.layouts.base import (
    _GAUSS_W,
    _GAUSS_X,
    Layout,
)


class _Disk(Layout):
    """Layouts made of unit disks side by side, each in an N x N square, with a radial density.

    A texel is valid when it overlaps the disk; a rim texel whose centre lies outside the disk
    takes the direction of the disk point nearest to its centre, and its solid angle is that of
    its part inside the disk, so the valid texels cover the sphere exactly (4 pi).

    ``(a, b) = (2u' - 1, 1 - 2v')`` in a disk's own square (b up). The texel solid angle is the
    integral of the density ``dOmega/dA = g(r)`` over the texel square clipped to the disk,
    written as the cumulative ``G(rho) = int_0^rho g(r) r dr = rho^2 H(rho^2)``, exact to float64
    through 24-point Gauss-Legendre rules of analytic integrands.
    """

    disks = 1
    #: G(1): the disk's solid angle over 2 pi.
    g_max = 2.0

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, self.disks * n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 2 or shape[1] != self.disks * shape[0]:
            want = "square" if self.disks == 1 else f"{self.disks}:1 (width:height)"
            raise ArgumentError(
                f"{with_article(self.name)} image must be {want}; got (H, W) = {shape}"
            )

    def default_size(self, texels: int) -> int:
        return max(1, round(np.sqrt(texels / (self.disks * np.pi / 4))))

    def _H(self, q: np.ndarray) -> np.ndarray:
        """G(rho) / rho^2 as a function of q = rho^2."""
        raise NotImplementedError

    def _overlap(self, n: int) -> np.ndarray:
        """Texels of one disk's square that overlap the open unit disk (the valid ones)."""
        t = np.maximum(np.abs(2 * (np.arange(n) + 0.5) / n - 1) - 1 / n, 0)
        return t[None, :] ** 2 + t[:, None] ** 2 < 1 - _kinds.DISK_OVERLAP_EPS

    def _valid(self, shape: tuple[int, ...]) -> np.ndarray:
        return np.concatenate([self._overlap(shape[0])] * self.disks, axis=1)

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        n, _ = self.check_shape(shape)
        omega = np.where(self._overlap(n), _disk_texel_integrals(n, self), 0.0)
        return np.concatenate([omega] * self.disks, axis=1)


@functools.lru_cache(maxsize=16)
def _disk_texel_integrals(n: int, lay: _Disk) -> np.ndarray:
    """Exact solid angles of the n x n texels of one disk (read-only, cached)."""
    # corner integral C(x, y) = integral of the density over [0, x] x [0, y]; by symmetry it is
    # needed only at |corner coordinates|, and C(x, y) = F(x, y) + F(y, x) where F integrates
    # the triangle (0,0), (x,0), (x,y) in polar form: with s = x tan(phi),
    # F = x int_0^S H(x^2 + s^2) ds + G(1) (atan2(y, x) - atan2(S, x)), S = min(y, sqrt(1-x^2))
    t = np.abs(2 * np.arange(n + 1) / n - 1)
    q = np.unique(t)
    x, y = q[:, None], q[None, :]
    s_in = np.minimum(y, np.sqrt(np.maximum(0.0, 1 - x * x)))
    nodes = (_GAUSS_X + 1) / 2
    integral = np.zeros(np.broadcast_shapes(x.shape, y.shape))
    for node, weight in zip(nodes, _GAUSS_W / 2, strict=True):
        s = s_in * node
        integral += weight * lay._H(x * x + s * s)
    f = x * s_in * integral + lay.g_max * (np.arctan2(y, x) - np.arctan2(s_in, x))
    c_abs = f + f.T
    pos = np.searchsorted(q, t)
    edges = 2 * np.arange(n + 1) / n - 1
    sign = np.sign(edges)
    # signed corner integral over [0, x] x [0, y] on the (a, b) grid (b = -row coordinate)
    c = c_abs[np.ix_(pos, pos)] * sign[:, None] * sign[None, :]
    # texel (row j, col i): a in [e_i, e_i+1], row coordinate in [e_j, e_j+1]
    omega = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
    omega = np.abs(omega)
    omega.setflags(write=False)
    return omega


class Angular(_Disk):
    """Debevec's light probe as HDRShop reads it: ``theta = pi r`` from the centre, which looks
    forward (-Z); the rim looks behind (+Z), right of centre is +X, above is +Y.

    ``d = (a/r sin theta, b/r sin theta, -cos theta)``. In HDRShop's own left-handed frame (z
    forward, our ``(x, y, -z)``) this is Debevec's ``(u, v) = (Dx, Dy) acos(Dz) / (pi sqrt(Dx^2 +
    Dy^2))``, so Debevec's probes and HDRShop's conversions of them (the crosses of his gallery)
    agree with bakeshop's. Solid angle density ``dOmega/dA = pi sin(pi r) / r``.
    """

    name = "angular"
    kind = _kinds.ANGULAR

    def _H(self, q: np.ndarray) -> np.ndarray:
        # G(rho) = 1 - cos(pi rho) = (pi^2 / 2) rho^2 sinc(rho / 2)^2
        return (np.pi**2 / 2) * np.sinc(np.sqrt(q) / 2) ** 2


class AngularPhysical(Angular):
    """The angular map of a mirror ball's physical reflection: a camera looking along -Z sees
    behind itself (+Z) at the centre, so ``d = (a/r sin theta, b/r sin theta, +cos theta)``:
    the z-mirror image of :class:`Angular` (HDRShop's), for matching a photographed set."""

    name = "angular-physical"
    kind = _kinds.ANGULAR_PHYSICAL


class MirrorBall(_Disk):
    """A mirror ball as HDRShop reads it: the same centre and axes as :class:`Angular` (centre
    forward, -Z; right +X; up +Y), with ``r = sin(theta / 2)`` for the angle ``theta`` from the
    centre (a ball seen from far away), so ``r = sin(45 deg)`` right of centre is +X:
    ``d = (2 n_z a, 2 n_z b, -(1 - 2 r^2))``, ``n_z = sqrt(1 - r^2)``. ``dOmega/dA = 4``."""

    name = "mirrorball"
    kind = _kinds.MIRRORBALL

    def _H(self, q: np.ndarray) -> np.ndarray:
        return np.full_like(q, 2.0)


class MirrorBallPhysical(MirrorBall):
    """A photographed mirror ball's exact reflection: normal ``n = (a, b, sqrt(1 - r^2))``,
    camera looking along -Z, ``d = reflect((0, 0, -1), n) = (2 n_z a, 2 n_z b, 1 - 2 r^2)``;
    centre +Z (behind the camera), rim -Z. The z-mirror image of :class:`MirrorBall`."""

    name = "mirrorball-physical"
    kind = _kinds.MIRRORBALL_PHYSICAL


class DualParaboloid(_Disk):
    """Two paraboloid maps (Heidrich and Seidel 1998) side by side, ``(N, 2N)``.

    Left disk: the front hemisphere (z <= 0) as seen from inside looking forward (-Z): right is
    +X, up is +Y. Right disk: the back hemisphere (z > 0) looking backward (+Z): right is -X, up
    +Y. In each, with ``f`` the hemisphere's axis and ``(r, t)`` its right and up axes,
    ``(a, b) = (d.r, d.t) / (1 + d.f)``; ``dOmega/dA = 4 / (1 + r^2)^2``.
    """

    name = "dual-paraboloid"
    kind = _kinds.DUAL_PARABOLOID
    disks = 2
    g_max = 1.0

    def _H(self, q: np.ndarray) -> np.ndarray:
        return 2 / (1 + q)
