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

import numba
import numpy as np

from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.sphere import _maps
from bakeshop.sphere import cube as _cube

#: largest accepted edge length of any layout, in texels.
MAX_EDGE = 1 << 16
#: largest accepted number of texels of one layout (a 32768 x 16384 latlong, 6 x 8192^2 cube).
MAX_TEXELS = 1 << 29

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(24)


def _dirs_array(dirs) -> np.ndarray:
    d = np.asarray(dirs, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 3:
        raise ArgumentError(f"directions must be an array of shape (..., 3); got {d.shape}")
    return d


def power_of_two_edge(area: float) -> int:
    """The power of two nearest (in log scale) to ``sqrt(area)``: the default edge of cube faces,
    so that a cube's texels number about ``6 * area`` and every mip level halves exactly
    (296 texels becomes 256, 326 becomes 256, 400 becomes 512)."""
    edge = float(np.sqrt(max(float(area), 1.0)))
    return int(2 ** round(np.log2(edge)))


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
        """The size (for :meth:`shape`) whose valid texels number about ``texels`` (for cubes,
        crosses and strips: the nearest power-of-two face edge, :func:`power_of_two_edge`)."""
        raise NotImplementedError

    # -- the three operations --------------------------------------------------------------------

    #: kind number of the layout in the scalar maps (:mod:`bakeshop.sphere.kernels`).
    kind = -1

    def grid(self, shape) -> tuple[int, int, int]:
        """``(h, w, faces)`` of a spatial shape, as the scalar maps take them
        (:mod:`bakeshop.sphere.kernels`): a flat layout's ``(H, W, 1)``, the cube's
        ``(S, S, 6)``."""
        h, w = self.check_shape(shape)
        return h, w, 1

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
        shape = self.check_shape(shape)
        return self.directions_at(self._centres(shape), shape), self._valid(shape)

    def _valid(self, shape) -> np.ndarray:
        return np.ones(shape, bool)

    def directions_at(self, coords, shape) -> np.ndarray:
        """Unit directions at continuous texel coordinates: the inverse of :meth:`coordinates`.

        ``coords`` is ``(..., 2)`` ``(x, y)`` (``(..., 3)`` ``(face, x, y)`` for the cube);
        returns ``(..., 3)`` float64. Points outside a disk give the direction of the disk's
        nearest point.
        """
        h, w, _ = self.grid(shape)
        c = np.asarray(coords, dtype=np.float64)
        if c.shape[-1] != (3 if self.cubic else 2):
            raise ArgumentError(f"{self.name} coordinates must be (..., {3 if self.cubic else 2})")
        flat = c.reshape(-1, c.shape[-1])
        if not self.cubic:
            flat = np.concatenate([np.zeros((len(flat), 1)), flat], axis=1)
        out = np.empty((len(flat), 3))
        _maps.directions_at(self.kind, h, w, np.ascontiguousarray(flat), out)
        return out.reshape(c.shape[:-1] + (3,))

    def _centres(self, shape):
        h, w = shape[-2:]
        x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        c = np.stack([x, y], axis=-1)
        if self.cubic:
            f = np.broadcast_to(np.arange(6.0)[:, None, None, None], (6, h, w, 1))
            c = np.concatenate([f, np.broadcast_to(c, (6, h, w, 2))], axis=-1)
        return c

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
        h, w, _ = self.grid(shape)
        d = _dirs_array(dirs)
        out = np.empty((d.size // 3, 3))
        _maps.coordinates_of(self.kind, h, w, np.ascontiguousarray(d.reshape(-1, 3)), out)
        out = out.reshape(d.shape[:-1] + (3,))
        return out if self.cubic else out[..., 1:]

    # -- cube views ----------------------------------------------------------------------------

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
    ``d = (sin theta sin phi, cos theta, -sin theta cos phi)``; centre column -Z, top row +Y.

    Any (H, W) is accepted (2:1 is usual). Filtering across a pole uses the texel half a turn
    away in the same row, exact for even widths (odd widths round it to the nearest column).
    """

    name = "latlong"
    kind = _maps.LATLONG

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
        # separable: W + H sines and cosines, then products (docs/BENCHMARKS.md, irradiance;
        # bit-identical to the general path: the same trigonometry as remap's plans)
        shape = self.check_shape(shape)
        dirs = np.empty(shape + (3,))
        _latlong_directions(dirs)
        return dirs, self._valid(shape)

    def solid_angles(self, shape):
        h, w = self.check_shape(shape)
        # exact: the band between theta_j and theta_j+1 covers 2 pi (cos theta_j - cos theta_j+1)
        c = np.cos(np.pi * np.arange(h + 1) / h)
        band = (c[:-1] - c[1:]) * (2 * np.pi / w)
        return np.repeat(band[:, None], w, axis=1)


@numba.njit(parallel=True, cache=True)
def _latlong_directions(out):
    """Fill ``out`` (H, W, 3) with the latlong texel-centre directions
    ``(sin theta_j sin phi_i, cos theta_j, -sin theta_j cos phi_i)``."""
    h, w = out.shape[0], out.shape[1]
    trig = _maps.latlong_trig(h, w)
    for j in numba.prange(h):
        st, ct = trig[2, j], trig[3, j]
        for i in range(w):
            out[j, i, 0] = st * trig[0, i]
            out[j, i, 1] = ct
            out[j, i, 2] = -st * trig[1, i]


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

    def _overlap(self, n):
        """Texels of one disk's square that overlap the open unit disk (the valid ones)."""
        t = np.maximum(np.abs(2 * (np.arange(n) + 0.5) / n - 1) - 1 / n, 0)
        return t[None, :] ** 2 + t[:, None] ** 2 < 1 - _maps.DISK_OVERLAP_EPS

    def _valid(self, shape):
        return np.concatenate([self._overlap(shape[0])] * self.disks, axis=1)

    def solid_angles(self, shape):
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
    kind = _maps.ANGULAR

    def _H(self, q):
        # G(rho) = 1 - cos(pi rho) = (pi^2 / 2) rho^2 sinc(rho / 2)^2
        return (np.pi**2 / 2) * np.sinc(np.sqrt(q) / 2) ** 2


class AngularPhysical(Angular):
    """The angular map of a mirror ball's physical reflection: a camera looking along -Z sees
    behind itself (+Z) at the centre, so ``d = (a/r sin theta, b/r sin theta, +cos theta)``:
    the z-mirror image of :class:`Angular` (HDRShop's), for matching a photographed set."""

    name = "angular-physical"
    kind = _maps.ANGULAR_PHYSICAL


class MirrorBall(_Disk):
    """A mirror ball as HDRShop reads it: the same centre and axes as :class:`Angular` (centre
    forward, -Z; right +X; up +Y), with ``r = sin(theta / 2)`` for the angle ``theta`` from the
    centre (a ball seen from far away), so ``r = sin(45 deg)`` right of centre is +X:
    ``d = (2 n_z a, 2 n_z b, -(1 - 2 r^2))``, ``n_z = sqrt(1 - r^2)``. ``dOmega/dA = 4``."""

    name = "mirrorball"
    kind = _maps.MIRRORBALL

    def _H(self, q):
        return np.full_like(q, 2.0)


class MirrorBallPhysical(MirrorBall):
    """A photographed mirror ball's exact reflection: normal ``n = (a, b, sqrt(1 - r^2))``,
    camera looking along -Z, ``d = reflect((0, 0, -1), n) = (2 n_z a, 2 n_z b, 1 - 2 r^2)``;
    centre +Z (behind the camera), rim -Z. The z-mirror image of :class:`MirrorBall`."""

    name = "mirrorball-physical"
    kind = _maps.MIRRORBALL_PHYSICAL


class DualParaboloid(_Disk):
    """Two paraboloid maps (Heidrich and Seidel 1998) side by side, ``(N, 2N)``.

    Left disk: the front hemisphere (z <= 0) as seen from inside looking forward (-Z): right is
    +X, up is +Y. Right disk: the back hemisphere (z > 0) looking backward (+Z): right is -X, up
    +Y. In each, with ``f`` the hemisphere's axis and ``(r, t)`` its right and up axes,
    ``(a, b) = (d.r, d.t) / (1 + d.f)``; ``dOmega/dA = 4 / (1 + r^2)^2``.
    """

    name = "dual-paraboloid"
    kind = _maps.DUAL_PARABOLOID
    disks = 2
    g_max = 1.0

    def _H(self, q):
        return 2 / (1 + q)


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
    kind = _maps.OCTAHEDRAL

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

    def solid_angles(self, shape):
        n, _ = self.check_shape(shape)
        return _octahedral_solid_angles(n)


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
    # the texel corners' directions (a triangle's solid angle depends only on its vertices'
    # directions: its edges project onto great circles)
    corners = np.arange(n + 1.0)
    x, y = np.meshgrid(corners, corners)
    d = _LAYOUTS["octahedral"].directions_at(np.stack([x, y], axis=-1), (n, n))
    pts = {"00": d[:-1, :-1], "10": d[:-1, 1:], "01": d[1:, :-1], "11": d[1:, 1:]}
    e = 2 * np.arange(n + 1) / n - 1
    a0, a1 = e[None, :-1], e[None, 1:]
    c0, c1 = e[:-1, None], e[1:, None]
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


# --- OpenEXR's environment maps --------------------------------------------------------------


def _centre_aligned_edges(n: int) -> np.ndarray:
    """The cell edges, in [-1, 1], of ``n`` samples whose first and last lie on -1 and 1: the
    midpoints between samples, and the ends (the end samples' cells are half as wide)."""
    e = (2 * np.arange(n + 1) - 1) / (n - 1) - 1
    e[0], e[-1] = -1.0, 1.0
    return e


class OpenEXRLatLong(Layout):
    """OpenEXR's latitude-longitude environment (``envmap = latlong``, ``ImfEnvmap.h``).

    Texel centres, not edges, reach the ends: column ``i`` of ``W`` has longitude
    ``lon = pi (1 - 2 i / (W - 1))`` (+pi to -pi) and row ``j`` of ``H`` latitude
    ``lat = pi (1/2 - j / (H - 1))`` (+pi/2 to -pi/2); ``d = (sin lon cos lat, sin lat,
    cos lon cos lat)``: longitude 0 is +Z (the centre column), pi/2 is +X (a quarter to the
    left of the centre), the first and last rows are the poles and the first and last columns
    the same meridian (-Z). It is bakeshop's latlong turned half a turn, on a texel grid half
    a texel off both ways (a resampling, never a reordering).

    Each texel covers the part of the sphere nearer to its centre than to its neighbours'
    along each axis (its cell between midpoints), so the pole rows and the two seam columns are
    half cells: solid angles are exact and sum to 4*pi. Sizes are at least 2 x 2.
    """

    name = "openexr-latlong"
    kind = _maps.OPENEXR_LATLONG

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            return self.check_shape((h, w))
        n = int(size)
        return self.check_shape((n, 2 * n))

    def _check(self, shape):
        if len(shape) != 2 or min(shape) < 2:
            raise ArgumentError(
                "an openexr-latlong image is (H, W) with H, W >= 2 (its first and last rows "
                f"are the poles); got spatial shape {shape}"
            )

    def default_size(self, texels):
        return max(2, round(np.sqrt(texels / 2)))

    def solid_angles(self, shape):
        h, w = self.check_shape(shape)
        colatitude = np.pi * (_centre_aligned_edges(h) + 1) / 2
        c = np.cos(colatitude)
        band = c[:-1] - c[1:]
        width = np.pi * np.diff(_centre_aligned_edges(w))
        return band[:, None] * width[None, :]


class OpenEXRCube(Layout):
    """OpenEXR's cube environment (``envmap = cube``, ``ImfEnvmap.h``): six ``S x S`` faces
    stacked top to bottom in the order +X, -X, +Y, -Y, +Z, -Z, an ``(6 S, S)`` picture.

    Each face is the world seen from inside the cube, unmirrored (right-handed): +X has +Y up
    and +Z right, -X +Y up and -Z right, +Y +Z up and +X right, -Y -Z up and +X right, +Z +Y up
    and -X right, -Z +Y up and +X right (:data:`~bakeshop.sphere.cube.OPENEXR_FACE_BASES`).
    Texel centres reach the cube's edges: texel ``i`` of a face is at face coordinate
    ``2 i / (S - 1) - 1``, so neighbouring faces both hold the samples along their shared edge
    (each texel's solid angle is its cell's on its own face: exact, summing to 4*pi).
    Coordinates are ``(x, y)`` in the stacked picture; the scalar maps see six faces
    (:meth:`grid` is ``(S, S, 6)``). Faces are at least 2 x 2.
    """

    name = "openexr-cube"
    kind = _maps.OPENEXR_CUBE

    def shape(self, size):
        if isinstance(size, (tuple, list)):
            w, h = size
            if h != 6 * w:
                raise ArgumentError(
                    f"an openexr-cube is six square faces stacked (height 6 x width); got size "
                    f"{w}x{h}"
                )
            size = w
        n = int(size)
        return self.check_shape((6 * n, n))

    def _check(self, shape):
        if len(shape) != 2 or shape[0] != 6 * shape[1] or shape[1] < 2:
            raise ArgumentError(
                "an openexr-cube image is six square faces stacked top to bottom, (H, W) = "
                f"(6 S, S) with S >= 2; got (H, W) = {shape}"
            )

    def default_size(self, texels):
        return max(2, round(np.sqrt(texels / 6)))

    def grid(self, shape):
        _, s = self.check_shape(shape)
        return s, s, 6

    def face_size(self, shape) -> int:
        return self.check_shape(shape)[1]

    def directions_at(self, coords, shape):
        s = self.face_size(shape)
        c = np.asarray(coords, dtype=np.float64)
        if c.shape[-1] != 2:
            raise ArgumentError(f"{self.name} coordinates must be (..., 2)")
        face = np.clip(np.floor(c[..., 1] / s), 0, 5)
        fxy = np.stack([face, c[..., 0], c[..., 1] - face * s], axis=-1).reshape(-1, 3)
        out = np.empty((len(fxy), 3))
        _maps.directions_at(self.kind, s, s, np.ascontiguousarray(fxy), out)
        return out.reshape(c.shape[:-1] + (3,))

    def coordinates(self, dirs, shape):
        s = self.face_size(shape)
        d = _dirs_array(dirs)
        out = np.empty((d.size // 3, 3))
        _maps.coordinates_of(self.kind, s, s, np.ascontiguousarray(d.reshape(-1, 3)), out)
        out = out.reshape(d.shape[:-1] + (3,))
        return np.stack([out[..., 1], out[..., 0] * s + out[..., 2]], axis=-1)

    def solid_angles(self, shape):
        s = self.face_size(shape)
        e = _centre_aligned_edges(s)
        c = _cube_corner(e[None, :], e[:, None])
        face = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
        return np.tile(face, (6, 1))


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


class Cube(Layout):
    """The internal cube map ``(6, S, S)``: OpenGL order and orientation (see
    :mod:`bakeshop.sphere.cube`). Coordinates are ``(face, x, y)``. Texel solid angles are
    exact: ``atan(xy / sqrt(1 + x^2 + y^2))`` differenced over the texel's corners."""

    name = "cube"
    kind = _maps.CUBE
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
        return power_of_two_edge(texels / 6)

    def solid_angles(self, shape):
        _, s, _ = self.check_shape(shape)
        return np.broadcast_to(_cube_face_solid_angles(s), shape).copy()

    def grid(self, shape):
        _, s, _ = self.check_shape(shape)
        return s, s, 6


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
        return power_of_two_edge(texels / 6)

    def directions(self, shape):
        s = self.face_size(shape)
        d = _cube.cube_to_view(CUBE.directions((6, s, s))[0], self.name)
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
        c = CUBE.coordinates(dirs, (6, s, s))
        face, x, y = c[..., 0].astype(np.int64), c[..., 1], c[..., 2]
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
        AngularPhysical(),
        MirrorBallPhysical(),
        CUBE,
        Octahedral(),
        DualParaboloid(),
        OpenEXRLatLong(),
        OpenEXRCube(),
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
