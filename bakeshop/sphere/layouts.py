"""Panorama layouts: where each texel looks, how much of the sphere it covers, and where a
direction lands.

Every layout answers three questions, and everything spherical in bakeshop (remapping, SH
projection, irradiance, sun detection) is written against them, never against one layout:

- :meth:`Layout.directions`: the unit direction of each texel centre, with a validity mask
  (False outside the disk of the disk layouts and in the unused squares of a cross);
- :meth:`Layout.solid_angles`: the exact solid angle of each texel (0 where invalid); they sum
  to 4*pi over a layout;
- :meth:`Layout.coordinates`: the continuous texel coordinates of directions (texel ``i``'s
  centre is at ``x = i + 0.5``).

The world frame is right-handed, +Y up, -Z forward, +X right (DESIGN.md). Texel ``(i, j)`` is
``(column, row)``, row 0 at the top; ``u = (i + 0.5) / W``, ``v = (j + 0.5) / H`` at its centre.
Sizes: :meth:`Layout.shape` turns a user size (an int, or ``(width, height)``) into the
layout's array shape.
"""

from __future__ import annotations

import functools

import numpy as np

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.sphere import cube as _cube

#: largest accepted edge length of any layout, in texels.
MAX_EDGE = 1 << 16
#: largest accepted number of texels of one layout (a 32768 x 16384 latlong, 6 x 8192^2 cube).
MAX_TEXELS = 1 << 29

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(24)


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _dirs_array(dirs) -> np.ndarray:
    d = np.asarray(dirs, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 3:
        raise ArgumentError(f"directions must be an array of shape (..., 3); got {d.shape}")
    return d


class Layout:
    """A panorama layout. Get one with :func:`layout` (``layout("latlong")``)."""

    #: the layout's name, as given to :func:`layout`.
    name: str = ""
    #: True when the image array has a face axis first (``(6, S, S, C)``).
    cubic = False

    def __repr__(self) -> str:
        return f"layout({self.name!r})"

    # -- shapes --------------------------------------------------------------------------------

    def shape(self, size) -> tuple[int, ...]:
        """The spatial array shape for a user ``size``: an int, or ``(width, height)``."""
        raise NotImplementedError

    def check_shape(self, shape) -> tuple[int, ...]:
        """Return ``shape`` as a tuple of ints if it is a valid array shape of this layout, else
        raise :class:`~bakeshop.errors.ArgumentError`."""
        shape = tuple(int(n) for n in shape)
        self._check(shape)
        if min(shape) < 1 or max(shape) > MAX_EDGE or int(np.prod(shape)) > MAX_TEXELS:
            raise ArgumentError(
                f"{self.name} shape {shape} is out of range (edges 1..{MAX_EDGE}, "
                f"at most {MAX_TEXELS} texels)"
            )
        return shape

    def _check(self, shape) -> None:
        raise NotImplementedError

    def default_size(self, texels: int) -> int:
        """The size (for :meth:`shape`) whose valid texels number about ``texels``."""
        raise NotImplementedError

    # -- the three operations --------------------------------------------------------------------

    def directions(self, shape) -> tuple[np.ndarray, np.ndarray]:
        """Unit directions of the texel centres and the validity mask.

        Parameters
        ----------
        shape : tuple of int
            Spatial array shape, as returned by :meth:`shape`.

        Returns
        -------
        dirs : shape + (3,) float64
            Unit vectors (x, y, z) in the world frame. Invalid texels hold a unit vector too
            (the nearest meaningful one), never NaN.
        valid : shape bool
        """
        raise NotImplementedError

    def directions_at(self, coords, shape) -> np.ndarray:
        """Unit directions at continuous texel coordinates: the inverse of :meth:`coordinates`.

        ``coords`` is ``(..., 2)`` ``(x, y)`` (``(..., 3)`` ``(face, x, y)`` for the cube);
        returns ``(..., 3)`` float64. Points outside a disk give the direction of the disk's
        nearest point; points in the unused squares of a cross give -Z.
        """
        raise NotImplementedError

    def _centres(self, shape):
        h, w = shape[-2:]
        x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        return np.stack([x, y], axis=-1)

    def solid_angles(self, shape) -> np.ndarray:
        """Solid angle of each texel in steradians, float64 ``shape``; 0 where invalid.

        Exact (closed forms, or integrals evaluated to float64 precision); the whole layout
        sums to 4*pi.
        """
        raise NotImplementedError

    def coordinates(self, dirs, shape) -> np.ndarray:
        """Continuous texel coordinates of directions.

        Parameters
        ----------
        dirs : (..., 3) array
            Directions (need not be normalised; a zero vector gives an arbitrary texel).
        shape : tuple of int

        Returns
        -------
        (..., 2) float64
            ``(x, y)``: column and row coordinates, texel ``i``'s centre at ``i + 0.5``, in
            ``[0, W] x [0, H]``. Cube layouts return ``(..., 3)``: ``(face, x, y)``.
        """
        raise NotImplementedError

    # -- sampling support (used by bakeshop.sphere.sampling) -----------------------------------

    def _resolve(self, ix, iy, shape, coords):
        """Flat texel index of integer texel ``(ix, iy)`` (possibly one texel outside the image
        or the disk) used when filtering around the sample point ``coords``."""
        raise NotImplementedError

    def taps(self, coords, shape, filter: str):
        """Flat source texel indices and weights for sampling at continuous ``coords``.

        Returns ``(index, frac)``: nearest: ``index`` (...,) and ``frac`` None; bilinear:
        ``index`` (..., 4) for texels (x0, y0), (x0+1, y0), (x0, y0+1), (x0+1, y0+1) and
        ``frac`` (..., 2) the fractional position (fx, fy) between them. An index of -1 is a
        texel that does not exist (a cube corner): the filter replaces it with the mean of the
        other three, as OpenGL's seamless cube filtering does.
        """
        x, y = coords[..., -2], coords[..., -1]
        if filter == "nearest":
            ix = np.floor(x).astype(np.int64)
            iy = np.floor(y).astype(np.int64)
            return self._resolve(ix, iy, shape, coords), None
        xs, ys = x - 0.5, y - 0.5
        x0, y0 = np.floor(xs), np.floor(ys)
        frac = np.stack([xs - x0, ys - y0], axis=-1)
        x0 = x0.astype(np.int64)
        y0 = y0.astype(np.int64)
        index = np.stack(
            [
                self._resolve(x0, y0, shape, coords),
                self._resolve(x0 + 1, y0, shape, coords),
                self._resolve(x0, y0 + 1, shape, coords),
                self._resolve(x0 + 1, y0 + 1, shape, coords),
            ],
            axis=-1,
        )
        return index, frac

    @property
    def base(self) -> Layout:
        """The layout images of this one are sampled in (the cube for crosses and strips)."""
        return self

    def prepare(self, image) -> np.ndarray:
        """``image`` in :attr:`base` form: the image itself, or the cube of a cross or strip."""
        return image


# --- latitude-longitude ---------------------------------------------------------------------


class LatLong(Layout):
    """Equirectangular: ``phi = 2 pi (u - 0.5)``, ``theta = pi v``,
    ``d = (sin theta sin phi, cos theta, -sin theta cos phi)``; centre column -Z, top row +Y."""

    name = "latlong"

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, 2 * n))

    def _check(self, shape):
        if len(shape) != 2:
            raise ArgumentError(f"a latlong image is (H, W); got spatial shape {shape}")

    def default_size(self, texels):
        return max(1, round(np.sqrt(texels / 2)))

    def directions(self, shape):
        h, w = self.check_shape(shape)
        phi = 2 * np.pi * ((np.arange(w) + 0.5) / w - 0.5)
        theta = np.pi * (np.arange(h) + 0.5) / h
        st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
        d = np.empty((h, w, 3))
        d[..., 0] = st * np.sin(phi)
        d[..., 1] = ct
        d[..., 2] = -st * np.cos(phi)
        return d, np.ones((h, w), bool)

    def directions_at(self, coords, shape):
        h, w = self.check_shape(shape)
        c = np.asarray(coords, dtype=np.float64)
        phi = 2 * np.pi * (c[..., 0] / w - 0.5)
        theta = np.pi * c[..., 1] / h
        st = np.sin(theta)
        return np.stack([st * np.sin(phi), np.cos(theta), -st * np.cos(phi)], axis=-1)

    def solid_angles(self, shape):
        h, w = self.check_shape(shape)
        # exact: the band between theta_j and theta_j+1 covers 2 pi (cos theta_j - cos theta_j+1)
        c = np.cos(np.pi * np.arange(h + 1) / h)
        band = (c[:-1] - c[1:]) * (2 * np.pi / w)
        return np.repeat(band[:, None], w, axis=1)

    def coordinates(self, dirs, shape):
        h, w = self.check_shape(shape)
        d = _dirs_array(dirs)
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        phi = np.arctan2(x, -z)
        theta = np.arctan2(np.hypot(x, z), y)
        return np.stack([(phi / (2 * np.pi) + 0.5) * w, theta / np.pi * h], axis=-1)

    def _resolve(self, ix, iy, shape, coords):
        h, w = shape
        # across a pole, the texel beyond row 0 is row 0 half a turn away
        over = (iy < 0) | (iy >= h)
        ix = np.where(over, ix + w // 2, ix) % w
        iy = np.clip(iy, 0, h - 1)
        return iy * w + ix


# --- disk layouts -----------------------------------------------------------------------------


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

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, self.disks * n))

    def _check(self, shape):
        if len(shape) != 2 or shape[1] != self.disks * shape[0]:
            want = "square" if self.disks == 1 else f"{self.disks}:1 (width:height)"
            raise ArgumentError(f"a {self.name} image must be {want}; got (H, W) = {shape}")

    def default_size(self, texels):
        return max(1, round(np.sqrt(texels / (self.disks * np.pi / 4))))

    def _H(self, q):
        """G(rho) / rho^2 as a function of q = rho^2."""
        raise NotImplementedError

    def _disk_directions(self, a, b, disk):
        raise NotImplementedError

    def _disk_coordinates(self, d):
        """(a, b, disk) of directions."""
        raise NotImplementedError

    def directions(self, shape):
        n, _ = self.check_shape(shape)
        valid = np.concatenate([self._overlap(n)] * self.disks, axis=1)
        return self.directions_at(self._centres(shape), shape), valid

    def directions_at(self, coords, shape):
        n, _ = self.check_shape(shape)
        c = np.asarray(coords, dtype=np.float64)
        disk = np.clip(np.floor(c[..., 0] / n), 0, self.disks - 1)
        a = 2 * (c[..., 0] - disk * n) / n - 1
        b = 1 - 2 * c[..., 1] / n
        # outside the disk (a rim texel's centre): the direction of the disk's nearest point
        r2 = a * a + b * b
        scale = np.where(r2 <= 1, 1, 1 / np.sqrt(np.maximum(r2, 1e-300)))
        return self._disk_directions(a * scale, b * scale, disk)

    def _overlap(self, n):
        """Texels of one disk's square that overlap the open unit disk (the valid ones)."""
        t = np.maximum(np.abs(2 * (np.arange(n) + 0.5) / n - 1) - 1 / n, 0)
        return t[None, :] ** 2 + t[:, None] ** 2 < 1

    def solid_angles(self, shape):
        n, _ = self.check_shape(shape)
        omega = np.where(self._overlap(n), _disk_texel_integrals(n, self), 0.0)
        return np.concatenate([omega] * self.disks, axis=1)

    def coordinates(self, dirs, shape):
        n, _ = self.check_shape(shape)
        d = _unit(_dirs_array(dirs))
        a, b, disk = self._disk_coordinates(d)
        return np.stack([(a + 1) / 2 * n + disk * n, (1 - b) / 2 * n], axis=-1)

    def _resolve(self, ix, iy, shape, coords):
        n = shape[0]
        disk = np.clip(np.floor(coords[..., 0] / n), 0, self.disks - 1).astype(np.int64)
        lx = ix - disk * n
        a = 2 * (lx + 0.5) / n - 1
        b = 1 - 2 * (iy + 0.5) / n
        r = np.hypot(a, b)
        outside = (r > 1) | (lx < 0) | (lx >= n) | (iy < 0) | (iy >= n)
        index = np.clip(iy, 0, n - 1) * shape[1] + np.clip(lx, 0, n - 1) + disk * n
        if np.any(outside):
            # a texel beyond the rim stands for the disk texel that looks where it would look
            a, b, k = a[outside], b[outside], disk[outside]
            d = self._beyond_rim(a, b, k, n)
            c = self.coordinates(d, shape)
            x = np.clip(np.floor(c[..., 0]), 0, shape[1] - 1).astype(np.int64)
            y = np.clip(np.floor(c[..., 1]), 0, n - 1).astype(np.int64)
            index[outside] = y * shape[1] + x
        return index

    def _beyond_rim(self, a, b, disk, n):
        """Direction a texel centre beyond the rim stands for: the formula continued past the rim
        where it continues (angular: theta > pi; paraboloid: the other hemisphere)."""
        return self._disk_directions(a, b, disk)


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
    """Debevec's light probe: ``theta = pi r`` from +Z; centre +Z, rim -Z.

    ``(u, v)`` of a direction: ``(Dx, Dy) acos(Dz) / (pi sqrt(Dx^2 + Dy^2))``. Solid angle
    density ``dOmega/dA = pi sin(pi r) / r``.
    """

    name = "angular"

    def _H(self, q):
        # G(rho) = 1 - cos(pi rho) = (pi^2 / 2) rho^2 sinc(rho / 2)^2
        return (np.pi**2 / 2) * np.sinc(np.sqrt(q) / 2) ** 2

    def _disk_directions(self, a, b, disk):
        r = np.hypot(a, b)
        s = np.pi * np.sinc(r)  # sin(pi r) / r
        return np.stack([a * s, b * s, np.cos(np.pi * r)], axis=-1)

    def _disk_coordinates(self, d):
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        rho = np.hypot(x, y)
        r = np.arctan2(rho, z) / np.pi
        psi = np.arctan2(y, x)
        return r * np.cos(psi), r * np.sin(psi), 0


class MirrorBall(_Disk):
    """A photographed mirror ball: normal ``n = (a, b, sqrt(1 - r^2))``, camera looking along
    -Z, ``d = reflect((0, 0, -1), n)``; centre +Z, rim -Z. ``dOmega/dA = 4`` everywhere."""

    name = "mirrorball"

    def _H(self, q):
        return np.full_like(q, 2.0)

    def _disk_directions(self, a, b, disk):
        r2 = np.minimum(a * a + b * b, 1.0)
        nz = np.sqrt(1 - r2)
        return np.stack([2 * nz * a, 2 * nz * b, 1 - 2 * r2], axis=-1)

    def _beyond_rim(self, a, b, disk, n):
        # the whole rim looks at -Z: stand for the disk texel radially inside instead
        r = np.hypot(a, b)
        pull = max(0.0, 1 - 1.5 / n) / np.maximum(r, 1e-300)
        return self._disk_directions(a * pull, b * pull, disk)

    def _disk_coordinates(self, d):
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        r = np.sqrt(np.clip((1 - z) / 2, 0, 1))
        psi = np.arctan2(y, x)
        return r * np.cos(psi), r * np.sin(psi), 0


class DualParaboloid(_Disk):
    """Two paraboloid maps (Heidrich and Seidel 1998) side by side, ``(N, 2N)``.

    Left disk: the front hemisphere (z <= 0) as seen from inside looking forward (-Z): right is
    +X, up is +Y. Right disk: the back hemisphere (z > 0) looking backward (+Z): right is -X, up
    +Y. In each, with ``f`` the hemisphere's axis and ``(r, t)`` its right and up axes,
    ``(a, b) = (d.r, d.t) / (1 + d.f)``; ``dOmega/dA = 4 / (1 + r^2)^2``.
    """

    name = "dual-paraboloid"
    disks = 2
    g_max = 1.0

    def _H(self, q):
        return 2 / (1 + q)

    def _disk_directions(self, a, b, disk):
        r2 = a * a + b * b
        k = 1 / (1 + r2)
        fwd = (1 - r2) * k
        side = np.where(disk == 0, -1.0, 1.0)
        return np.stack([-side * 2 * a * k, 2 * b * k, side * fwd], axis=-1)

    def _disk_coordinates(self, d):
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        back = z > 0
        right = np.where(back, -x, x)
        f = np.abs(z)
        return right / (1 + f), y / (1 + f), back.astype(np.int64)


# --- octahedral -------------------------------------------------------------------------------


class Octahedral(Layout):
    """Octahedral map (Engelhardt and Dachsbacher 2008), +Y at the centre.

    With ``a = 2u - 1`` (toward +X) and ``c = 2v - 1`` (toward +Z, so the top of the picture
    looks forward, -Z): inside the diamond ``|a| + |c| <= 1`` the octahedron point is
    ``(a, 1 - |a| - |c|, c)``; outside it the lower half is folded out,
    ``(sgn(a) (1 - |c|), 1 - |a| - |c|, sgn(c) (1 - |a|))``; ``d`` is that point normalised. The
    map is piecewise affine onto the octahedron, so each texel is two planar triangles whose
    solid angles are exact (Van Oosterom and Strackee 1983). Sizes must be even (the folds then
    run along texel edges and diagonals).
    """

    name = "octahedral"

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, n))

    def _check(self, shape):
        if len(shape) != 2 or shape[0] != shape[1] or shape[0] % 2:
            raise ArgumentError(
                f"an octahedral image must be square with an even edge; got (H, W) = {shape}"
            )

    def default_size(self, texels):
        return max(2, 2 * round(np.sqrt(texels) / 2))

    @staticmethod
    def _points(a, c):
        aa, ac = np.abs(a), np.abs(c)
        y = 1 - aa - ac
        lower = y < 0
        sa = np.where(a < 0, -1.0, 1.0)
        sc = np.where(c < 0, -1.0, 1.0)
        x = np.where(lower, sa * (1 - ac), a)
        z = np.where(lower, sc * (1 - aa), c)
        return np.stack([x, y, z], axis=-1)

    def directions(self, shape):
        n, _ = self.check_shape(shape)
        return self.directions_at(self._centres(shape), shape), np.ones((n, n), bool)

    def directions_at(self, coords, shape):
        n, _ = self.check_shape(shape)
        c = np.asarray(coords, dtype=np.float64)
        return _unit(self._points(2 * c[..., 0] / n - 1, 2 * c[..., 1] / n - 1))

    def solid_angles(self, shape):
        n, _ = self.check_shape(shape)
        return _octahedral_solid_angles(n)

    def coordinates(self, dirs, shape):
        n, _ = self.check_shape(shape)
        d = _dirs_array(dirs)
        norm1 = np.abs(d).sum(axis=-1)
        p = d / np.where(norm1 > 0, norm1, 1)[..., None]
        x, y, z = p[..., 0], p[..., 1], p[..., 2]
        lower = y < 0
        sx = np.where(x < 0, -1.0, 1.0)
        sz = np.where(z < 0, -1.0, 1.0)
        a = np.where(lower, sx * (1 - np.abs(z)), x)
        c = np.where(lower, sz * (1 - np.abs(x)), z)
        return np.stack([(a + 1) / 2 * n, (c + 1) / 2 * n], axis=-1)

    def _resolve(self, ix, iy, shape, coords):
        n = shape[0]
        out_x = (ix < 0) | (ix >= n)
        out_y = (iy < 0) | (iy >= n)
        cx, cy = np.clip(ix, 0, n - 1), np.clip(iy, 0, n - 1)
        # beyond an edge, the map folds back mirrored; beyond a corner lies the opposite corner
        nx = np.where(out_y, n - 1 - cx, cx)
        ny = np.where(out_x, n - 1 - cy, cy)
        return ny * n + nx


def _triangle_solid_angle(p, q, r):
    """Solid angle of the planar triangle pqr seen from the origin (Van Oosterom and Strackee,
    IEEE Trans. Biomed. Eng. 30 (1983) 125, doi:10.1109/TBME.1983.325207)."""
    lp, lq, lr = (np.linalg.norm(v, axis=-1) for v in (p, q, r))
    det = np.abs(np.einsum("...i,...i", p, np.cross(q, r)))
    den = (
        lp * lq * lr
        + np.einsum("...i,...i", p, q) * lr
        + np.einsum("...i,...i", p, r) * lq
        + np.einsum("...i,...i", q, r) * lp
    )
    return 2 * np.arctan2(det, den)


@functools.lru_cache(maxsize=8)
def _octahedral_solid_angles(n: int) -> np.ndarray:
    e = 2 * np.arange(n + 1) / n - 1
    a0, a1 = e[None, :-1], e[None, 1:]
    c0, c1 = e[:-1, None], e[1:, None]
    pts = {
        k: Octahedral._points(*np.broadcast_arrays(a, c))
        for k, (a, c) in {"00": (a0, c0), "10": (a1, c0), "01": (a0, c1), "11": (a1, c1)}.items()
    }
    # split each texel along the diagonal parallel to its quadrant's fold |a| + |c| = 1
    ac = (a0 + a1) * (c0 + c1) > 0
    anti = _triangle_solid_angle(pts["01"], pts["10"], pts["00"]) + _triangle_solid_angle(
        pts["01"], pts["10"], pts["11"]
    )
    main = _triangle_solid_angle(pts["00"], pts["11"], pts["10"]) + _triangle_solid_angle(
        pts["00"], pts["11"], pts["01"]
    )
    omega = np.where(ac, anti, main)
    omega.setflags(write=False)
    return omega


# --- cube ---------------------------------------------------------------------------------


def _cube_corner(x, y):
    return np.arctan2(x * y, np.sqrt(x * x + y * y + 1))


@functools.lru_cache(maxsize=8)
def _cube_face_solid_angles(s: int) -> np.ndarray:
    # exact: the solid angle of [0,x] x [0,y] on the plane at distance 1 is atan(xy/sqrt(1+x^2+y^2))
    e = 2 * np.arange(s + 1) / s - 1
    x, y = e[None, :], e[:, None]
    c = _cube_corner(x, y)
    omega = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
    omega.setflags(write=False)
    return omega


def _face_directions(s: int) -> np.ndarray:
    t = 2 * (np.arange(s) + 0.5) / s - 1
    sc, tc = t[None, :, None], t[:, None, None]
    b = _cube.FACE_BASES
    d = b[:, None, None, 0] + sc[None] * b[:, None, None, 1] + tc[None] * b[:, None, None, 2]
    return _unit(d)


def cube_face_coordinates(d):
    """(face, sc, tc) of directions ``d`` (..., 3): OpenGL's major-axis rule, sc, tc in [-1, 1]."""
    ad = np.abs(d)
    axis = np.argmax(ad, axis=-1)
    major = np.take_along_axis(d, axis[..., None], axis=-1)[..., 0]
    face = 2 * axis + (major < 0)
    basis = _cube.FACE_BASES[face]
    ma = np.abs(major)
    ma = np.where(ma > 0, ma, 1.0)
    sc = np.einsum("...i,...i", d, basis[..., 1, :]) / ma
    tc = np.einsum("...i,...i", d, basis[..., 2, :]) / ma
    return face, sc, tc


class Cube(Layout):
    """The internal cube map ``(6, S, S)``: OpenGL order and orientation (see
    :mod:`bakeshop.sphere.cube`). Coordinates are ``(face, x, y)``. Texel solid angles are
    exact: ``atan(xy / sqrt(1 + x^2 + y^2))`` differenced over the texel's corners."""

    name = "cube"
    cubic = True

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            if w != h:
                raise ArgumentError(f"cube faces are square; got size {w}x{h}")
            size = w
        n = int(size)
        return self.check_shape((6, n, n))

    def _check(self, shape):
        if len(shape) != 3 or shape[0] != 6 or shape[1] != shape[2]:
            raise ArgumentError(f"a cube map is (6, S, S); got spatial shape {shape}")

    def default_size(self, texels):
        return max(1, round(np.sqrt(texels / 6)))

    def directions(self, shape):
        _, s, _ = self.check_shape(shape)
        return _face_directions(s), np.ones(shape, bool)

    def directions_at(self, coords, shape):
        _, s, _ = self.check_shape(shape)
        c = np.asarray(coords, dtype=np.float64)
        b = _cube.FACE_BASES[np.clip(c[..., 0].astype(np.int64), 0, 5)]
        sc = (2 * c[..., 1] / s - 1)[..., None]
        tc = (2 * c[..., 2] / s - 1)[..., None]
        return _unit(b[..., 0, :] + sc * b[..., 1, :] + tc * b[..., 2, :])

    def solid_angles(self, shape):
        _, s, _ = self.check_shape(shape)
        return np.broadcast_to(_cube_face_solid_angles(s), shape).copy()

    def coordinates(self, dirs, shape):
        _, s, _ = self.check_shape(shape)
        face, sc, tc = cube_face_coordinates(_dirs_array(dirs))
        return np.stack([face, (sc + 1) / 2 * s, (tc + 1) / 2 * s], axis=-1)

    def _resolve(self, ix, iy, shape, coords):
        _, s, _ = shape
        face = coords[..., 0].astype(np.int64)
        out_x = (ix < 0) | (ix >= s)
        out_y = (iy < 0) | (iy >= s)
        index = face * s * s + np.clip(iy, 0, s - 1) * s + np.clip(ix, 0, s - 1)
        edge = out_x ^ out_y
        if np.any(edge):
            # the texel beyond an edge is the neighbour face's texel at its extended position
            f, i, j = face[edge], ix[edge], iy[edge]
            b = _cube.FACE_BASES[f]
            sc = (2 * (i + 0.5) / s - 1)[:, None]
            tc = (2 * (j + 0.5) / s - 1)[:, None]
            g, nsc, ntc = cube_face_coordinates(b[:, 0] + sc * b[:, 1] + tc * b[:, 2])
            ni = np.clip(np.floor((nsc + 1) / 2 * s), 0, s - 1).astype(np.int64)
            nj = np.clip(np.floor((ntc + 1) / 2 * s), 0, s - 1).astype(np.int64)
            index[edge] = g * s * s + nj * s + ni
        # beyond a corner there is no texel: the filter uses the mean of the other three
        return np.where(out_x & out_y, -1, index)


class CubeView(Layout):
    """A cube map drawn as one picture: a cross or a strip (see :data:`bakeshop.sphere.cube.VIEWS`).

    Slot F shows face F of the left-handed (directx) face set, as HDRShop and cmft draw them:
    the picture is the world seen from inside the cube, unmirrored, and the centre of a cross
    looks forward (-Z). Texels of the unused squares of a cross are invalid (solid angle 0).
    """

    cubic = False

    def __init__(self, name: str):
        self.name = name
        self.cols, self.rows, _ = _cube.VIEWS[name]

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            if w * self.rows != h * self.cols:
                raise ArgumentError(
                    f"a {self.name} is {self.cols}:{self.rows} (width:height); got size {w}x{h}"
                )
            size = w // self.cols
        n = int(size)
        return self.check_shape((self.rows * n, self.cols * n))

    def _check(self, shape):
        if (
            len(shape) != 2
            or shape[0] % self.rows
            or shape[1] % self.cols
            or shape[0] // self.rows != shape[1] // self.cols
        ):
            raise ArgumentError(
                f"a {self.name} image is {self.rows} x {self.cols} square faces "
                f"(H = {self.rows} S, W = {self.cols} S); got (H, W) = {shape}"
            )

    def face_size(self, shape) -> int:
        return self.check_shape(shape)[0] // self.rows

    def default_size(self, texels):
        return max(1, round(np.sqrt(texels / 6)))

    def directions(self, shape):
        s = self.face_size(shape)
        d = _cube.cube_to_view(_face_directions(s), self.name)
        valid = _cube.cube_to_view(np.ones((6, s, s), bool), self.name, fill=False)
        d[~valid] = (0.0, 0.0, -1.0)
        return d, valid

    def directions_at(self, coords, shape):
        s = self.face_size(shape)
        c = np.asarray(coords, dtype=np.float64)
        col = np.clip(np.floor(c[..., 0] / s), 0, self.cols - 1).astype(np.int64)
        row = np.clip(np.floor(c[..., 1] / s), 0, self.rows - 1).astype(np.int64)
        # slot (row, col) -> (internal face or -1, flip x, flip y)
        table = np.full((self.rows, self.cols, 3), -1, dtype=np.int64)
        for g, (sc, sr, fx, fy) in enumerate(_cube.view_slots(self.name)):
            table[sr, sc] = (g, fx, fy)
        face, fx, fy = (table[row, col, k] for k in range(3))
        x, y = c[..., 0] - col * s, c[..., 1] - row * s
        x = np.where(fx == 1, s - x, x)
        y = np.where(fy == 1, s - y, y)
        d = CUBE.directions_at(np.stack([np.maximum(face, 0), x, y], axis=-1), (6, s, s))
        return np.where((face < 0)[..., None], np.array([0.0, 0.0, -1.0]), d)

    def solid_angles(self, shape):
        s = self.face_size(shape)
        return _cube.cube_to_view(CUBE.solid_angles((6, s, s)), self.name)

    def coordinates(self, dirs, shape):
        s = self.face_size(shape)
        face, sc, tc = cube_face_coordinates(_dirs_array(dirs))
        x, y = (sc + 1) / 2 * s, (tc + 1) / 2 * s
        slots = np.array(_cube.view_slots(self.name), dtype=np.int64)[face]
        col, row, fx, fy = (slots[..., k] for k in range(4))
        x = np.where(fx == 1, s - x, x) + col * s
        y = np.where(fy == 1, s - y, y) + row * s
        return np.stack([x, y], axis=-1)

    @property
    def base(self):
        return CUBE

    def prepare(self, image):
        return _cube.view_to_cube(image, self.name)


CUBE = Cube()

_LAYOUTS: dict[str, Layout] = {
    lay.name: lay
    for lay in (
        LatLong(),
        Angular(),
        MirrorBall(),
        CUBE,
        Octahedral(),
        DualParaboloid(),
        *(CubeView(v) for v in _cube.VIEWS),
    )
}

#: every layout name :func:`layout` accepts.
LAYOUT_NAMES = tuple(_LAYOUTS)


def layout(name: str) -> Layout:
    """The layout called ``name``: one of :data:`LAYOUT_NAMES`.

    >>> layout("latlong").shape(512)
    (512, 1024)
    """
    if isinstance(name, Layout):
        return name
    validate_choice(name, LAYOUT_NAMES, "layout")
    return _LAYOUTS[name]


def guess_layout(height: int, width: int) -> list[str]:
    """Layouts whose images have this shape, the likely one first.

    A 2:1 image is taken for a latlong (a dual-paraboloid map has the same shape: name it); a
    square is ambiguous (angular, mirror ball or octahedral) and every candidate is returned,
    so that the caller can ask; 3:4, 4:3, 6:1 and 1:6 are the cube's crosses and strips. An
    empty list means no layout has that shape.
    """
    h, w = int(height), int(width)
    if h < 1 or w < 1:
        return []
    if w == 2 * h:
        return ["latlong"]
    if w == h:
        return ["angular", "mirrorball", "octahedral"] if h % 2 == 0 else ["angular", "mirrorball"]
    for name in _cube.VIEWS:
        lay = _LAYOUTS[name]
        if h * lay.cols == w * lay.rows and h % lay.rows == 0:
            return [name]
    return []
