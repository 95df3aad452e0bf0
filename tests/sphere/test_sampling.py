"""Sampling and remapping against analytic environments: a smooth function of direction and a
checker whose cells have known directions, into every layout; seams, corners, poles, rotation,
disk masks and bad input."""

from pathlib import Path

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.io import read_image
from bakeshop.sphere import (
    LAYOUT_NAMES,
    cache_info,
    clear_caches,
    cube_to_view,
    layout,
    remap,
    remap_shape,
    rotation_matrix,
    sample,
)
from tests.files import DATA
from tests.tolerances import (
    FLOAT32_WEIGHTS,
    SPHERE_AREA_ENERGY_RTOL,
    SPHERE_AREA_LINEAR_ATOL,
    SPHERE_AREA_POLAR_RRMS,
    SPHERE_AREA_VS_BRUTE_FORCE_RRMS,
    SPHERE_BILINEAR_SMOOTH_ATOL,
    SPHERE_LATLONG_CUBE_ROUND_TRIP_ATOL,
    SPHERE_NEAREST_SMOOTH_ATOL,
    SPHERE_SUPERSAMPLE_VS_BRUTE_FORCE_RRMS,
)


def smooth(d):
    """A smooth RGB environment: every channel has curvature in every direction."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([1 + 0.5 * x + 0.3 * y - 0.2 * z + 0.4 * x * y, np.exp(z), 1 + y * y], -1)


def environment(name, size, fn=smooth):
    """fn evaluated at the texel centres of layout ``name`` (invalid texels 0)."""
    lay = layout(name)
    shape = lay.shape(size)
    dirs, valid = lay.directions(shape)
    img = fn(dirs).astype(np.float32)
    img[~valid] = 0
    return img


SOURCES = {  # sizes giving texels of about 0.3 degrees
    "latlong": 600,
    "cube": 300,
    "angular": 1200,
    "mirrorball": 1200,
    "mirrorball-physical": 1200,
    "octahedral": 600,
    "dual-paraboloid": 600,
    "cross-vertical": 300,
    "openexr-latlong": 600,
    "openexr-cube": 300,
}


@pytest.mark.parametrize("src", SOURCES)
@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
def test_smooth_environment_into_every_layout(src, filter):
    img = environment(src, SOURCES[src])
    bound = SPHERE_BILINEAR_SMOOTH_ATOL if filter == "bilinear" else SPHERE_NEAREST_SMOOTH_ATOL
    for dst in LAYOUT_NAMES:
        d = layout(dst)
        out = remap(img, src, dst, 24, filter=filter)
        dirs, valid = d.directions(d.shape(24))
        assert out.shape == d.shape(24) + (3,) and out.dtype == np.float32
        err = np.abs(out - smooth(dirs)).max(axis=-1)
        if src.startswith("mirrorball"):
            # the mirror ball squeezes a hemisphere into its rim: only the neighbourhood of the
            # rim's direction (+Z; -Z for the physical variant) is poorly sampled (a physical
            # limit of the photograph, not of the filter)
            rim = -1 if src == "mirrorball-physical" else 1
            valid = valid & (rim * dirs[..., 2] < 0.9)
        assert err[valid].max() < bound, (dst, err[valid].max())
        assert np.all(out[~d.directions(d.shape(24))[1]] == 0)


def checker(d):
    """1 or 0 on 30 x 30 degree cells of longitude and colatitude (edges on texel edges of a
    720 x 360 latlong)."""
    phi = np.arctan2(d[..., 0], -d[..., 2])
    theta = np.arctan2(np.hypot(d[..., 0], d[..., 2]), d[..., 1])
    cell = np.floor(phi / (np.pi / 6)) + np.floor(theta / (np.pi / 6))
    return (cell % 2)[..., None].astype(np.float32)


def distance_to_cell_edge(d):
    phi = np.arctan2(d[..., 0], -d[..., 2])
    theta = np.arctan2(np.hypot(d[..., 0], d[..., 2]), d[..., 1])
    step = np.pi / 6
    dp = np.abs((phi + step / 2) % step - step / 2) * np.sin(theta)
    dt = np.abs((theta + step / 2) % step - step / 2)
    return np.minimum(dp, dt)


@pytest.mark.parametrize("dst", LAYOUT_NAMES)
def test_checker_of_known_directions(dst):
    """Cell edges lie on source texel edges, so nearest is exact everywhere, and bilinear is
    exact wherever the direction is more than one source texel from an edge."""
    src = environment("latlong", 360, checker)
    d = layout(dst)
    shape = d.shape(32)
    dirs, valid = d.directions(shape)
    truth = checker(dirs)
    edge = distance_to_cell_edge(dirs)
    near = remap(src, "latlong", dst, 32, filter="nearest")
    ok = valid & (edge > 1e-9)
    np.testing.assert_array_equal(near[ok], truth[ok])
    bil = remap(src, "latlong", dst, 32, filter="bilinear")
    far = valid & (edge > 1.5 * np.pi / 360)
    np.testing.assert_allclose(bil[far], truth[far], atol=1e-6)


def test_latlong_cube_latlong_round_trip():
    """latlong 512 x 256 -> cube 128 (about the same texel count) -> latlong 512 x 256."""
    img = environment("latlong", 256)
    cube = remap(img, "latlong", "cube", 128)
    back = remap(cube, "cube", "latlong", 256)
    err = np.abs(back - img)
    assert err.max() < SPHERE_LATLONG_CUBE_ROUND_TRIP_ATOL


# --- seams ---------------------------------------------------------------------------------------


def test_cube_corner_is_the_mean_of_three_faces():
    """At a cube corner, bilinear filtering uses the mean of the three corner texels, as
    OpenGL's seamless cube map filtering does."""
    rng = np.random.default_rng(0)
    s = 8
    cube = rng.random((6, s, s, 2)).astype(np.float32)
    v = sample(cube, "cube", np.array([1.0, 1.0, 1.0]))
    # (x, y, z) = (+, +, +): +X texel (row 0, col 0), +Y (row S-1, col S-1), +Z (row 0, col S-1)
    expected = (cube[0, 0, 0] + cube[2, s - 1, s - 1] + cube[4, 0, s - 1]) / 3
    np.testing.assert_allclose(v, expected, rtol=1e-6)


def test_cube_edge_blends_both_faces():
    """A direction on the +X/+Z edge halfway between texel rows blends the two faces' edge
    texels 50/50 (and never clamps to one face)."""
    s = 4
    cube = np.zeros((6, s, s), np.float32)
    cube[0] = 1.0  # +X
    cube[4] = 3.0  # +Z
    v = sample(cube, "cube", np.array([1.0, 0.0, 1.0]))
    assert v == pytest.approx(2.0, rel=1e-6)


def test_latlong_seam_and_poles():
    h, w = 16, 32
    img = np.arange(h * w, dtype=np.float32).reshape(h, w)
    # the back (+Z) seam, halfway between the last and first columns
    theta = np.pi * 5.5 / h
    d = np.array([0.0, np.cos(theta), np.sin(theta)])
    assert sample(img, "latlong", d) == pytest.approx((img[5, 0] + img[5, -1]) / 2)
    # at the north pole, every texel of row 0 and its opposite meridian meet
    s = environment("latlong", 64)
    for pole in ([0.0, 1.0, 0.0], [0.0, -1.0, 0.0]):
        p = np.array(pole)
        np.testing.assert_allclose(sample(s, "latlong", p), smooth(p), atol=2e-3)


def test_octahedral_edges_fold():
    """Bilinear samples next to the map's folded edges and corners (the lower hemisphere near
    the x = 0 and z = 0 planes, and -Y) are as accurate as anywhere else on the map."""
    img = environment("octahedral", 64)
    rng = np.random.default_rng(2)
    d = rng.normal(size=(200000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    err = np.abs(sample(img, "octahedral", d) - smooth(d)).max(axis=-1)
    ad = np.abs(d)
    edge = (d[:, 1] < 0) & ((ad[:, 0] < 0.03) | (ad[:, 2] < 0.03) | (ad[:, 1] > 0.97))
    assert edge.sum() > 1000
    assert err[edge].max() < 1.5 * err[~edge].max()


# --- rotation, masks, types, errors --------------------------------------------------------------


def test_rotation_moves_what_was_at_d_to_R_d():
    img = environment("latlong", 256)
    for angles in [(90, 0, 0), (0, 90, 0), (0, 0, 90), (30, -20, 75)]:
        r = rotation_matrix(*angles)
        out = remap(img, "latlong", "cube", 32, rotation=angles)
        dirs, _ = layout("cube").directions((6, 32, 32))
        np.testing.assert_allclose(out, smooth(dirs @ r), atol=SPHERE_BILINEAR_SMOOTH_ATOL)
        np.testing.assert_array_equal(out, remap(img, "latlong", "cube", 32, rotation=r))


def test_rotation_axes_and_signs():
    r = rotation_matrix(yaw=90)
    np.testing.assert_allclose(r @ [0, 0, -1], [-1, 0, 0], atol=1e-15)  # forward turns left
    np.testing.assert_allclose(rotation_matrix(pitch=90) @ [0, 0, -1], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(rotation_matrix(roll=90) @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    # a bright spot ahead ends up on the left after yaw = 90
    img = np.zeros((64, 128), np.float32)
    img[30:34, 62:66] = 1  # around -Z
    out = remap(img, "latlong", "latlong", rotation=(90, 0, 0))
    assert out[30:34, 30:34].min() > 0.2 and out[:, 60:68].max() == 0


def test_disks_write_zero_outside_and_alpha_follows():
    img = np.ones((64, 128, 4), np.float32)
    for dst in ("angular", "mirrorball", "dual-paraboloid", "cross-vertical", "cross-horizontal"):
        d = layout(dst)
        out = remap(img, "latlong", dst, 32)
        _, valid = d.directions(d.shape(32))
        assert np.all(out[~valid] == 0)
        np.testing.assert_allclose(out[valid], 1, rtol=FLOAT32_WEIGHTS)


def test_mirrorball_rim_has_no_nan():
    img = environment("mirrorball", 64)
    for dst in ("latlong", "cube", "mirrorball", "angular"):
        assert np.all(np.isfinite(remap(img, "mirrorball", dst, 32)))
    d, v = layout("mirrorball").directions((64, 64))
    assert np.all(np.isfinite(d))


def test_types_and_channel_axis():
    img = environment("latlong", 32)
    assert remap(img[..., 0], "latlong", "cube", 8).shape == (6, 8, 8)
    assert remap(img.astype(np.float64), "latlong", "cube", 8).dtype == np.float64
    assert remap((img * 100).astype(np.uint16), "latlong", "cube", 8).dtype == np.float32
    cube = remap(img, "latlong", "cube", 8)
    cross = remap(img, "latlong", "cross-vertical", 8)
    np.testing.assert_array_equal(cross, cube_to_view(cube, "cross-vertical"))
    # default: about the same texel count, as a power-of-two face (sqrt(64 * 32 / 6) = 18.5)
    assert remap(img, "latlong", "cube").shape == (6, 16, 16, 3)
    for texels, edge in ((6 * 296**2, 256), (6 * 326**2, 256), (6 * 400**2, 512), (1, 1)):
        for name in ("cube", "cross-vertical", "strip-horizontal"):
            assert layout(name).default_size(texels) == edge
    assert remap_shape("latlong", (512, 1024), "cross-vertical") == (1024, 768)
    dirs = np.random.default_rng(0).normal(size=(4, 5, 3))
    assert sample(img, "latlong", dirs).shape == (4, 5, 3)
    assert sample(img[..., 0], "latlong", dirs[0, 0]).shape == ()


def test_sample_agrees_with_remap():
    img = environment("octahedral", 64)
    d = layout("angular")
    dirs, valid = d.directions((20, 20))
    np.testing.assert_array_equal(
        sample(img, "octahedral", dirs)[valid], remap(img, "octahedral", "angular", 20)[valid]
    )


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        ((np.zeros((8, 16)), "latlong", "cube"), {"filter": "cubic"}, "filter"),
        ((np.zeros((8, 16)), "latlong", "spherical"), {}, "layout"),
        ((np.zeros((8, 10)), "angular", "cube"), {}, "square"),
        ((np.zeros((6, 8, 9, 3)), "cube", "latlong"), {}, "cube"),
        ((np.zeros(5), "latlong", "cube"), {}, "shape"),
        ((np.zeros((8, 16)), "latlong", "cube"), {"rotation": np.ones((3, 3))}, "orthogonal"),
        ((np.zeros((8, 16)), "latlong", "cube"), {"rotation": (1, 2)}, "rotation"),
        ((np.zeros((8, 16)), "latlong", "octahedral"), {"size": 7}, "even"),
    ],
)
def test_bad_arguments(args, kwargs, match):
    with pytest.raises(ArgumentError, match=match):
        remap(*args, **kwargs)


def test_bad_directions():
    with pytest.raises(ArgumentError, match="directions"):
        sample(np.zeros((8, 16)), "latlong", np.zeros((4, 2)))


# --- the area filter ---------------------------------------------------------------------------


def energy(image, name):
    lay = layout(name)
    omega = lay.solid_angles(image.shape[: 3 if lay.cubic else 2])
    return (image.astype(np.float64) * omega[..., None]).reshape(-1, image.shape[-1]).sum(axis=0)


@pytest.fixture(scope="module")
def probe():
    from bakeshop.io import read_image

    return read_image(Path(__file__).parents[2] / "bakeshop" / "data" / "default_probe.hdr")


@pytest.mark.parametrize(
    ("dst", "size", "rtol"),
    [
        ("cube", 64, SPHERE_AREA_ENERGY_RTOL),
        ("cube", 16, SPHERE_AREA_ENERGY_RTOL),
        ("latlong", 64, SPHERE_AREA_ENERGY_RTOL),
        ("angular", 128, SPHERE_AREA_ENERGY_RTOL),
        ("octahedral", 64, SPHERE_AREA_ENERGY_RTOL),
        ("dual-paraboloid", 64, SPHERE_AREA_ENERGY_RTOL),
        ("cross-vertical", 32, SPHERE_AREA_ENERGY_RTOL),
        ("strip-horizontal", 32, SPHERE_AREA_ENERGY_RTOL),
        ("mirrorball", 128, SPHERE_AREA_ENERGY_RTOL),
        ("mirrorball", 64, SPHERE_AREA_ENERGY_RTOL),
        ("mirrorball-physical", 64, SPHERE_AREA_ENERGY_RTOL),
        ("openexr-latlong", 64, SPHERE_AREA_ENERGY_RTOL),
        ("openexr-cube", 48, SPHERE_AREA_ENERGY_RTOL),
    ],
)
def test_area_filter_preserves_the_energy_of_a_real_probe(probe, dst, size, rtol):
    """The default probe (a sun 10^5 times the sky in one texel) downsampled into every layout:
    sum of radiance x solid angle is preserved."""
    out = remap(probe, "latlong", dst, size, filter="area")
    np.testing.assert_allclose(energy(out, dst), energy(probe, "latlong"), rtol=rtol)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("dst", "size"),
    [("angular", 700), ("angular", 512), ("mirrorball", 700), ("octahedral", 700),
     ("dual-paraboloid", 700), ("cube", 300)],
)  # fmt: skip
def test_area_filter_preserves_the_energy_of_a_one_texel_sun_where_the_output_is_finer(
    probe, dst, size
):
    """Regression: where destination texels are smaller than the source's (an angular map's
    and a mirror ball's rim, a cube's corners, ...), each source texel's energy is shared
    exactly among the texels it covers; a bilinear fallback there aliased the one-texel sun
    (+7% at angular 700, -4.5% at cube 300)."""
    out = remap(probe, "latlong", dst, size, filter="area")
    np.testing.assert_allclose(
        energy(out, dst), energy(probe, "latlong"), rtol=SPHERE_AREA_ENERGY_RTOL
    )


def brute_force_area_average(img, src, dst, size, k, rotation=None):
    """Each output texel of ``dst`` cut into k x k sub-texels, each looking the (piecewise
    constant) source up by nearest (at R^T d when the environment is rotated by R), averaged
    by their solid angles: (means, valid)."""
    lay = layout(dst)
    shape, fine = lay.shape(size), lay.shape(size * k)
    dirs, _ = lay.directions(fine)
    if rotation is not None:
        dirs = dirs @ rotation_matrix(*rotation)
    omega = lay.solid_angles(fine)
    energy = sample(img, src, dirs, filter="nearest") * omega[..., None]
    blocks = (6, size, k, size, k) if lay.cubic else (shape[0], k, shape[1], k)
    axes = (2, 4) if lay.cubic else (1, 3)
    weight = omega.reshape(blocks).sum(axis=axes)
    valid = weight > 0
    return energy.reshape(blocks + (img.shape[-1],)).sum(axis=axes)[valid] / weight[valid][
        :, None
    ], valid


@pytest.mark.parametrize(
    ("dst", "size"),
    [
        ("cube", 64),
        ("angular", 128),
        ("angular-physical", 128),
        pytest.param("octahedral", 128, marks=pytest.mark.slow),
    ],
)
def test_area_filter_is_the_area_average_of_a_brute_force_supersampling(probe, dst, size):
    """Reference: every output texel cut into 16 x 16 sub-texels, each looking the (piecewise
    constant) source up by nearest, averaged by their solid angles. The area filter is close
    to it; bilinear point sampling is not (it aliases the grass and the clouds)."""
    img = np.minimum(probe[..., :3], 50).astype(np.float32)
    ref, valid = brute_force_area_average(img, "latlong", dst, size, 16)

    def rrms(out):
        return np.sqrt(np.mean((out[valid] - ref) ** 2) / np.mean(ref**2))

    area = rrms(remap(img, "latlong", dst, size, filter="area"))
    bilinear = rrms(remap(img, "latlong", dst, size, filter="bilinear"))
    assert area < SPHERE_AREA_VS_BRUTE_FORCE_RRMS and area < bilinear / 2.5


@pytest.mark.parametrize(
    ("src", "dst", "size"),
    [("latlong", "cube", 96), ("latlong", "cube", 128), ("cube", "latlong", 192)],
)
def test_area_filter_near_one_to_one_is_the_area_average(probe, src, dst, size):
    """Where output texels are about as large as the source's, most source texels are cut into
    2-16 parts (deposited through their affine images, ``_window_taps``): the filter is still
    the brute-force area average (measured 6.6e-3 to 8.6e-3 RRMS, bilinear 1.3e-2 to 2.3e-2)."""
    img = np.minimum(probe[..., :3], 50).astype(np.float32)
    img = remap(img, "latlong", src, 128 if src == "cube" else 256, filter="area")
    ref, valid = brute_force_area_average(img, src, dst, size, 12)

    def rrms(out):
        return np.sqrt(np.mean((out[valid] - ref) ** 2) / np.mean(ref**2))

    area = rrms(remap(img, src, dst, size, filter="area"))
    assert area < SPHERE_AREA_VS_BRUTE_FORCE_RRMS / 2
    assert area < rrms(remap(img, src, dst, size, filter="bilinear")) / 1.4


@pytest.mark.parametrize(
    ("face", "j", "i", "rotation"),
    [(0, 230, 352, None), (2, 256, 256, None), (2, 100, 300, None), (3, 3, 500, None),
     (4, 400, 10, (30, 50, 10)), (1, 60, 200, (30, 50, 10))],
)  # fmt: skip
def test_a_cube_texels_overlaps_with_a_latlongs_texels(face, j, i, rotation):
    """A 512^2 cube's texel into a 2048x1024 latlong (``latlong_taps``, cube_latlong.hpp: at the
    equator's side, round a pole, beside a pole, rotated) against 400 x 400 points over the
    texel (one at random in each cell of a 400 x 400 grid), each weighted by its solid angle
    (|d_axis|^3 on a face) and binned by the latlong texel it falls in: every overlap within
    3e-4 of the texel's solid angle (measured 2e-5 to 1e-4, and 6e-6 to 2e-5 with 1600 x 1600
    points: the points' own error)."""
    from bakeshop.sphere._kinds import CUBE
    from bakeshop.sphere._native import directions_at, latlong_taps

    rot = np.eye(3) if rotation is None else rotation_matrix(*rotation)
    omega = layout("cube").solid_angles((6, 512, 512))[face, j, i]
    taps, weights = np.zeros(8192, np.int32), np.zeros(8192, np.float32)
    n = latlong_taps(CUBE, 512, 512, face, i, j, rot, 1024, 2048, omega, 0, 8192, taps, weights)
    k = 400
    jitter = np.random.default_rng(0).random((2, k, k))
    steps = np.arange(k) / k
    coords = np.stack(np.broadcast_arrays(face, i + (steps[None, :] + jitter[0] / k),
                                          j + (steps[:, None] + jitter[1] / k)), -1)  # fmt: skip
    dirs = np.empty((k * k, 3))
    directions_at(CUBE, 512, 512, coords.reshape(-1, 3).astype(np.float64), dirs)
    solid = np.abs(dirs).max(axis=1) ** 3
    x, y, z = (dirs @ rot.T).T
    column = np.floor((np.arctan2(x, -z) / (2 * np.pi) + 0.5) * 2048).astype(int) % 2048
    row = np.minimum(np.floor(np.arctan2(np.hypot(x, z), y) / np.pi * 1024).astype(int), 1023)
    reference = np.bincount(row * 2048 + column, solid, 1024 * 2048) * (omega / solid.sum())
    got = np.zeros(1024 * 2048)
    got[taps[:n]] = weights[:n]
    assert n > 0 and np.all(np.diff(taps[:n]) > 0)
    assert np.abs(got - reference).max() < 3e-4 * omega


@pytest.mark.parametrize("rotation", [None, (30, 50, 10)])
def test_area_filter_from_a_cube_around_a_latlongs_poles_is_the_area_average(rotation):
    """Around a latlong's poles a cube texel covers a few rows and tens of columns; its exact
    overlaps (``src/sphere/cube_latlong.hpp``) make the filter the area average there: noise
    from a 64^2 cube into a 128x64 latlong, the three rows at each pole against 64 x 64
    nearest lookups per output texel (see SPHERE_AREA_POLAR_RRMS)."""
    img = np.random.default_rng(1).random((6, 64, 64, 1)).astype(np.float32)
    ref, valid = brute_force_area_average(img, "cube", "latlong", 64, 64, rotation)
    out = remap(img, "cube", "latlong", 64, filter="area", rotation=rotation)
    rows = np.broadcast_to(np.arange(64)[:, None], (64, 128))[valid]
    polar = (rows < 3) | (rows >= 61)
    error = out[valid][polar] - ref[polar]
    assert np.sqrt(np.mean(error**2) / np.mean(ref[polar] ** 2)) < SPHERE_AREA_POLAR_RRMS


@pytest.mark.parametrize(
    ("dst", "size"),
    [("cube", 256), ("cube", 128), pytest.param("octahedral", 512, marks=pytest.mark.slow)],
)
def test_area_filter_keeps_a_linear_function_where_it_is(dst, size):
    """The balanced weights stay centred: a linear function of direction comes out as its
    value at the output texel centres (to a fraction of its change across a texel)."""

    def f(d):
        return 1 + 0.5 * d[..., 0] + 0.3 * d[..., 1] - 0.2 * d[..., 2]

    src_dirs, _ = layout("latlong").directions((512, 1024))
    out = remap(f(src_dirs)[..., None].astype(np.float32), "latlong", dst, size, filter="area")
    dirs, valid = layout(dst).directions(out.shape[:-1])
    np.testing.assert_allclose(out[..., 0][valid], f(dirs)[valid], atol=SPHERE_AREA_LINEAR_ATOL)


@pytest.mark.slow
@pytest.mark.parametrize("row", [0, 1, 3])
def test_area_filter_preserves_the_energy_of_a_sun_at_the_zenith(row):
    """A one-texel sun in a latlong's top rows (noon in the tropics), where the texels are thin
    wedges meeting at the pole and where the balancing converges slowest."""
    img = np.full((512, 1024, 1), 0.1, np.float32)
    omega = layout("latlong").solid_angles(img.shape[:2])
    img[row, 100] = 1e5 * omega[256, 0] / omega[row, 100]
    for dst, size in [("cube", 256), ("octahedral", 256), ("angular", 300), ("mirrorball", 256)]:
        out = remap(img, "latlong", dst, size, filter="area")
        np.testing.assert_allclose(
            energy(out, dst), energy(img, "latlong"), rtol=SPHERE_AREA_ENERGY_RTOL
        )


@pytest.mark.parametrize(
    "src", ["latlong", "cube", "octahedral", "angular", "openexr-latlong", "openexr-cube"]
)
def test_area_filter_preserves_energy_of_noise_with_rotation(src):
    rng = np.random.default_rng(4)
    lay = layout(src)
    shape = lay.shape(128 if src.endswith("latlong") else 96)
    img = (rng.random(shape + (2,)) ** 4).astype(np.float32)
    img[~lay.directions(shape)[1]] = 0
    for dst, size, rtol in [
        ("cube", 16, SPHERE_AREA_ENERGY_RTOL),
        ("latlong", 24, SPHERE_AREA_ENERGY_RTOL),
        ("octahedral", 24, SPHERE_AREA_ENERGY_RTOL),
        ("mirrorball", 32, SPHERE_AREA_ENERGY_RTOL),
        ("openexr-cube", 16, SPHERE_AREA_ENERGY_RTOL),
    ]:
        out = remap(img, src, dst, size, filter="area", rotation=(30, 20, 10))
        np.testing.assert_allclose(energy(out, dst), energy(img, src), rtol=rtol)


@pytest.mark.parametrize(
    "dst",
    ["cube", "latlong", "angular", "mirrorball", "dual-paraboloid", "openexr-latlong",
     "openexr-cube"],
)  # fmt: skip
def test_area_filter_keeps_a_uniform_environment_uniform(dst):
    """Down and up: the filter is a weighted mean, so a constant stays exactly constant."""
    for size in (8, 200):
        out = remap(np.full((64, 128, 3), 2.5, np.float32), "latlong", dst, size, filter="area")
        _, valid = layout(dst).directions(out.shape[:-1])
        np.testing.assert_allclose(out[valid], 2.5, rtol=1e-6)


def test_area_filter_antialiases_and_becomes_bilinear_when_upsampling():
    # a 2-texel checker: bilinear point samples alias to anything in [0, 1]; the area mean is 1/2
    h = 512
    j, i = np.mgrid[0:h, 0 : 2 * h]
    fine = (((i // 2) + (j // 2)) % 2).astype(np.float32)
    area = remap(fine, "latlong", "cube", 16, filter="area")
    bil = remap(fine, "latlong", "cube", 16, filter="bilinear")
    assert np.abs(area - 0.5).max() < 0.05 < np.abs(bil - 0.5).max()
    # upsampling (every source texel over 4/3 destination texels long along both its axes):
    # plain bilinear
    coarse = environment("cube", 16)
    up_area = remap(coarse, "cube", "cube", 48, filter="area", rotation=(10, 5, 0))
    up_bil = remap(coarse, "cube", "cube", 48, filter="bilinear", rotation=(10, 5, 0))
    np.testing.assert_array_equal(up_area, up_bil)


def test_nan_and_infinite_directions_give_nan():
    img = environment("cube", 8)
    d = np.array([[np.nan, 0, 1], [0, np.inf, 0], [1, 0, 0]])
    for filter in ("nearest", "bilinear"):
        out = sample(img, "cube", d, filter=filter)
        assert np.isnan(out[:2]).all() and np.isfinite(out[2]).all()


def test_area_filter_plan_is_cached_per_geometry_and_the_filter_is_linear():
    """The area filter's geometry is cached: a second image of the same shape reuses it and
    gets what a fresh plan gives; the filter is linear (a cached plan cannot hold image data)."""
    rng = np.random.default_rng(7)
    a = rng.random((96, 192, 3)).astype(np.float32)
    b = (rng.random((96, 192, 3)) ** 3).astype(np.float32)
    args = ("latlong", "cube", 12)
    first = remap(a, *args, filter="area", rotation=(20, 10, 0))
    hits = cache_info()["area filter matrices"]["hits"]
    mixed = remap(a + 2 * b, *args, filter="area", rotation=(20, 10, 0))
    assert cache_info()["area filter matrices"]["hits"] == hits + 1
    only_b = remap(b, *args, filter="area", rotation=(20, 10, 0))
    np.testing.assert_allclose(mixed, first + 2 * only_b, rtol=1e-5, atol=1e-6)
    clear_caches()
    np.testing.assert_array_equal(remap(b, *args, filter="area", rotation=(20, 10, 0)), only_b)


def test_area_balancing_makes_rows_means_and_columns_carry_their_solid_angle():
    """Sinkhorn balancing of a random sparse positive matrix, checked densely: every row sums
    to 1 and sum_q omega_out[q] M[q, p] = omega_in[p]."""
    from bakeshop.sphere import area

    rng = np.random.default_rng(3)
    m, n = 40, 60
    dense = rng.random((m, n)) * (rng.random((m, n)) < 0.3)
    dense[np.arange(m), rng.integers(0, n, m)] += 0.5  # no empty row
    dense[rng.integers(0, m, n), np.arange(n)] += 0.5  # no empty column
    omega_out = rng.random(m) + 0.5
    omega_in = rng.random(n) + 0.5
    omega_in *= omega_out.sum() / omega_in.sum()
    rows, cols = np.nonzero(dense)
    indptr = np.searchsorted(rows, np.arange(m + 1)).astype(np.int64)
    values = dense[rows, cols].astype(np.float32)
    err = area._balance(indptr, cols.astype(np.int32), values, omega_out, omega_in)
    balanced = np.zeros((m, n))
    balanced[rows, cols] = values
    np.testing.assert_allclose(balanced.sum(axis=1), 1, rtol=1e-6)
    np.testing.assert_allclose(omega_out @ balanced, omega_in, rtol=2 * area.AREA_BALANCE_RTOL)
    assert err <= area.AREA_BALANCE_RTOL


def test_area_plan_cache_keeps_recent_plans_within_its_byte_budget():
    from bakeshop.sphere._cache import ByteBoundedCache

    calls = []
    cache = ByteBoundedCache("test", 100)
    for n in (40, 50, 40, 30, 50, 500, 500):
        cache.cached((n,), lambda n=n: calls.append(n) or (np.zeros(n, np.uint8),))
    # 40 and 50 fit together; 30 evicts the least recent (50); 500 alone exceeds the budget
    # but the newest result stays
    assert calls == [40, 50, 30, 50, 500] and cache.hits == 2
    assert list(cache.entries) == [(500,)]


@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
def test_first_remap_applies_the_plan_as_a_cached_one_does(filter):
    """A first conversion applies its plan while building it; a cached one gathers: equal."""
    for src, dst in [("latlong", "cube"), ("cube", "latlong"), ("mirrorball", "octahedral")]:
        img = environment(src, 20)
        clear_caches()
        first = remap(img, src, dst, 24, filter=filter, rotation=(15, 5, 0))
        hits = cache_info()["remap plans"]["hits"]
        assert cache_info()["remap plans"]["entries"] == 1
        np.testing.assert_array_equal(
            remap(img, src, dst, 24, filter=filter, rotation=(15, 5, 0)), first
        )
        assert cache_info()["remap plans"]["hits"] == hits + 1


@pytest.mark.parametrize("filter", ["nearest", "bilinear"])
@pytest.mark.parametrize("view", ["cross-vertical", "cross-horizontal", "strip-vertical"])
def test_a_cube_picture_gathered_straight_from_its_own_plan_is_the_arranged_cube(filter, view):
    """A cached conversion to a cross or strip gathers into the picture through a reordered
    plan: it equals the cube converted and then arranged, unused squares zero."""
    img = environment("mirrorball", 40)
    clear_caches()
    cube = remap(img, "mirrorball", "cube", 16, filter=filter)
    first = remap(img, "mirrorball", view, 16, filter=filter)
    hits = cache_info()["remap plans"]["hits"]
    cached = remap(img, "mirrorball", view, 16, filter=filter)
    assert cache_info()["remap plans"]["hits"] == hits + 1
    np.testing.assert_array_equal(first, cube_to_view(cube, view))
    np.testing.assert_array_equal(cached, first)


def test_area_filter_into_a_cube_picture_is_the_arranged_cube():
    img = (np.random.default_rng(5).random((64, 128, 3)) ** 3).astype(np.float32)
    cube = remap(img, "latlong", "cube", 12, filter="area")
    for view in ("cross-horizontal", "strip-horizontal"):
        np.testing.assert_array_equal(
            remap(img, "latlong", view, 12, filter="area"), cube_to_view(cube, view)
        )


# --- large sources: exact reductions, supersampling, plans applied in parts ------------------


@pytest.fixture
def supersampled(monkeypatch):
    """The supersampled area filter, which large sources get, forced on small ones."""
    from bakeshop.sphere import area

    monkeypatch.setattr(area, "AREA_MATRIX_TEXELS", 0)
    clear_caches()
    yield
    clear_caches()


@pytest.mark.parametrize(("dst", "size"), [("cube", 64), ("cube", 16), ("angular", 128),
                                           ("octahedral", 64), ("mirrorball", 64),
                                           ("cross-vertical", 32)])  # fmt: skip
def test_supersampling_preserves_the_energy_of_a_real_probe(probe, supersampled, dst, size):
    """The default probe's sun is one texel 10^5 times the sky: bilinear samples as dense as
    the texels would move its energy by ~4%; the bright texels' excess is deposited exactly."""
    out = remap(probe, "latlong", dst, size, filter="area")
    np.testing.assert_allclose(
        energy(out, dst), energy(probe, "latlong"), rtol=SPHERE_AREA_ENERGY_RTOL
    )


@pytest.mark.parametrize(("dst", "size"), [("cube", 64), ("angular", 128), ("octahedral", 128)])
def test_supersampling_is_the_area_average_of_a_brute_force_supersampling(probe, supersampled, dst,
                                                                          size):  # fmt: skip
    img = np.minimum(probe[..., :3], 50).astype(np.float32)
    ref, valid = brute_force_area_average(img, "latlong", dst, size, 16)

    def rrms(out):
        return np.sqrt(np.mean((out[valid] - ref) ** 2) / np.mean(ref**2))

    area = rrms(remap(img, "latlong", dst, size, filter="area"))
    bilinear = rrms(remap(img, "latlong", dst, size, filter="bilinear"))
    assert area < SPHERE_SUPERSAMPLE_VS_BRUTE_FORCE_RRMS and area < bilinear / 2.5


@pytest.mark.parametrize("size", [256, 200])
def test_supersampling_at_1_to_1_sizes_is_the_area_average(supersampled, size):
    """Regression: where the output is as fine as the source (4096x2048 -> 6x1024^2 is
    supersampled), one sample an output texel sent each bright texel's energy to the few output
    texels that sampled it, or to the wrong ones (35 % RMS off the area average). The quarry
    probe (its sun clipped) into faces as fine as its texels, against the brute-force
    average of 8 x 8 nearest lookups per output texel."""
    img = np.minimum(read_image(DATA / "quarry_01_1k.hdr")[..., :3], 50).astype(np.float32)
    ref, valid = brute_force_area_average(img, "latlong", "cube", size, 8)
    out = remap(img, "latlong", "cube", size, filter="area")
    assert np.sqrt(np.mean((out[valid] - ref) ** 2) / np.mean(ref**2)) < (
        SPHERE_SUPERSAMPLE_VS_BRUTE_FORCE_RRMS
    )
    np.testing.assert_allclose(energy(out, "cube"), energy(img, "latlong"),
                               rtol=SPHERE_AREA_ENERGY_RTOL)  # fmt: skip


def test_supersampling_keeps_a_uniform_environment_uniform_and_rotates(probe, supersampled):
    for dst in ("cube", "angular", "octahedral"):
        out = remap(np.full((256, 512, 3), 2.5, np.float32), "latlong", dst, 16, filter="area")
        _, valid = layout(dst).directions(out.shape[:-1])
        np.testing.assert_allclose(out[valid], 2.5, rtol=1e-6)
    out = remap(probe, "latlong", "cube", 32, filter="area", rotation=(30, 20, 10))
    np.testing.assert_allclose(
        energy(out, "cube"), energy(probe, "latlong"), rtol=SPHERE_AREA_ENERGY_RTOL
    )


@pytest.mark.parametrize("row", [0, 1, 3, 200])
def test_supersampling_deposits_a_one_texel_sun_exactly(supersampled, row):
    """Anywhere, the pole's wedges included: the sun's energy lands near its direction."""
    img = np.full((256, 512, 1), 0.1, np.float32)
    omega = layout("latlong").solid_angles(img.shape[:2])
    img[row, 100] = 1e5 * omega[128, 0] / omega[row, 100]
    for dst, size in [("cube", 32), ("octahedral", 64)]:
        out = remap(img, "latlong", dst, size, filter="area")
        np.testing.assert_allclose(
            energy(out, dst), energy(img, "latlong"), rtol=SPHERE_AREA_ENERGY_RTOL
        )


def test_the_area_filter_supersamples_only_beyond_the_matrix_size():
    from bakeshop.sphere import area

    assert area.supersampling("latlong", (1024, 2048), "cube", (6, 256, 256)) == 0
    assert area.supersampling("latlong", (4096, 8192), "cube", (6, 256, 256)) == 9
    assert area.supersampling("latlong", (4096, 8192), "cube", (6, 2048, 2048)) == 3  # 1:1
    # the grid of samples stays a layout's shape (2^29 texels): 2, then 1 a side
    assert area.supersampling("latlong", (8192, 16384), "cube", (6, 4096, 4096)) == 2
    assert area.supersampling("latlong", (16384, 32768), "cube", (6, 8192, 8192)) == 1
    assert area.supersampling("latlong", (4096, 8192), "cube", (6, 4096, 4096)) == 0  # up


def test_latlong_to_latlong_area_is_the_exact_solid_angle_weighted_box():
    """Reference: each output texel the solid-angle-weighted mean of the source texels its
    footprint covers, with the covered fractions of the boundary texels (numpy, float64)."""
    from bakeshop.image import area_weights

    rng = np.random.default_rng(2)
    img = (rng.random((30, 60, 2)) ** 3).astype(np.float32)
    img[3, 7] = 1e4
    out = remap(img, "latlong", "latlong", (25, 12), filter="area")
    c = np.cos(np.pi * np.arange(13) / 12)
    rows = np.zeros((12, 30))
    for i in range(12):  # exact overlap of input rows with output row i, in solid angle
        for k in range(30):
            lo, hi = max(k / 30, i / 12), min((k + 1) / 30, (i + 1) / 12)
            if hi > lo:
                rows[i, k] = np.cos(np.pi * lo) - np.cos(np.pi * hi)
        rows[i] /= c[i] - c[i + 1]
    cols = area_weights(60, 25).toarray()
    ref = np.einsum("ik,jl,klc->ijc", rows, cols, img.astype(np.float64))
    np.testing.assert_allclose(out, ref, rtol=1e-6)
    np.testing.assert_allclose(energy(out, "latlong"), energy(img, "latlong"), rtol=1e-6)


def test_cube_to_smaller_cube_and_cross_area_is_the_exact_solid_angle_weighted_block_mean():
    rng = np.random.default_rng(3)
    cube = rng.random((6, 12, 12, 3)).astype(np.float32)
    omega = layout("cube").solid_angles((6, 12, 12))
    blocks = (cube * omega[..., None]).reshape(6, 4, 3, 4, 3, 3).sum((2, 4))
    ref = blocks / omega.reshape(6, 4, 3, 4, 3).sum((2, 4))[..., None]
    np.testing.assert_allclose(remap(cube, "cube", "cube", 4, filter="area"), ref, rtol=1e-6)
    cross = remap(cube, "cube", "cross-vertical", 4, filter="area")
    from bakeshop.sphere import cube_to_view

    np.testing.assert_allclose(
        cross, cube_to_view(ref.astype(np.float32), "cross-vertical"), rtol=1e-6
    )


@pytest.mark.parametrize("filter", ["bilinear", "nearest"])
def test_a_large_plan_applied_in_parts_equals_the_whole_and_is_not_kept(monkeypatch, filter):
    from bakeshop.sphere import _plans

    rng = np.random.default_rng(9)
    img = rng.random((64, 128, 3)).astype(np.float32)
    clear_caches()
    whole = remap(img, "latlong", "cube", 40, filter=filter, rotation=(10, 20, 30))
    clear_caches()
    monkeypatch.setattr(_plans, "KEEP_PLAN_BYTES", 0)
    monkeypatch.setattr(_plans, "PART_BYTES", 3000)
    parts = remap(img, "latlong", "cube", 40, filter=filter, rotation=(10, 20, 30))
    np.testing.assert_array_equal(parts, whole)
    assert cache_info()["remap plans"]["entries"] == 0


@pytest.mark.parametrize(("size", "out"), [(128, 128), (256, 128)])
def test_area_filter_from_a_mirror_ball_stays_finite(probe, size, out):
    """Regression: a mirror ball's rim texels (the one direction behind it) all deposit into
    the few latlong texels there, ten times those texels' solid angle; the balancing scaled
    their columns until float32 overflowed, and four texels came out NaN. A constant stays
    constant everywhere, and a probe's energy is kept."""
    ball = remap(np.ones((size, size, 1), np.float32), "mirrorball", "latlong", out, filter="area")
    np.testing.assert_allclose(ball, 1, rtol=1e-5)
    img = remap(np.minimum(probe[..., :3], 50).astype(np.float32), "latlong", "mirrorball", size,
                filter="area")  # fmt: skip
    back = remap(img, "mirrorball", "latlong", out, filter="area")
    assert np.isfinite(back).all()
    np.testing.assert_allclose(energy(back, "latlong"), energy(img, "mirrorball"),
                               rtol=SPHERE_AREA_ENERGY_RTOL)  # fmt: skip
