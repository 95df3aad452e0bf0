"""Layouts against their definitions (DESIGN.md): round trips, landmark texels, and texel solid
angles against independent quadrature of each layout's area density and Monte Carlo binning."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.sphere import LAYOUT_NAMES, guess_layout, layout
from tests.tolerances import (
    SPHERE_COORD_ATOL,
    SPHERE_DIRECTION_ATOL,
    SPHERE_LATLONG_SEPARABLE_ATOL,
    SPHERE_ROUND_TRIP_ATOL,
    SPHERE_SOLID_ANGLE_RTOL,
    SPHERE_TEXEL_OMEGA_RTOL,
)

SIZES = {name: (1, 2, 7, 16, 33) for name in LAYOUT_NAMES}
SIZES["octahedral"] = (2, 8, 16, 34)
# OpenEXR's maps put texel centres on the poles, seams and cube edges: at least 2 texels
SIZES["openexr-latlong"] = SIZES["openexr-cube"] = (2, 3, 7, 16, 33)
#: the layouts made of disks.
DISKS = ("angular", "mirrorball", "angular-physical", "mirrorball-physical", "dual-paraboloid")


def centres(shape):
    """(x, y) texel-centre coordinates for a spatial shape (H, W)."""
    h, w = shape[-2:]
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return np.broadcast_to(np.stack([x, y], -1), shape + (2,))


def inside(lay, shape):
    """Texels whose centres lie in the layout's domain and map back to themselves alone (disk
    rim texels, and OpenEXR's texels on poles, seams and cube edges, excepted)."""
    dirs, valid = lay.directions(shape)
    if lay.name in DISKS:
        n = shape[0]
        t = 2 * (np.arange(n) + 0.5) / n - 1
        valid = valid & np.tile(t[None, :] ** 2 + t[:, None] ** 2 <= 1, (1, shape[1] // n))
    if lay.name == "openexr-latlong":
        valid = valid.copy()
        valid[[0, -1]] = False
        valid[:, -1] = False
    if lay.name == "openexr-cube":
        s = shape[1]
        edge = np.zeros((s, s), bool)
        edge[[0, -1]] = edge[:, [0, -1]] = True
        valid = valid & ~np.tile(edge, (6, 1))
    return valid


@pytest.mark.parametrize("name", LAYOUT_NAMES)
def test_directions_coordinates_round_trip(name):
    lay = layout(name)
    for n in SIZES[name]:
        shape = lay.shape(n)
        dirs, valid = lay.directions(shape)
        assert dirs.shape == shape + (3,) and valid.shape == shape
        assert np.all(np.isfinite(dirs))
        np.testing.assert_allclose(np.linalg.norm(dirs, axis=-1), 1, atol=SPHERE_DIRECTION_ATOL)
        coords = lay.coordinates(dirs, shape)
        ok = inside(lay, shape)
        np.testing.assert_allclose(
            coords[..., -2:][ok], centres(shape)[ok], atol=SPHERE_COORD_ATOL * max(shape)
        )
        if lay.cubic:
            np.testing.assert_array_equal(
                coords[..., 0], np.arange(6)[:, None, None] + 0 * coords[..., 1]
            )


@pytest.mark.parametrize("name", LAYOUT_NAMES)
def test_random_directions_round_trip(name):
    """Random directions -> coordinates -> directions_at is the identity to 1e-6 (in practice
    ~1e-15); the coordinates land in valid texels."""
    lay = layout(name)
    rng = np.random.default_rng(3)
    d = rng.normal(size=(20000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    for n in (2, 64, 1024):
        shape = lay.shape(n)
        coords = lay.coordinates(d, shape)
        back = lay.directions_at(coords, shape)
        assert np.abs(back - d).max() < SPHERE_ROUND_TRIP_ATOL
        _, valid = lay.directions(shape)
        x = np.clip(np.floor(coords[..., -2]).astype(int), 0, shape[-1] - 1)
        y = np.clip(np.floor(coords[..., -1]).astype(int), 0, shape[-2] - 1)
        idx = (coords[..., 0].astype(int), y, x) if lay.cubic else (y, x)
        assert valid[idx].all()


def test_round_trip_identity_to_1e6():
    """Exact inverse formulas: every layout's coordinates of its own directions are the texel
    centres to 1e-6 texel (the issue's bound), at a production size."""
    for name in LAYOUT_NAMES:
        lay = layout(name)
        shape = lay.shape(256)
        dirs, _ = lay.directions(shape)
        ok = inside(lay, shape)
        err = np.abs(lay.coordinates(dirs, shape)[..., -2:] - centres(shape))[ok].max()
        assert err < 1e-6, (name, err)


def direction_at(name, x, y, shape):
    """Direction of continuous coordinates, written from DESIGN.md independently of the code."""
    h, w = shape[-2:]
    u, v = x / w, y / h
    if name == "latlong":
        phi, theta = 2 * np.pi * (u - 0.5), np.pi * v
        return np.array([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)])
    a, b = 2 * u - 1, 1 - 2 * v
    r = np.hypot(a, b)
    if name == "angular":
        # DESIGN.md (HDRShop's): theta = pi r from the centre, which looks forward (-Z)
        th = np.pi * r
        return np.array([a / r * np.sin(th), b / r * np.sin(th), -np.cos(th)])
    if name == "mirrorball":
        # the same centre, r = sin(theta / 2)
        th = 2 * np.arcsin(r)
        return np.array([a / r * np.sin(th), b / r * np.sin(th), -np.cos(th)])
    if name in ("angular-physical", "mirrorball-physical"):
        # a ball photographed by a camera looking along -Z reflects the view ray about its normal
        n = np.array([a, b, np.sqrt(1 - a * a - b * b)])
        view = np.array([0, 0, -1.0])
        ball = view - 2 * view.dot(n) * n
        if name == "mirrorball-physical":
            return ball
        # the angular map of the same reflection: angle from the centre (+Z) linear in r
        th = np.pi * r
        return np.array([a / r * np.sin(th), b / r * np.sin(th), np.cos(th)])
    raise AssertionError(name)


@pytest.mark.parametrize(
    ("name", "xy", "expected"),
    [
        ("latlong", (0.75, 0.5), (1, 0, 0)),
        ("latlong", (0.5, 0.5), (0, 0, -1)),
        ("latlong", (0.25, 0.5), (-1, 0, 0)),
        ("latlong", (1.0, 0.5), (0, 0, 1)),  # the seam: u = 1 (u = 0 is the same)
        ("latlong", (0.3, 0.0), (0, 1, 0)),
        ("latlong", (0.3, 1.0), (0, -1, 0)),
        # HDRShop's probes: the centre looks forward, right is +X, up is +Y, the rim behind
        ("angular", (0.5, 0.5), (0, 0, -1)),
        ("angular", (0.75, 0.5), (1, 0, 0)),  # Debevec: r = acos(Dz) / pi = 1/2
        ("angular", (0.5, 0.25), (0, 1, 0)),
        ("angular", (0.25, 0.5), (-1, 0, 0)),
        ("angular", (1.0, 0.5), (0, 0, 1)),
        ("angular", (0.5, 1.0), (0, 0, 1)),
        ("mirrorball", (0.5, 0.5), (0, 0, -1)),
        ("mirrorball", (0.5 + np.sqrt(0.5) / 2, 0.5), (1, 0, 0)),  # r = sin(45 degrees)
        ("mirrorball", (0.5, 0.5 - np.sqrt(0.5) / 2), (0, 1, 0)),
        ("mirrorball", (0.5 - np.sqrt(0.5) / 2, 0.5), (-1, 0, 0)),
        ("mirrorball", (0.0, 0.5), (0, 0, 1)),
        # the physical reflection: the z-mirror image (the camera, +Z, at the centre)
        ("angular-physical", (0.5, 0.5), (0, 0, 1)),
        ("angular-physical", (0.75, 0.5), (1, 0, 0)),
        ("angular-physical", (0.5, 0.25), (0, 1, 0)),
        ("angular-physical", (0.0, 0.5), (0, 0, -1)),
        ("mirrorball-physical", (0.5, 0.5), (0, 0, 1)),
        ("mirrorball-physical", (0.5 + np.sqrt(0.5) / 2, 0.5), (1, 0, 0)),  # normal at 45 deg
        ("mirrorball-physical", (0.5, 0.5 - np.sqrt(0.5) / 2), (0, 1, 0)),
        ("mirrorball-physical", (0.5, 0.0), (0, 0, -1)),
        ("octahedral", (0.5, 0.5), (0, 1, 0)),
        ("octahedral", (1.0, 0.5), (1, 0, 0)),
        ("octahedral", (0.5, 0.0), (0, 0, -1)),
        ("octahedral", (0.5, 1.0), (0, 0, 1)),
        ("octahedral", (0.0, 0.0), (0, -1, 0)),
        ("dual-paraboloid", (0.25, 0.5), (0, 0, -1)),
        ("dual-paraboloid", (0.75, 0.5), (0, 0, 1)),
        ("dual-paraboloid", (0.5, 0.5), (1, 0, 0)),  # right rim of the front disk
        ("dual-paraboloid", (0.0, 0.5), (-1, 0, 0)),
        ("dual-paraboloid", (0.25, 0.0), (0, 1, 0)),
        ("dual-paraboloid", (0.875, 0.5), (-0.8, 0, 0.6)),  # back disk: right is -X
    ],
)
def test_landmarks(name, xy, expected):
    """Image position (u, v) (fractions of width and height) looks where DESIGN.md says, and
    the direction maps back to that position (up to the ambiguity of poles and rims)."""
    lay = layout(name)
    shape = lay.shape(64)
    h, w = shape
    pos = np.array([xy[0] * w, xy[1] * h])
    np.testing.assert_allclose(lay.directions_at(pos, shape), expected, atol=1e-12)
    back = lay.coordinates(np.array(expected, float), shape)
    np.testing.assert_allclose(lay.directions_at(back, shape), expected, atol=1e-12)
    unique = not (expected[1] != 0 and name == "latlong") and expected != (0, -1, 0)
    rim = (0, 0, -1) if name.endswith("-physical") else (0, 0, 1)
    if unique and not (expected == rim and name in DISKS):
        np.testing.assert_allclose(back, pos, atol=1e-9)


@pytest.mark.parametrize(
    "name", ["latlong", "angular", "mirrorball", "angular-physical", "mirrorball-physical"]
)
def test_directions_follow_design_formulas(name):
    lay = layout(name)
    shape = lay.shape(16)
    dirs, _ = lay.directions(shape)
    ok = inside(lay, shape)
    for j, i in zip(*np.nonzero(ok), strict=True):
        np.testing.assert_allclose(
            dirs[j, i], direction_at(name, i + 0.5, j + 0.5, shape), atol=1e-12
        )


def test_latlong_separable_directions_match_the_per_texel_formula():
    """latlong directions are built from per-column and per-row sines and cosines: they equal
    the general path (``directions_at`` the texel centres) and DESIGN.md's formula evaluated
    per texel, to a few ulps, on odd, tiny, non-2:1 and large shapes."""
    lay = layout("latlong")
    rng = np.random.default_rng(7)
    for shape in [(1, 1), (1, 2), (3, 7), (33, 66), (17, 500), (1000, 2000)]:
        dirs, valid = lay.directions(shape)
        assert dirs.shape == shape + (3,) and dirs.dtype == np.float64
        assert valid.shape == shape and valid.dtype == bool and valid.all()
        h, w = shape
        j, i = rng.integers(0, h, 5000), rng.integers(0, w, 5000)
        general = lay.directions_at(np.stack([i + 0.5, j + 0.5], -1), shape)
        phi = 2 * np.pi * ((i + 0.5) / w - 0.5)
        theta = np.pi * (j + 0.5) / h
        design = np.stack(
            [np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], -1
        )
        for expected in (general, design):
            np.testing.assert_allclose(
                dirs[j, i], expected, rtol=0, atol=SPHERE_LATLONG_SEPARABLE_ATOL
            )


def test_angular_matches_debevec_formula():
    """Debevec's (u, v) = (Dx, Dy) acos(Dz) / (pi sqrt(Dx^2 + Dy^2)), u right and v up from the
    centre, holds in HDRShop's left-handed frame (z forward: D = (x, y, -z) of ours) for
    ``angular`` and in ours for ``angular-physical``."""
    rng = np.random.default_rng(0)
    d = rng.normal(size=(1000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    n = 100
    for name, frame in (("angular", [1, 1, -1]), ("angular-physical", [1, 1, 1])):
        dh = d * frame
        k = np.arccos(dh[:, 2]) / (np.pi * np.hypot(dh[:, 0], dh[:, 1]))
        c = layout(name).coordinates(d, (n, n))
        np.testing.assert_allclose(c[:, 0] / n * 2 - 1, dh[:, 0] * k, atol=1e-12)
        np.testing.assert_allclose(1 - c[:, 1] / n * 2, dh[:, 1] * k, atol=1e-12)


def test_cube_face_table():
    """Each face's centre and its texel (0, 0) corner follow the OpenGL table of DESIGN.md."""
    lay = layout("cube")
    s = 64
    dirs, _ = lay.directions((6, s, s))
    # (sc, tc) = (-1, -1) at texel (0, 0): d = ma - U - V for the table's sc, tc
    expected_corner = {
        0: (1, 1, 1),  # +X: sc=-z, tc=-y  -> z=+1, y=+1
        1: (-1, 1, -1),  # -X: sc=+z, tc=-y
        2: (-1, 1, -1),  # +Y: sc=+x, tc=+z
        3: (-1, -1, 1),  # -Y: sc=+x, tc=-z
        4: (-1, 1, 1),  # +Z: sc=+x, tc=-y
        5: (1, 1, -1),  # -Z: sc=-x, tc=-y
    }
    axes = np.eye(3)
    for f in range(6):
        centre = dirs[f, s // 2 - 1 : s // 2 + 1, s // 2 - 1 : s // 2 + 1].mean(axis=(0, 1))
        np.testing.assert_allclose(
            centre / np.linalg.norm(centre), axes[f // 2] * (1 - 2 * (f % 2)), atol=1e-12
        )
        corner = np.array(expected_corner[f], float) / np.sqrt(3)
        assert np.dot(dirs[f, 0, 0], corner) > np.cos(2.5 / s)


@pytest.mark.parametrize(
    ("name", "slot", "expected"),
    [
        ("cross-vertical", (1, 1), (0, 0, -1)),
        ("cross-vertical", (0, 1), (-1, 0, 0)),
        ("cross-vertical", (2, 1), (1, 0, 0)),
        ("cross-vertical", (1, 0), (0, 1, 0)),
        ("cross-vertical", (1, 2), (0, -1, 0)),
        ("cross-vertical", (1, 3), (0, 0, 1)),
        ("cross-horizontal", (1, 1), (0, 0, -1)),
        ("cross-horizontal", (3, 1), (0, 0, 1)),
        ("cross-horizontal", (1, 0), (0, 1, 0)),
        ("strip-horizontal", (0, 0), (1, 0, 0)),
        ("strip-horizontal", (4, 0), (0, 0, -1)),  # slot +Z of the left-handed set: forward
        ("strip-horizontal", (5, 0), (0, 0, 1)),
        ("strip-vertical", (2, 0), (0, 1, 0)),
    ],
)
def test_view_slots(name, slot, expected):
    lay = layout(name)
    s = 8
    shape = lay.shape(s)
    dirs, valid = lay.directions(shape)
    col, row = slot
    if name == "strip-vertical":
        col, row = row, col
    block = dirs[row * s : (row + 1) * s, col * s : (col + 1) * s]
    assert valid[row * s : (row + 1) * s, col * s : (col + 1) * s].all()
    c = block[s // 2 - 1 : s // 2 + 1, s // 2 - 1 : s // 2 + 1].mean(axis=(0, 1))
    np.testing.assert_allclose(c / np.linalg.norm(c), expected, atol=1e-12)


def test_vertical_cross_is_unmirrored_and_continuous():
    """Seen from inside: in the centre (forward) face +X is right and +Y up; the faces around it
    continue across their shared edges (adjacent texels across every cross edge look at nearly
    the same direction); the bottom face (+Z) is turned 180 degrees so it meets -Y."""
    lay = layout("cross-vertical")
    s = 32
    dirs, valid = lay.directions(lay.shape(s))
    centre = dirs[s : 2 * s, s : 2 * s]
    assert centre[s // 2, -1, 0] > centre[s // 2, 0, 0]  # x grows to the right
    assert centre[0, s // 2, 1] > centre[-1, s // 2, 1]  # y grows upward
    limit = 2.5 * (2 / s)
    edges = [
        (dirs[s - 1, s : 2 * s], dirs[s, s : 2 * s]),  # +Y above centre
        (dirs[s : 2 * s, s - 1], dirs[s : 2 * s, s]),  # -X left of centre
        (dirs[s : 2 * s, 2 * s - 1], dirs[s : 2 * s, 2 * s]),  # +X right of centre
        (dirs[2 * s - 1, s : 2 * s], dirs[2 * s, s : 2 * s]),  # -Y below centre
        (dirs[3 * s - 1, s : 2 * s], dirs[3 * s, s : 2 * s]),  # back face below -Y
    ]
    for p, q in edges:
        angle = np.arccos(np.clip(np.einsum("ij,ij->i", p, q), -1, 1))
        assert angle.max() < limit
    assert not valid[0, 0] and valid[0, s]


# --- solid angles -----------------------------------------------------------------------------


def gauss_integral(density, x0, x1, y0, y1, n=40):
    """Tensor Gauss-Legendre integral of density(x, y) over the rectangle (float64)."""
    g, w = np.polynomial.legendre.leggauss(n)
    xs = (x0 + x1) / 2 + (x1 - x0) / 2 * g
    ys = (y0 + y1) / 2 + (y1 - y0) / 2 * g
    X, Y = np.meshgrid(xs, ys)
    return (w[None, :] * w[:, None] * density(X, Y)).sum() * (x1 - x0) * (y1 - y0) / 4


def oct_point(a, c):
    aa, ac = np.abs(a), np.abs(c)
    y = 1 - aa - ac
    low = y < 0
    return np.stack(
        [np.where(low, np.sign(a) * (1 - ac), a), y, np.where(low, np.sign(c) * (1 - aa), c)], -1
    )


DENSITIES = {
    # dOmega / dA on each layout's natural (a, b) square [-1, 1]^2 (interior texels only)
    "angular": lambda a, b: np.pi * np.sin(np.pi * np.hypot(a, b)) / np.hypot(a, b),
    "mirrorball": lambda a, b: 4.0 + 0 * a,
    "angular-physical": lambda a, b: np.pi * np.sin(np.pi * np.hypot(a, b)) / np.hypot(a, b),
    "mirrorball-physical": lambda a, b: 4.0 + 0 * a,
    "dual-paraboloid": lambda a, b: 4 / (1 + a * a + b * b) ** 2,
    "octahedral": lambda a, c: 1 / np.linalg.norm(oct_point(a, c), axis=-1) ** 3,
    "cube": lambda x, y: 1 / (1 + x * x + y * y) ** 1.5,
}


@pytest.mark.parametrize("name", LAYOUT_NAMES)
def test_solid_angles_sum_to_4pi(name):
    lay = layout(name)
    for n in SIZES[name]:
        shape = lay.shape(n)
        omega = lay.solid_angles(shape)
        _, valid = lay.directions(shape)
        assert omega.shape == shape
        assert omega.sum() == pytest.approx(4 * np.pi, rel=SPHERE_SOLID_ANGLE_RTOL)
        assert np.all(omega[valid] > 0) and np.all(omega[~valid] == 0)


@pytest.mark.parametrize("name", [*DISKS, "octahedral", "cube"])
def test_texel_solid_angles_match_quadrature_of_the_density(name):
    lay = layout(name)
    n = 16
    shape = lay.shape(n)
    omega = lay.solid_angles(shape)
    if lay.cubic:
        omega = omega[4]
    e = 2 * np.arange(n + 1) / n - 1
    checked = 0
    for j in range(n):
        for i in range(n):
            a0, a1, c0, c1 = e[i], e[i + 1], e[j], e[j + 1]
            if name in DISKS:
                if max(abs(a0), abs(a1)) ** 2 + max(abs(c0), abs(c1)) ** 2 > 1:
                    continue
            if name == "octahedral":
                # skip texels cut by a fold (the density is smooth only within one face)
                corners = np.abs([a0, a1])[:, None] + np.abs([c0, c1])[None, :]
                if corners.min() < 1 < corners.max():
                    continue
            exact = gauss_integral(DENSITIES[name], a0, a1, c0, c1)
            assert omega[j, i] == pytest.approx(exact, rel=SPHERE_TEXEL_OMEGA_RTOL), (j, i)
            checked += 1
    assert checked > n * n // 3


def test_latlong_band_matches_quadrature():
    lay = layout("latlong")
    h, w = 10, 20
    omega = lay.solid_angles((h, w))
    for j in range(h):
        t0, t1 = np.pi * j / h, np.pi * (j + 1) / h
        exact = gauss_integral(lambda p, t: np.sin(t), 0, 2 * np.pi / w, t0, t1)
        np.testing.assert_allclose(omega[j], exact, rtol=SPHERE_TEXEL_OMEGA_RTOL)


@pytest.mark.parametrize("name", [*DISKS, "octahedral"])
def test_rim_and_fold_texels_are_sums_of_their_subtexels(name):
    """Texels cut by the rim or a fold have no smooth density: each must equal the sum of its
    2 x 2 sub-texels at twice the resolution (different corners, the same exact integral)."""
    lay = layout(name)
    n = 14
    coarse = lay.solid_angles(lay.shape(n))
    fine = lay.solid_angles(lay.shape(2 * n))
    h, w = coarse.shape
    summed = fine.reshape(h, 2, w, 2).sum(axis=(1, 3))
    np.testing.assert_allclose(coarse, summed, rtol=SPHERE_TEXEL_OMEGA_RTOL, atol=1e-15)


@pytest.mark.parametrize(
    "name",
    ["latlong", "angular", "mirrorball-physical", "octahedral", "dual-paraboloid",
     "cross-vertical", "openexr-latlong", "openexr-cube"],
)  # fmt: skip
def test_solid_angles_match_monte_carlo_binning(name):
    """Uniform random directions binned by coordinates: counts / total * 4 pi ~ solid angle."""
    lay = layout(name)
    shape = lay.shape(8)
    omega = lay.solid_angles(shape)
    rng = np.random.default_rng(7)
    m = 400_000
    d = rng.normal(size=(m, 3))
    c = lay.coordinates(d, shape)
    x = np.clip(np.floor(c[:, 0]).astype(int), 0, shape[1] - 1)
    y = np.clip(np.floor(c[:, 1]).astype(int), 0, shape[0] - 1)
    counts = np.zeros(shape)
    np.add.at(counts, (y, x), 1)
    expected = omega / (4 * np.pi) * m
    sel = expected > 200
    z = (counts[sel] - expected[sel]) / np.sqrt(expected[sel])
    assert np.abs(z).max() < 5.5
    assert counts[omega == 0].sum() == 0


# --- shapes and guesses -----------------------------------------------------------------------


def test_shapes_from_sizes():
    assert layout("latlong").shape(256) == (256, 512)
    assert layout("latlong").shape((360, 180)) == (180, 360)
    assert layout("angular").shape(100) == (100, 100)
    assert layout("cube").shape(32) == (6, 32, 32)
    assert layout("cross-vertical").shape(32) == (128, 96)
    assert layout("cross-horizontal").shape((128, 96)) == (96, 128)
    assert layout("strip-horizontal").shape(16) == (16, 96)
    assert layout("strip-vertical").shape(16) == (96, 16)
    assert layout("dual-paraboloid").shape(64) == (64, 128)


@pytest.mark.parametrize(
    ("name", "size"),
    [("octahedral", 15), ("angular", (10, 12)), ("cube", (4, 5)), ("cross-vertical", (10, 10)),
     ("latlong", 0), ("latlong", (1 << 17, 4)), ("dual-paraboloid", (10, 10))],
)  # fmt: skip
def test_bad_sizes_are_refused(name, size):
    with pytest.raises(ArgumentError):
        layout(name).shape(size)


def test_unknown_layout_names_the_choices():
    with pytest.raises(ArgumentError, match="latlong"):
        layout("equirect")


def test_guess_layout():
    assert guess_layout(512, 1024) == ["latlong"]
    assert guess_layout(1024, 768) == ["cross-vertical"]
    assert guess_layout(768, 1024) == ["cross-horizontal"]
    assert guess_layout(64, 384) == ["strip-horizontal"]
    assert guess_layout(384, 64) == ["strip-vertical"]
    assert guess_layout(512, 512) == [
        "angular", "mirrorball", "octahedral", "angular-physical", "mirrorball-physical"
    ]  # fmt: skip
    assert "octahedral" not in guess_layout(511, 511)
    assert guess_layout(100, 333) == []
