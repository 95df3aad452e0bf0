"""Mirror balls: photos rendered here by ray-sphere reflection (not bakeshop's layout code)
unwrap back to the probe they reflect within 1 % RMS away from the rim, in the physical
convention and as HDRShop's z-mirrored result; the ball is found to a tenth of a pixel; two
views merged fill each photographer from the other view."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.photo import Circle, best_yaw, card_reflectance, crop_ball, find_ball, merge_views
from bakeshop.photo import unwrap as unwrap_ball
from bakeshop.photo.mirrorball import ball_coordinates, ball_directions, layout_directions
from tests.photo import synthetic
from tests.photo.tolerances import BALL_PX, TWO_VIEW_RMS, UNWRAP_RMS

CIRCLE = Circle(311.37, 248.81, 180.23)


@pytest.fixture(scope="module")
def photo():
    return synthetic.ball_photo(500, 640, CIRCLE.x, CIRCLE.y, CIRCLE.radius)


def rms(a, b, mask):
    rel = a[mask] / b[mask] - 1
    return float(np.sqrt(np.mean(rel * rel)))


def test_the_ball_is_found_to_a_tenth_of_a_pixel(photo):
    found = find_ball(photo)
    assert abs(found.x - CIRCLE.x) < BALL_PX and abs(found.y - CIRCLE.y) < BALL_PX
    assert abs(found.radius - CIRCLE.radius) < BALL_PX
    again = find_ball(photo, guess=Circle(found.x + 2, found.y - 2, found.radius + 1.5))
    assert abs(again.x - CIRCLE.x) < BALL_PX and abs(again.radius - CIRCLE.radius) < BALL_PX


def test_unwrap_physical_is_the_reflected_probe(photo):
    out = unwrap_ball(photo, CIRCLE, size=128, convention="physical")
    dirs, _ = layout_directions("latlong", 128)
    away = dirs[..., 2] > -math.cos(math.radians(30))  # the rim shows -Z in this convention
    assert rms(out, synthetic.smooth_probe(dirs), away) < UNWRAP_RMS


def test_unwrap_hdrshop_is_the_z_mirror_and_matches_design(photo):
    out = unwrap_ball(photo, CIRCLE, size=128)  # HDRShop's convention is the default
    dirs, _ = layout_directions("latlong", 128)
    # DESIGN's latlong written out here: u = 0.75 looks at +X, the centre column at -Z
    v, u = (np.arange(128) + 0.5) / 128, (np.arange(256) + 0.5) / 256
    theta, phi = np.pi * v[:, None], 2 * np.pi * (u[None, :] - 0.5)
    mine = np.stack(np.broadcast_arrays(np.sin(theta) * np.sin(phi), np.cos(theta),
                                        -np.sin(theta) * np.cos(phi)), -1)  # fmt: skip
    np.testing.assert_allclose(dirs, mine, atol=1e-12)
    away = dirs[..., 2] < math.cos(math.radians(30))  # the rim is behind: +Z
    mirrored = synthetic.smooth_probe(dirs * [1, 1, -1])
    assert rms(out, mirrored, away) < UNWRAP_RMS
    # HDRShop's angular map (DESIGN: theta = pi r, d_z = -cos theta) of the same photo
    ang = unwrap_ball(photo, CIRCLE, to="angular", size=96)
    c = (np.arange(96) + 0.5) / 96
    a, b = np.meshgrid(2 * c - 1, 1 - 2 * c)
    r = np.hypot(a, b)
    t = np.pi * r
    d = np.stack([a / r * np.sin(t), b / r * np.sin(t), -np.cos(t)], -1)
    inside = r < 5 / 6  # away from the rim (150 degrees)
    assert rms(ang, synthetic.smooth_probe(d * [1, 1, -1]), inside) < UNWRAP_RMS
    assert np.all(ang[r > 1] == 0)


def test_ball_geometry_round_trips():
    rng = np.random.default_rng(2)
    d = rng.normal(size=(1000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    for convention in ("hdrshop", "physical"):
        ab = ball_coordinates(d, convention)
        np.testing.assert_allclose(ball_directions(ab[:, 0], ab[:, 1], convention), d, atol=1e-9)
    # HDRShop: r = sin(45 deg) right of centre looks at +X; the centre looks at -Z
    np.testing.assert_allclose(ball_directions(math.sqrt(0.5), 0.0), [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(ball_directions(0.0, 0.0), [0, 0, -1], atol=1e-12)


def test_crop_is_the_ball_picture(photo):
    crop = crop_ball(photo, CIRCLE, size=200)
    np.testing.assert_array_equal(unwrap_ball(photo, CIRCLE, to="mirrorball", size=200), crop)
    # HDRShop's mirror ball is the photo's ball as it is: through directions (a full turn
    # forces the general path) it comes back to the crop
    turned = unwrap_ball(photo, CIRCLE, to="mirrorball", size=200, yaw_deg=360.0)
    inside = np.hypot(*np.meshgrid(np.linspace(-1, 1, 200), np.linspace(-1, 1, 200))) < 0.98
    assert rms(turned, crop, inside) < 1e-4


def photographer(centre):
    """Directions within 15 degrees of ``centre`` are hidden by the photographer."""
    return lambda d: d @ centre > math.cos(math.radians(15))


def test_two_views_remove_each_photographer():
    # physically, each camera (and its photographer) stands where its ball's centre looks: +Z
    # of its own frame; the second stands 90 degrees around the vertical
    turn = np.radians(90)
    rot = np.array(
        [[math.cos(turn), 0, math.sin(turn)], [0, 1, 0], [-math.sin(turn), 0, math.cos(turn)]]
    )
    circle_b = Circle(300.6, 240.2, 170.9)
    view_a = synthetic.ball_photo(500, 640, CIRCLE.x, CIRCLE.y, CIRCLE.radius,
                                  blocker=photographer(np.array([0, 0, 1.0])))  # fmt: skip
    # view B's frame is the world turned by -90 degrees: it sees env(R d_b)
    view_b = synthetic.ball_photo(480, 600, circle_b.x, circle_b.y, circle_b.radius,
                                  environment=lambda d: synthetic.smooth_probe(d @ rot.T),
                                  blocker=photographer(np.array([0, 0, 1.0])))  # fmt: skip
    yaw, plus, minus = best_yaw([view_a, view_b], [CIRCLE, circle_b], convention="physical")
    assert yaw == 90 and plus < minus
    out, weight = merge_views([view_a, view_b], [CIRCLE, circle_b], yaws_deg=[0, yaw],
                              size=128, convention="physical")  # fmt: skip
    dirs, _ = layout_directions("latlong", 128)
    truth = synthetic.smooth_probe(dirs)
    hidden_a = dirs @ [0, 0, 1.0] > math.cos(math.radians(15))
    single = unwrap_ball(view_a, CIRCLE, size=128, convention="physical")
    assert rms(single, truth, hidden_a) > 0.5  # the photographer is there in one view
    assert rms(out, truth, hidden_a) < TWO_VIEW_RMS  # and gone from the merge
    everywhere = weight > 0
    assert everywhere.mean() > 0.99 and rms(out, truth, everywhere) < TWO_VIEW_RMS


def test_grey_card_reflectance():
    photo = np.ones((40, 60, 3), np.float32)
    photo[5:15, 5:15] = [0.5, 0.4, 0.3]
    photo[20:24, 40:44] = [0.35, 0.28, 0.21]
    np.testing.assert_allclose(
        card_reflectance(photo, (5, 5, 10, 10), (40, 20, 4, 4)), 0.7, rtol=1e-5
    )
    with pytest.raises(ArgumentError, match="inside"):
        card_reflectance(photo, (55, 5, 10, 10), (40, 20, 4, 4))


def test_no_ball_and_bad_circles_are_refused():
    flat = np.full((64, 64, 3), 0.5, np.float32)
    with pytest.raises(ArgumentError, match="no edges|no round edge|rim"):
        find_ball(flat)
    with pytest.raises(ArgumentError, match="implausible"):
        unwrap_ball(flat, Circle(10, 10, float("nan")))
    with pytest.raises(ArgumentError, match="convention"):
        unwrap_ball(flat, Circle(32, 32, 20), convention="debevec")
