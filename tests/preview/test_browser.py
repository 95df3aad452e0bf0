"""`bakeshop view` in a real browser: Debian's Chromium, headless, WebGL2 on SwiftShader, takes
screenshots of the page, which must be the offscreen render (moderngl, llvmpipe) of the same view
through bakeshop's display rule: the same shaders on two hosts and two drivers."""

import shutil
import subprocess
from urllib.parse import urlencode

import numpy as np
import pytest

from bakeshop.image import to_picture
from bakeshop.io import read_image
from bakeshop.preview import Camera, Renderer, View, default_camera
from bakeshop.preview.server import serve
from tests.preview.bakes import synthetic_bake
from tests.preview.tolerances import BROWSER_MAX_CODES, BROWSER_MEAN_CODES

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
W, H = 320, 180
EV = 0.5

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(CHROMIUM is None, reason="no Chromium (Debian: apt-get install chromium)"),
]


@pytest.fixture(scope="module")
def setup():
    bake = synthetic_bake()
    viewer = serve(bake)
    with Renderer(bake) as renderer:
        yield viewer, renderer
    viewer.close()


def screenshot(viewer, tmp_path, **query) -> np.ndarray:
    """The page at ``query`` as Chromium draws it: (H, W, 3) int code values."""
    shot = tmp_path / "shot.png"
    url = viewer.url + "?" + urlencode({"width": W, "height": H, "ui": 0, "ev": EV, **query})
    args = [CHROMIUM, "--headless=new", "--no-sandbox", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--hide-scrollbars", "--force-device-scale-factor=1",
            f"--user-data-dir={tmp_path / 'profile'}", f"--window-size={W},{H}",
            "--virtual-time-budget=30000", f"--screenshot={shot}", url]  # fmt: skip
    subprocess.run(args, check=True, capture_output=True, timeout=180)
    return np.rint(read_image(shot)[..., :3] * 255).astype(int)


def _near_change(field, tolerance=0.0) -> np.ndarray:
    """Pixels whose 3 x 3 neighbourhood holds a value of ``field`` (H, W[, C]) more than
    ``tolerance`` away from their own."""
    f = field if field.ndim == 3 else field[..., None]
    padded = np.pad(f, ((1, 1), (1, 1), (0, 0)), mode="edge")
    out = np.zeros(f.shape[:2], bool)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            out |= (np.abs(padded[dy : dy + H, dx : dx + W] - f) > tolerance).any(axis=-1)
    return out


def offscreen(renderer, view) -> tuple[np.ndarray, np.ndarray]:
    """bakeshop preview's picture of ``view`` and its edges: a ball's silhouette; on the golf
    course a change of surface, of normal, of sun visibility (a shadow's rim, where the two
    drivers' shadow-map rasterisation may differ by a texel) or of water, and a pixel next to
    one more than BROWSER_MAX_CODES brighter or darker."""
    picture = to_picture(renderer.render(view)[..., :3], ev=EV, operator="aces")
    if view.scene in ("sky", "balls"):
        edge = _near_change(renderer.render(view, mode=1)[..., 3])
    else:
        normal_lit = renderer.render(view, mode=1)
        edge = _near_change(normal_lit, 0.3)
        edge |= _near_change(renderer.render(view, mode=2)[..., :3], 1e-3)
        edge |= _near_change(renderer.render(view, mode=5)[..., 3])
        edge |= _near_change(renderer.render(view, mode=3)[..., 3])
        # and a sharp feature of the picture itself (the sun's glint on calm water, HDR path)
        edge |= _near_change(picture.pixels.astype(float), BROWSER_MAX_CODES)
    return picture.pixels.astype(int), edge


CASES = [
    ({"scene": "balls"}, {}),
    ({"scene": "balls", "sun_light": 1}, {"sun_light": True}),
    ({"scene": "sky", "sky_level": 2.5}, {"sky_level": 2.5}),
    ({"scene": "balls", "yaw": 35, "pitch": 20, "distance": 18}, {"orbit": (35.0, 20.0, 18.0)}),
    ({"scene": "golf"}, {}),
    ({"scene": "golf", "diffuse": "shadow", "water": 0}, {"diffuse": "shadow", "water": False}),
    ({"scene": "water", "reflection": "hdr"}, {"reflection": "hdr"}),
]


@pytest.mark.parametrize("query, options", CASES)
def test_the_browser_draws_what_bakeshop_preview_draws(setup, tmp_path, query, options):
    viewer, renderer = setup
    scene = query["scene"]
    camera = None
    if "orbit" in options:
        base = default_camera(scene)
        yaw, pitch, distance = options.pop("orbit")
        camera = Camera(base.target, yaw, pitch, distance, base.fov, base.near, base.far)
    expected, edge = offscreen(renderer, View(scene, W, H, camera=camera, **options))
    shown = screenshot(viewer, tmp_path, **query)
    assert shown.shape == expected.shape
    if scene in ("golf", "water"):
        # a sliver of a billboard seen edge-on, which one rasteriser covers and the other not
        edge |= _near_change(shown.astype(float), BROWSER_MAX_CODES)
    diff = np.abs(shown - expected)
    assert diff.mean() < BROWSER_MEAN_CODES
    assert diff.max(axis=-1)[~edge].max() <= BROWSER_MAX_CODES


def test_the_sun_light_toggle_adds_the_suns_highlight(setup, tmp_path):
    """Toggling the sun light changes exactly the pixels the offscreen sun term changes."""
    viewer, renderer = setup
    off = screenshot(viewer, tmp_path, scene="balls")
    on = screenshot(viewer, tmp_path, scene="balls", sun_light=1)
    expected_off, _ = offscreen(renderer, View("balls", W, H))
    expected_on, _ = offscreen(renderer, View("balls", W, H, sun_light=True))
    changes = np.abs(expected_on - expected_off).max(axis=-1) > BROWSER_MAX_CODES
    assert changes.sum() > 20  # the highlights are in view
    assert (np.abs(on - off).max(axis=-1)[changes] > 0).all()
    assert (on >= off - 1).all()  # a light only adds
