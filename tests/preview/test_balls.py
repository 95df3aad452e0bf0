"""The offscreen material balls and skybox (moderngl over EGL, Mesa's llvmpipe) against the numpy
reference of the same equations (bakeshop.preview.reference), pixel by pixel."""

import numpy as np
import pytest

from bakeshop.image import to_picture
from bakeshop.preview import Renderer, View, balls
from bakeshop.preview.reference import camera_rays, shade_balls
from tests.preview.bakes import synthetic_bake
from tests.preview.tolerances import (
    PREVIEW_CODE_ATOL,
    PREVIEW_DISPLAY_CODES,
    PREVIEW_EDGE_CODES,
    PREVIEW_LINEAR_RTOL,
    PREVIEW_UNIFORM_ATOL,
)

W, H = 320, 180
EV = 0.5


@pytest.fixture(scope="module")
def renderer():
    with Renderer(synthetic_bake()) as r:
        yield r


def codes(linear):
    """bakeshop's display rule (exposure, ACES, sRGB, 8 bits) on (N, 3) linear values."""
    pic = to_picture(np.asarray(linear, np.float32)[None], ev=EV, operator="aces")
    return pic.pixels[0].astype(int)


def away_from_edges(bake, view, rows, cols):
    """Pixels whose reference value holds still (to PREVIEW_EDGE_CODES) when the ray moves a
    quarter pixel in each direction: not on a silhouette, not on a sharp feature seen in a
    mirror."""
    ref, index = shade_balls(bake, view, rows, cols)
    keep = np.ones(len(rows), bool)
    centre = codes(ref)
    for dr, dc in ((0.25, 0), (-0.25, 0), (0, 0.25), (0, -0.25)):
        moved, moved_index = shade_balls(bake, view, rows + dr, cols + dc)
        keep &= moved_index == index
        keep &= np.abs(codes(moved) - centre).max(axis=1) <= PREVIEW_EDGE_CODES
    return ref, index, keep


def sample_pixels(n, seed=0):
    rng = np.random.default_rng(seed)
    return rng.integers(0, H, n), rng.integers(0, W, n)


@pytest.mark.parametrize("sun_light", [False, True])
def test_balls_match_the_numpy_reference(renderer, sun_light):
    """Every ball kind (sun DIM, shadow DIM, SH, the roughness x metalness grid) at 3000 random
    pixels: within 1/255 after tone mapping away from edges, and the ball hit is the same."""
    bake = renderer.bake
    view = View("balls", W, H, sun_light=sun_light)
    image = renderer.render(view)[..., :3]
    ids = renderer.render(view, mode=1)[..., 3].astype(int) - 1
    rows, cols = sample_pixels(3000)
    ref, index, keep = away_from_edges(bake, view, rows, cols)
    assert keep.mean() > 0.9
    # every ball is sampled, and the driver hits the ball the reference hits
    assert set(index[keep]) == set(range(-1, len(renderer.ball_list(view))))
    np.testing.assert_array_equal(ids[rows, cols][keep], index[keep])
    got = image[rows, cols][keep]
    assert np.abs(codes(got) - codes(ref[keep])).max() <= PREVIEW_CODE_ATOL
    np.testing.assert_allclose(got, ref[keep], rtol=PREVIEW_LINEAR_RTOL, atol=1e-4)


@pytest.mark.parametrize("level", [-1.0, 0.0, 2.5])
def test_the_skybox_is_the_baked_cube(renderer, level):
    """The sky scene shows the environment cube (or a level of detail of the chain) exactly as
    baked: the reference's seamless bilinear lookups, every pixel."""
    view = View("sky", W, H, sky_level=level)
    image = renderer.render(view)[..., :3]
    rows, cols = np.mgrid[0:H:3, 0:W:3].reshape(2, -1)
    ref, _ = shade_balls(renderer.bake, view, rows, cols)
    np.testing.assert_allclose(image[rows, cols], ref, rtol=PREVIEW_LINEAR_RTOL, atol=1e-4)
    assert np.abs(codes(image[rows, cols]) - codes(ref)).max() <= PREVIEW_CODE_ATOL


def test_the_camera_looks_where_the_reference_says(renderer):
    """The pixel the reference's ray through a ball's centre names shows that ball (the
    projection, the row order and the handedness are the driver's)."""
    view = View("balls", W, H)
    ids = renderer.render(view, mode=1)[..., 3].astype(int) - 1
    items = renderer.ball_list(view)
    cam = view.eye
    clip = cam.view_projection(W / H) @ np.array([[*b["centre"], 1.0] for b in items]).T
    ndc = clip[:2] / clip[3]
    cols = np.floor((ndc[0] + 1) / 2 * W).astype(int)
    rows = np.floor((1 - ndc[1]) / 2 * H).astype(int)
    np.testing.assert_array_equal(ids[rows, cols], np.arange(len(items)))
    # and the ray through that pixel passes within a pixel's width of the centre
    origin, d = camera_rays(view, rows, cols)
    centres = np.array([b["centre"] for b in items])
    miss = np.linalg.norm(np.cross(centres - origin, d), axis=1)
    assert miss.max() < 2 * cam.distance * np.tan(np.radians(cam.fov / 2)) / H * 1.5


def test_a_uniform_environment_gives_the_albedo():
    """Environment, chain and DIMs all 1: a Lambertian ball shows exactly its albedo, a GGX ball
    (1 - metalness) base + F0 A + B, and the sky 1."""
    bake = synthetic_bake(uniform=1.0)
    bake = bake._replace(sh=np.zeros((9, 3)) + [[2 * np.sqrt(np.pi)]] * np.eye(9)[:, :1])
    view = View("balls", W, H)
    with Renderer(bake) as r:
        image = r.render(view)[..., :3]
        ids = r.render(view, mode=1)[..., 3].astype(int) - 1
        items = r.ball_list(view)
    for i, ball in enumerate(items[:3]):
        inside = ids == i
        assert inside.sum() > 100
        # sun DIM and shadow DIM exactly; the SH constant term Y00 c0 = 1 to float32
        np.testing.assert_allclose(image[inside], ball["colour"][0], atol=PREVIEW_UNIFORM_ATOL)
    np.testing.assert_allclose(image[ids == -1], 1.0, atol=PREVIEW_UNIFORM_ATOL)


def test_the_shaders_display_step_is_bakeshops(renderer):
    """The in-shader tone mapping (what the browser shows) equals bakeshop.image.to_picture on
    the linear render: exposure, ACES (Hill), clamp, sRGB."""
    view = View("balls", W, H)
    linear = renderer.render(view)[..., :3]
    shown = renderer.render(view, display=(EV, "aces"))[..., :3]
    ours = to_picture(linear, ev=EV, operator="aces").pixels.astype(int)
    assert np.abs(np.rint(shown * 255).astype(int) - ours).max() <= PREVIEW_DISPLAY_CODES


def test_balls_grid_is_roughness_by_metalness():
    items = balls(9)
    ggx = [b for b in items if b["kind"] == "ggx"]
    assert len(ggx) == 27
    assert sorted({b["roughness"] for b in ggx}) == [m / 8 for m in range(9)]
    assert sorted({b["metalness"] for b in ggx}) == [0.0, 0.5, 1.0]
    # more levels than columns: evenly spread, each exactly one level
    spread = {b["roughness"] for b in balls(20) if b["kind"] == "ggx"}
    assert len(spread) == 9 and all(abs(r * 19 - round(r * 19)) < 1e-12 for r in spread)
