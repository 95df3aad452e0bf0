"""The clipped sun: seven 8-bit brackets of a sunny probe (1/4000 s to 1 s, the sun clipped in
every frame). bakeshop's merge with the sun modelled from its aureole keeps the sun's
irradiance within 10 %, where OpenCV's calibrate and merge keeps less than half (both measured
here, on the same frames, by this test's own integration)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.photo import (
    CLIPPED,
    MEASURED,
    MODELLED,
    known_response,
    make_stack,
    merge_stack,
    recover_response,
    recover_sun,
    relative_scale,
)
from bakeshop.photo.sun import buie_sunshape
from tests.photo import synthetic
from tests.photo.tolerances import OPENCV_SUN_LOSS, SUN_IRRADIANCE

TIMES = 1 / 4000 * 4.0 ** np.arange(7)  # 1/4000 s ... 1.02 s
GAIN = 0.18 * 60 / 0.5  # the sky (about 0.5) at mid-grey in the 1/60 s frame


@pytest.fixture(scope="module")
def sunny():
    probe, sky, irradiance = synthetic.sunny_probe()
    stack = make_stack(synthetic.shoot(probe, TIMES, gain=GAIN), TIMES)
    merged = merge_stack(stack, recover_response(stack.codes, stack.exposures))
    return probe, sky, irradiance, stack, merged


def test_the_sunshape_is_buies(sunny):
    # an independent transcription of Buie et al. 2003 lives in tests/photo/synthetic.py
    t = np.linspace(0, 80, 2001)
    np.testing.assert_allclose(buie_sunshape(t, 0.05), synthetic.buie(t, 0.05), rtol=1e-12)


def test_clipped_sun_recovered_within_ten_percent_where_opencv_loses_half(sunny):
    probe, sky, truth, stack, merged = sunny
    near = (merged.status == CLIPPED).sum()
    assert 0 < near < 200  # the sun is clipped in every frame, and only the sun
    recovered, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    scale = relative_scale(merged.radiance, probe, merged.votes > 0)
    ours = synthetic.sun_irradiance(recovered / scale, sky)
    before = synthetic.sun_irradiance(merged.radiance / scale, sky)
    images = [np.ascontiguousarray(f[..., ::-1]) for f in stack.codes]
    times = stack.exposures.astype(np.float32)
    curve = cv2.createCalibrateDebevec().process(images, times)
    theirs = cv2.createMergeDebevec().process(images, times, curve)[..., ::-1]
    theirs = synthetic.sun_irradiance(theirs / relative_scale(theirs, probe, merged.votes > 0), sky)
    print(
        f"sun kept: bakeshop {ours / truth}, clipped merge {before / truth}, "
        f"OpenCV {theirs / truth}"
    )
    assert np.all(np.abs(ours / truth - 1) < SUN_IRRADIANCE)
    assert np.all(theirs / truth < OPENCV_SUN_LOSS)
    assert np.all(before / truth < OPENCV_SUN_LOSS)
    assert found.source == "aureole" and found.circumsolar_ratio == pytest.approx(0.05, abs=0.02)
    assert np.all(status[merged.status == CLIPPED] == MODELLED)
    assert found.measured is not None  # light.sun finds and measures the modelled sun
    angle = np.degrees(np.arccos(found.direction @ synthetic.SUN_DIRECTION))
    assert angle < 0.1


def test_a_given_irradiance_sets_the_sun(sunny):
    probe, sky, truth, stack, merged = sunny
    scale = relative_scale(merged.radiance, probe, merged.votes > 0)
    want = float(truth @ [0.2126, 0.7152, 0.0722]) * scale * 1.3  # a meter reads 30 % more
    recovered, _, found = recover_sun(merged.radiance, merged.status, "latlong", irradiance=want)
    assert found.source == "given"
    got = found.irradiance @ [0.2126, 0.7152, 0.0722]
    assert got == pytest.approx(want, rel=1e-3)


def test_nothing_to_do_without_clipping():
    probe = synthetic.default_probe()
    status = np.zeros(probe.shape[:2], np.uint8)
    out, new_status, found = recover_sun(probe, status, "latlong")
    assert found is None and out is probe


def test_bad_arguments(sunny):
    _, _, _, _, merged = sunny
    with pytest.raises(ArgumentError, match="irradiance"):
        recover_sun(merged.radiance, merged.status, "latlong", irradiance=-1.0)
    with pytest.raises(ArgumentError, match="status"):
        recover_sun(merged.radiance, merged.status[:10], "latlong")


@pytest.mark.parametrize("sun", [(), pytest.param((1e6, 0.02), marks=pytest.mark.slow)])
def test_five_brackets_through_a_non_srgb_camera_keep_the_suns_energy(sun):
    """The issue's brackets, 1/4000-1/15 s, through the test camera's curve (none of bakeshop's
    known ones), recovered from the stack: the sun's energy within 10 % (the fixture's sun,
    and a brighter sun of a clearer sky)."""
    times = TIMES[:5]
    probe, sky, truth = synthetic.sunny_probe(*sun)
    stack = make_stack(synthetic.shoot(probe, times, gain=GAIN), times)
    merged = merge_stack(stack, recover_response(stack.codes, stack.exposures))
    recovered, _, found = recover_sun(merged.radiance, merged.status, "latlong")
    scale = relative_scale(merged.radiance, probe, merged.votes > 0)
    ours = synthetic.sun_irradiance(recovered / scale, sky)
    assert found.source == "aureole"
    assert np.all(np.abs(ours / truth - 1) < SUN_IRRADIANCE), ours / truth


def test_a_clipped_streak_is_not_a_sun(sunny):
    """A long clipped streak (a glint along a roof edge) and no other clipped region: not
    round, so no sun is modelled from it, said in one line."""
    _, _, _, _, merged = sunny
    radiance, status = merged.radiance.copy(), merged.status.copy()
    status[status == CLIPPED] = MEASURED  # the sun measured
    status[300, 100:160] = CLIPPED
    radiance[300, 100:160] = radiance.max()
    out, new_status, found = recover_sun(radiance, status, "latlong")
    assert found.source == "clipped" and "not round" in found.reason
    assert out is radiance and new_status is status


def _merged(probe, gain=GAIN):
    stack = make_stack(synthetic.shoot(probe, TIMES[:5], gain=gain), TIMES[:5])
    return merge_stack(stack, recover_response(stack.codes, stack.exposures))


def _refused(merged, found, why):
    """A refused fit: the merge returned as it was, the reason said in one line."""
    assert found.source == "clipped" and found.texels == 0
    assert why in found.reason and "\n" not in found.reason
    np.testing.assert_array_equal(found.irradiance, found.merged_irradiance)


def test_a_fit_that_does_not_explain_the_clipping_is_refused_and_the_clipped_values_kept():
    """A sun of the clearest sky (circumsolar ratio 0.005) leaves almost no aureole: a fit
    with a constant sky read the sky's slope as the aureole's (its disk held 1e37 times the
    light, the issue's 1.5e13x), one with a local plane gives a disk under the clipped lower
    bounds (0.3 % of the sun): refused either way."""
    probe, _, _ = synthetic.sunny_probe(2e5, 0.005)
    merged = _merged(probe)
    out, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    _refused(merged, found, "does not explain the clipping")
    assert out is merged.radiance and status is merged.status


@pytest.mark.slow
def test_an_overexposed_stack_models_the_sun_not_the_larger_clipped_cloud():
    """Eight times the fixture's gain clips the default probe's bright cloud (its painted-out
    sun) in every frame too, and it holds more clipped light than the sun: the old choice
    modelled the cloud and kept 0.03 of the sun. The sun is the region whose fitted disk is
    brightest: its energy within 10 %."""
    probe, sky, truth = synthetic.sunny_probe()
    merged = _merged(probe, GAIN * 8)
    recovered, _, found = recover_sun(merged.radiance, merged.status, "latlong")
    scale = relative_scale(merged.radiance, probe, merged.votes > 0)
    ours = synthetic.sun_irradiance(recovered / scale, sky)
    assert found.source == "aureole"
    assert np.degrees(np.arccos(found.direction @ synthetic.SUN_DIRECTION)) < 0.1
    assert np.all(np.abs(ours / truth - 1) < SUN_IRRADIANCE), ours / truth


@pytest.mark.slow
def test_a_sun_low_over_the_horizon_is_refused_not_modelled_five_times_too_bright():
    """The ground cuts the ring around a sun 6 degrees above the horizon: a constant sky level
    put 5.4 times its energy in the disk, a local plane still 1.4 times. The fit's residual on
    the ring (33 %) says it does not describe the aureole: refused in one line."""
    probe, _, _ = synthetic.sunny_probe(direction=synthetic.LOW_SUN)
    merged = _merged(probe)
    out, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    _refused(merged, found, "misses the measured ring")
    assert out is merged.radiance and status is merged.status
    low = np.asarray(synthetic.LOW_SUN) / np.linalg.norm(synthetic.LOW_SUN)
    assert np.degrees(np.arccos(found.direction @ low)) < 0.2


@pytest.mark.parametrize("response", ["srgb", "recovered"])
def test_a_sun_its_aureole_does_not_determine_is_refused_not_modelled_at_half_its_energy(
    response,
):
    """The red team's sun: smaller than a texel and brighter than Buie's sunshape makes it
    for its aureole, which is flattened near the disk, over a sky brightening towards it. Each
    fit was inside every bound and modelled 0.49 (sRGB), 0.77 (a curve recovered with Debevec)
    or 0.14 (Robertson) of its energy. The ring's inner and outer halves put 0.86 and 3.3
    times the fitted disk's light in it: refused in one line, the clipped values kept."""
    times = TIMES[:5]
    probe = synthetic.painted_sun_probe()
    if response == "srgb":
        x = np.clip(probe * times[:, None, None, None] * 13.5, 0, 1)
        z = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
        stack = make_stack(np.rint(z * 255).astype(np.uint8), times)
        merged = merge_stack(stack, known_response("srgb"))
    else:
        merged = _merged(probe, 13.5)
    out, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    _refused(merged, found, "does not determine the sun's energy")
    assert out is merged.radiance and status is merged.status


@pytest.mark.slow
def test_a_clear_skys_faint_aureole_that_does_not_determine_its_sun_is_refused():
    """Buie's own sun of a clear sky (circumsolar ratio 0.01) at the fixture's radiance: its
    faint aureole, near the sky's level in the outer ring, read a slope that modelled 0.75 of
    the sun's energy, nothing said. The ring's halves put 3.1 and 0.16 times the fitted disk's
    light in it: refused."""
    probe, _, _ = synthetic.sunny_probe(2e5, 0.01)
    merged = _merged(probe)
    out, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    _refused(merged, found, "does not determine the sun's energy")
    assert out is merged.radiance and status is merged.status
