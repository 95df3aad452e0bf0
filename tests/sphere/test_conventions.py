"""Conventions other tools made, each against an implementation written here in that tool's
own terms: HDRShop's light probes and crosses (its left-handed frame, Debevec's formula), a
mirror ball photographed in a set (the physical reflection), and OpenEXR's environment maps
(``ImfEnvmap.h``, read in :mod:`tests.imfenvmap`)."""

import numpy as np
import pytest

from bakeshop.sphere import layout, remap
from tests import imfenvmap as imf
from tests.tolerances import (
    CONVENTION_BILINEAR_ATOL,
    SPHERE_COORD_ATOL,
    SPHERE_DIRECTION_ATOL,
    SPHERE_TEXEL_OMEGA_RTOL,
)

# --- HDRShop ----------------------------------------------------------------------------------

#: HDRShop's vertical cross in its own left-handed frame (x right, y up, z forward): the cube
#: unfolded around the forward face and seen from inside. Slot (column, row) -> (centre,
#: right, up) of the face shown there. Each neighbour shares an edge with the face it touches
#: (the top face's lower edge is the forward face's upper edge, and so on down the column to
#: the back face, which is therefore upside down).
HDRSHOP_CROSS = {
    (1, 0): ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    (0, 1): ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    (1, 1): ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    (2, 1): ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    (1, 2): ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    (1, 3): ((0, 0, -1), (1, 0, 0), (0, -1, 0)),
}


def hdrshop_cross_directions(s):
    """Directions (HDRShop's frame) of the texel centres of a vertical cross of face size s,
    and the mask of its six squares."""
    t = 2 * (np.arange(s) + 0.5) / s - 1
    dirs = np.zeros((4 * s, 3 * s, 3))
    used = np.zeros((4 * s, 3 * s), bool)
    for (col, row), (c, r, u) in HDRSHOP_CROSS.items():
        c, r, u = (np.array(v, float) for v in (c, r, u))
        block = c + t[None, :, None] * r - t[:, None, None] * u  # rows run down
        dirs[row * s : (row + 1) * s, col * s : (col + 1) * s] = block
        used[row * s : (row + 1) * s, col * s : (col + 1) * s] = True
    norm = np.linalg.norm(dirs, axis=-1, keepdims=True)
    return dirs / np.where(used[..., None], norm, 1.0), used


def debevec_probe_position(d, n):
    """Debevec's light probe mapping in HDRShop's frame: (u, v) = (Dx, Dy) acos(Dz) /
    (pi sqrt(Dx^2 + Dy^2)), u right and v up from the centre; as texel coordinates of an
    n x n probe."""
    k = np.arccos(np.clip(d[..., 2], -1, 1)) / (np.pi * np.hypot(d[..., 0], d[..., 1]))
    u, v = d[..., 0] * k, d[..., 1] * k
    return np.stack([(u + 1) / 2 * n, (1 - v) / 2 * n], -1)


def debevec_probe_direction(n):
    """The inverse of Debevec's mapping at the texel centres of an n x n probe (HDRShop's
    frame), and the texels inside the disk."""
    x = (np.arange(n) + 0.5) / n * 2 - 1
    a, b = np.meshgrid(x, -x)
    r = np.hypot(a, b)
    th = np.pi * r
    d = np.stack([a / r * np.sin(th), b / r * np.sin(th), np.cos(th)], -1)
    return d, r < 1


@pytest.mark.slow
def test_angular_probe_to_cross_is_hdrshops_cross():
    """HDRShop's cross of a probe, computed entirely in HDRShop's frame (Debevec's formula,
    the cube unfolded around its forward face): bakeshop's angular -> cross-vertical gives the
    same picture. The probe holds 1.5 + its own HDRShop direction, so every texel of the cross
    must hold 1.5 + the direction HDRShop gives it: a mirrored convention is off by up to 2."""
    n, s = 512, 64
    probe_dirs, inside = debevec_probe_direction(n)
    probe = np.where(inside[..., None], probe_dirs + 1.5, 0.0).astype(np.float32)
    cross = remap(probe, "angular", "cross-vertical", s, filter="bilinear")
    expected, used = hdrshop_cross_directions(s)
    err = np.abs(cross - (expected + 1.5))[used]
    assert err.max() < CONVENTION_BILINEAR_ATOL, err.max()
    # the physical variant is HDRShop's z-mirror image: its cross is off by 2 at the centre
    mirrored = remap(probe, "angular-physical", "cross-vertical", s, filter="bilinear")
    assert np.abs(mirrored - (expected + 1.5))[used].max() > 1.9


def test_debevec_formula_round_trips_through_bakeshops_angular_layout():
    """Debevec's formula of a direction (HDRShop's frame, z forward) lands where bakeshop's
    angular layout puts the same direction (our frame: (x, y, -z))."""
    rng = np.random.default_rng(5)
    d = rng.normal(size=(5000, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    n = 64
    ours = d * [1, 1, -1]
    np.testing.assert_allclose(
        layout("angular").coordinates(ours, (n, n)),
        debevec_probe_position(d, n),
        atol=SPHERE_COORD_ATOL * n,
    )


def photographed_ball(n, environment):
    """A mirror ball photographed from far away by a camera looking along -Z (orthographic):
    pixel (a, b) of the ball's disk shows ``environment`` in the direction the view ray leaves
    the ball, reflected about the normal (a, b, sqrt(1 - a^2 - b^2))."""
    x = (np.arange(n) + 0.5) / n * 2 - 1
    a, b = np.meshgrid(x, -x)
    r2 = a * a + b * b
    normal = np.stack([a, b, np.sqrt(np.clip(1 - r2, 0, 1))], -1)
    view = np.array([0.0, 0.0, -1.0])
    d = view - 2 * (normal @ view)[..., None] * normal
    return np.where((r2 < 1)[..., None], environment(d), 0.0).astype(np.float32)


def sky(d):
    """A smooth environment that tells every axis apart: 1.5 + d."""
    return d + 1.5


def test_photographed_ball_is_the_set_with_the_physical_option():
    """A ball photographed in a set, read as ``mirrorball-physical``, gives the set's world as
    it is; read as ``mirrorball`` (HDRShop's) it gives the world mirrored front to back."""
    ball = photographed_ball(1024, sky)
    dirs, _ = layout("latlong").directions((64, 128))
    # the texels near the ball's rim (the direction ahead of the camera) are too compressed
    # for a texel-accurate bilinear lookup: compare away from it
    ahead = dirs[..., 2] < -0.9
    physical = remap(ball, "mirrorball-physical", "latlong", 64, filter="bilinear")
    assert np.abs(physical - sky(dirs))[~ahead].max() < CONVENTION_BILINEAR_ATOL
    hdrshop = remap(ball, "mirrorball", "latlong", 64, filter="bilinear")
    behind = dirs[..., 2] > 0.9
    mirrored = sky(dirs * [1, 1, -1])
    assert np.abs(hdrshop - mirrored)[~behind].max() < CONVENTION_BILINEAR_ATOL


@pytest.mark.parametrize("name", ["angular-physical", "mirrorball-physical"])
def test_physical_option_round_trips(name):
    """latlong -> the physical layout -> latlong keeps a smooth environment, and the same
    pixels read with HDRShop's convention are its z-mirror image."""
    dirs, _ = layout("latlong").directions((64, 128))
    env = sky(dirs).astype(np.float32)
    probe = remap(env, "latlong", name, 512, filter="bilinear")
    back = remap(probe, name, "latlong", 64, filter="bilinear")
    rim = dirs[..., 2] < -0.9  # the rim of a ball (ahead): see above
    keep = ~rim if name == "mirrorball-physical" else np.ones_like(rim)
    assert np.abs(back - env)[keep].max() < CONVENTION_BILINEAR_ATOL
    hdrshop = name.removesuffix("-physical")
    mirrored = remap(probe, hdrshop, "latlong", 64, filter="bilinear")
    keep = ~(dirs[..., 2] > 0.9) if name == "mirrorball-physical" else np.ones_like(rim)
    assert np.abs(mirrored - sky(dirs * [1, 1, -1]))[keep].max() < CONVENTION_BILINEAR_ATOL


# --- OpenEXR ----------------------------------------------------------------------------------


@pytest.mark.parametrize("shape", [(512, 1024), (7, 13), (2, 2), (3, 2)])
def test_openexr_latlong_directions_are_imfenvmaps(shape):
    h, w = shape
    y, x = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    dirs, valid = layout("openexr-latlong").directions(shape)
    assert valid.all()
    np.testing.assert_allclose(dirs, imf.latlong_direction(w, h, x, y), atol=SPHERE_DIRECTION_ATOL)


@pytest.mark.parametrize("s", [2, 3, 16, 256])
def test_openexr_cube_directions_are_imfenvmaps(s):
    """Face order, stacking and each face's orientation as ImfEnvmap's ``direction`` and
    ``pixelPosition`` place them."""
    dirs, valid = layout("openexr-cube").directions((6 * s, s))
    assert valid.all()
    np.testing.assert_allclose(dirs, imf.cube_directions(s), atol=SPHERE_DIRECTION_ATOL)


@pytest.mark.parametrize(("name", "size"), [("openexr-latlong", 33), ("openexr-cube", 17)])
def test_openexr_coordinates_are_imfenvmaps_pixel_positions(name, size):
    """Directions -> texel coordinates; ImfEnvmap's pixel position p is coordinate p + 0.5."""
    lay = layout(name)
    shape = lay.shape(size)
    h, w = shape
    rng = np.random.default_rng(11)
    d = rng.normal(size=(20000, 3))
    if name == "openexr-latlong":
        expected = imf.latlong_position(w, h, d)
    else:
        expected = imf.cube_position(w, d)
    np.testing.assert_allclose(
        lay.coordinates(d, shape) - 0.5, expected, atol=SPHERE_COORD_ATOL * max(shape)
    )


def cell_integral(density, x0, x1, y0, y1, n=40):
    g, wg = np.polynomial.legendre.leggauss(n)
    xs = (x0 + x1) / 2 + (x1 - x0) / 2 * g
    ys = (y0 + y1) / 2 + (y1 - y0) / 2 * g
    X, Y = np.meshgrid(xs, ys)
    return (wg[None, :] * wg[:, None] * density(X, Y)).sum() * (x1 - x0) * (y1 - y0) / 4


def test_openexr_solid_angles_are_the_cells_around_each_sample():
    """Each texel covers the face coordinates (cube) or angles (latlong) nearer its centre than
    its neighbours', clipped at the edges, poles and seam: Gauss quadrature of the density
    over those cells, independently of the layouts' closed forms."""
    s = 9
    omega = layout("openexr-cube").solid_angles((6 * s, s))
    p = 2 * np.arange(s) / (s - 1) - 1
    lo, hi = np.maximum(p - 1 / (s - 1), -1), np.minimum(p + 1 / (s - 1), 1)
    for j in range(s):
        for i in range(s):
            exact = cell_integral(
                lambda x, y: (1 + x * x + y * y) ** -1.5, lo[i], hi[i], lo[j], hi[j]
            )
            assert omega[2 * s + j, i] == pytest.approx(exact, rel=SPHERE_TEXEL_OMEGA_RTOL)
    h, w = 7, 12
    omega = layout("openexr-latlong").solid_angles((h, w))
    lat = np.pi / 2 - np.pi * np.arange(h) / (h - 1)
    lon_step = 2 * np.pi / (w - 1)
    for j in range(h):
        top, bottom = (
            min(np.pi / 2, lat[j] + np.pi / (2 * (h - 1))),
            max(-np.pi / 2, lat[j] - np.pi / (2 * (h - 1))),
        )
        band = cell_integral(lambda lon, la: np.cos(la), 0, lon_step, bottom, top)
        np.testing.assert_allclose(omega[j, 1:-1], band, rtol=SPHERE_TEXEL_OMEGA_RTOL)
        np.testing.assert_allclose(omega[j, [0, -1]], band / 2, rtol=SPHERE_TEXEL_OMEGA_RTOL)
