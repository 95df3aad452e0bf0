"""OpenEXR environment maps: the ``envmap`` attribute read and honoured, and written; OpenEXR's
own sample pairs (tests/data/exr, each scene published as a latlong and as a cube) converted
into each other.

The published files of a pair were each made from the original scene by exrenvmap, whose
lookups average 5 x 5 bilinear samples under a tent a texel or two wide, and are stored as half
floats (2^-11 relative); neither is a resampling of the other. A conversion by bakeshop
therefore differs from the published file where the scene is sharp (the sun, the lines of the
orientation pattern), by filtering, not by rounding; the bounds below are set between what the
right mapping gives and what a wrong one does (the faces read as bakeshop's own vertical strip,
as before the attribute was honoured), and each test checks that the wrong one fails them.
"""

from pathlib import Path

import numpy as np
import OpenEXR
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.io import read_environment, read_image, write_environment, write_image
from bakeshop.sphere import layout, remap
from tests import imfenvmap as imf
from tests.tolerances import (
    ENVMAP_KERNER_MEDIAN,
    ENVMAP_KERNER_SMOOTH_MEDIAN,
    ENVMAP_MATCHES_IMFENVMAP_RTOL,
    ENVMAP_ORIENTATION_OFF,
)

DATA = Path(__file__).resolve().parents[1] / "data" / "exr"
PAIRS = {"Kerner": ("KernerEnvLatLong.exr", "KernerEnvCube.exr"),
         "Orientation": ("OrientationLatLong.exr", "OrientationCube.exr")}  # fmt: skip


@pytest.fixture(scope="module", params=list(PAIRS))
def pair(request):
    """(name, latlong (H, W, 3), cube (6 S, S, 3)) of a published pair, read by bakeshop."""
    ll_name, cube_name = PAIRS[request.param]
    latlong = read_environment(DATA / ll_name)
    cube = read_environment(DATA / cube_name)
    assert (latlong.layout, cube.layout) == ("openexr-latlong", "openexr-cube")
    assert latlong.how == "its envmap attribute is latlong"
    assert cube.how == "its envmap attribute is cube"
    return request.param, latlong.image, cube.image


def converted(pair, wrong=False):
    """Each published file converted to the other's layout and size (bilinear): [(ours,
    published), ...]; ``wrong`` reads the cube as bakeshop's vertical strip instead."""
    _, latlong, cube = pair
    h, w = latlong.shape[:2]
    s = cube.shape[1]
    cube_layout = "strip-vertical" if wrong else "openexr-cube"
    return [
        (remap(latlong, "openexr-latlong", cube_layout, s, filter="bilinear"), cube),
        (remap(cube, cube_layout, "openexr-latlong", (w, h), filter="bilinear"), latlong),
    ]


@pytest.mark.slow
def test_conversions_agree_with_imfenvmaps_mapping(pair):
    """bakeshop's bilinear conversion of each published file equals exrenvmap's bilinear point
    lookup at the positions the test-side reading of ImfEnvmap.h gives (float32 rounding)."""
    _, latlong, cube = pair
    h, w = latlong.shape[:2]
    s = cube.shape[1]
    want = imf.sample(latlong, imf.latlong_position(w, h, imf.cube_directions(s)))
    got = remap(latlong, "openexr-latlong", "openexr-cube", s, filter="bilinear")
    np.testing.assert_allclose(got, want, rtol=ENVMAP_MATCHES_IMFENVMAP_RTOL, atol=1e-6)
    y, x = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    want = imf.sample(cube, imf.cube_position(s, imf.latlong_direction(w, h, x, y)))
    got = remap(cube, "openexr-cube", "openexr-latlong", (w, h), filter="bilinear")
    np.testing.assert_allclose(got, want, rtol=ENVMAP_MATCHES_IMFENVMAP_RTOL, atol=1e-6)


def block_means(a, k=4):
    h, w, c = a.shape
    return a.reshape(h // k, k, w // k, k, c).mean(axis=(1, 3))


def kerner_errors(ours, published):
    """Median relative error per texel, and of 4 x 4 block means (where filtering differences
    average out)."""
    per_texel = np.median(np.abs(ours - published) / np.abs(published))
    smooth = block_means(ours), block_means(published)
    return per_texel, np.median(np.abs(smooth[0] - smooth[1]) / np.abs(smooth[1]))


def orientation_off(ours, published):
    """Fraction of texels whose value differs by more than a quarter of the pattern's range."""
    return np.mean(np.abs(ours - published).max(axis=-1) > 0.25)


@pytest.mark.slow
def test_converting_either_of_a_pair_matches_the_other(pair):
    name = pair[0]
    for (ours, published), (wrong, _) in zip(converted(pair), converted(pair, wrong=True),
                                             strict=True):  # fmt: skip
        if name == "Kerner":
            texel, smooth = kerner_errors(ours, published)
            assert texel < ENVMAP_KERNER_MEDIAN and smooth < ENVMAP_KERNER_SMOOTH_MEDIAN
            texel, smooth = kerner_errors(wrong, published)
            assert texel > ENVMAP_KERNER_MEDIAN and smooth > ENVMAP_KERNER_SMOOTH_MEDIAN
        else:
            assert orientation_off(ours, published) < ENVMAP_ORIENTATION_OFF
    # both files hold the scene's energy (radiance x solid angle, each by its own layout)
    _, latlong, cube = pair
    energies = [
        np.einsum("hw,hwc->c", layout(lay).solid_angles(img.shape[:2]), img)
        for lay, img in (("openexr-latlong", latlong), ("openexr-cube", cube))
    ]
    np.testing.assert_allclose(energies[0], energies[1], rtol=0.01)


def test_the_orientation_pairs_wrong_reading_is_caught():
    """The orientation pattern read the old way (faces as bakeshop's strip) misplaces more
    than the bound's share of its texels one way round."""
    latlong = read_environment(DATA / "OrientationLatLong.exr").image
    cube = read_environment(DATA / "OrientationCube.exr").image
    wrong = remap(latlong, "openexr-latlong", "strip-vertical", cube.shape[1], filter="bilinear")
    assert orientation_off(wrong, cube) > ENVMAP_ORIENTATION_OFF


def test_envmap_attribute_is_written_and_read_back(tmp_path):
    rng = np.random.default_rng(2)
    for layout_name, shape, envmap in (
        ("openexr-latlong", (8, 16, 3), "latlong"),
        ("openexr-cube", (24, 4, 3), "cube"),
    ):
        image = rng.random(shape, dtype=np.float32)
        path = tmp_path / f"{envmap}.exr"
        assert write_environment(path, image, layout_name) == [path]
        header = OpenEXR.File(str(path), header_only=True).header()
        assert header["envmap"].name == f"ENVMAP_{envmap.upper()}"
        back = read_environment(path)
        assert back.layout == layout_name
        np.testing.assert_array_equal(back.image, image.astype(np.float16).astype(np.float32))


def test_openexr_layouts_refuse_other_formats(tmp_path):
    with pytest.raises(ArgumentError, match="write it to an .exr file"):
        write_environment(tmp_path / "a.hdr", np.ones((8, 16, 3), np.float32), "openexr-latlong")


def test_a_given_layout_overrides_the_attribute_and_says_so(tmp_path):
    path = tmp_path / "c.exr"
    write_environment(path, np.ones((24, 4, 3), np.float32), "openexr-cube")
    env = read_environment(path, "strip-vertical")
    assert env.layout == "strip-vertical"
    assert env.how == "given, over its envmap attribute (openexr-cube)"


def test_an_attribute_that_does_not_fit_the_shape_is_an_error(tmp_path):
    path = tmp_path / "bad.exr"
    write_image(path, np.ones((10, 4, 3), np.float32), envmap="cube")
    with pytest.raises(ArgumentError, match="envmap attribute says cube") as e:
        read_environment(path)
    assert "bad.exr" in str(e.value)


def test_files_without_the_attribute_keep_the_shape_guess(tmp_path):
    path = tmp_path / "plain.exr"
    write_image(path, np.ones((8, 16, 3), np.float32))
    assert "envmap" not in read_image(path, with_metadata=True)[1]
    assert read_environment(path).layout == "latlong"
