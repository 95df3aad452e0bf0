"""bakeshop against an independent implementation: py360convert (latlong <-> cube).

py360convert's frame is left-handed: its front is +z, so its (x, y, z) is our (x, y, -z); its
faces F, R, B, L, U, D are our directx (cross) slots +Z, +X, -Z, -X, +Y, -Y, drawn the same way
(seen from inside, unmirrored), and its "dice" is our cross-horizontal. Its face grids put
texel centres on the face edges (``linspace(-0.5, 0.5, w)``) where ours are half a texel in,
so pictures agree to the half-texel offset, and values at the same directions agree exactly.
"""

import numpy as np
import py360convert
import py360convert.utils
import pytest

from bakeshop.sphere import layout, remap, sample
from tests.tolerances import SPHERE_PEER_CV2_ATOL, SPHERE_PEER_SCIPY_ATOL


def smooth(d):
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([1 + 0.5 * x + 0.3 * y - 0.2 * z + 0.4 * x * y, np.exp(z), 1 + y * y], -1)


@pytest.fixture(scope="module")
def pano():
    rng = np.random.default_rng(0)
    dirs, _ = layout("latlong").directions((128, 256))
    # a smooth world plus texel noise, so that sampling positions matter to the last bit
    return (smooth(dirs) + 0.2 * rng.random((128, 256, 3))).astype(np.float32)


@pytest.mark.parametrize(
    ("engine", "atol"), [("cv2", SPHERE_PEER_CV2_ATOL), ("scipy", SPHERE_PEER_SCIPY_ATOL)]
)
def test_e2c_values_at_the_same_directions(pano, engine, atol, monkeypatch):
    """py360convert's e2c texel = bakeshop's bilinear latlong lookup at that texel's direction
    (z flipped into our frame), seams and poles included."""
    w = 32
    if engine == "scipy":
        monkeypatch.setattr(py360convert.utils, "cv2", None)
        w = 30  # another size: py360convert caches its samplers (and their engine) per size
    faces = py360convert.e2c(pano, face_w=w, mode="bilinear", cube_format="list")
    xyz = np.asarray(py360convert.utils.xyzcube(w), np.float64)  # (w, 6w, 3), their frame
    ours = sample(pano, "latlong", xyz * [1, 1, -1])
    theirs = np.concatenate(faces, axis=1)
    assert np.abs(theirs - ours).max() < atol


def test_dice_is_our_horizontal_cross(pano):
    """Same arrangement and orientation of faces: py360convert's dice and bakeshop's
    cross-horizontal of a smooth world differ only by the half-texel grid offset."""
    w = 64
    dirs, _ = layout("latlong").directions((256, 512))
    world = smooth(dirs).astype(np.float32)
    dice = py360convert.e2c(world, face_w=w, mode="bilinear", cube_format="dice")
    cross = remap(world, "latlong", "cross-horizontal", w)
    _, valid = layout("cross-horizontal").directions(cross.shape[:2])
    # half a texel of a 64 face is ~1/64 rad; the gradient is at most e: bound 0.05
    assert np.abs(dice - cross)[valid].max() < 0.05
    # a mirrored or misplaced face would differ by the function's range
    assert np.abs(np.fliplr(dice) - cross)[valid].max() > 0.5


def test_c2e_agrees_through_the_world():
    """Each library's cube -> latlong of the same smooth world lands on the world's values
    at its own texel directions."""
    w = 64
    their_dirs = np.asarray(py360convert.utils.xyzcube(w), np.float64)
    their_cube = smooth(their_dirs * [1, 1, -1] / np.linalg.norm(their_dirs, axis=-1)[..., None])
    faces = [their_cube[:, i * w : (i + 1) * w].astype(np.float32) for i in range(6)]
    theirs = py360convert.c2e(faces, h=128, w=256, mode="bilinear", cube_format="list")
    uu, vv = np.meshgrid(np.linspace(-np.pi, np.pi, 256), np.linspace(np.pi / 2, -np.pi / 2, 128))
    their_dirs = np.stack([np.cos(vv) * np.sin(uu), np.sin(vv), -np.cos(vv) * np.cos(uu)], -1)
    their_truth = smooth(their_dirs)
    our_cube = smooth(layout("cube").directions((6, w, w))[0]).astype(np.float32)
    cube = remap(our_cube, "cube", "latlong", 128)
    our_truth = smooth(layout("latlong").directions((128, 256))[0])
    assert np.abs(theirs - their_truth).max() < 0.05
    # bilinear from a 64 cube: worst next to cube corners (the mean of three texels)
    assert np.abs(cube - our_truth).max() < 5e-3
