"""The golf course's DIM shadows: a fragment the sun's shadow map sees takes the sun DIM, a
shadowed one the shadow DIM (numpy lookups of the same DIMs), and the shadows fall where a ray
cast to sun.json's sun in numpy says."""

import numpy as np
import pytest

from bakeshop.preview import Renderer, View
from bakeshop.preview.reference import latlong_bilinear
from bakeshop.preview.scene import GRASS, height_field
from tests.preview.bakes import SUN, synthetic_bake
from tests.preview.tolerances import PREVIEW_LINEAR_RTOL

W, H = 320, 180
#: metres a sun ray must clear an occluder by (or pass inside it by) to count as unambiguous:
#: the shadow map's texel (about 0.1 m), the terrain's triangles against its smooth formula.
MARGIN = 0.5


@pytest.fixture(scope="module")
def golf():
    with Renderer(synthetic_bake()) as r:
        view = View("golf", W, H, water=False)
        colour = r.render(view)[..., :3]
        normal_lit = r.render(view, mode=1)
        albedo = r.render(view, mode=2)[..., :3]
        position = r.render(view, mode=5)
        yield r, colour, normal_lit, albedo, position


def test_lit_fragments_take_the_sun_dim_and_shadowed_ones_the_shadow_dim(golf):
    r, colour, normal_lit, albedo, position = golf
    drawn = position[..., 3] > 0.5
    n = normal_lit[..., :3][drawn].astype(np.float64)
    lit = normal_lit[..., 3][drawn] > 0.5
    assert 0.1 < lit.mean() < 0.95  # both kinds of fragment are on screen
    expected = (
        np.where(
            lit[:, None],
            latlong_bilinear(r.bake.sun_dim, n),
            latlong_bilinear(r.bake.shadow_dim, n),
        )
        * albedo[drawn]
    )
    np.testing.assert_allclose(colour[drawn], expected, rtol=PREVIEW_LINEAR_RTOL, atol=1e-5)


def _ray_box(origin, direction, lo, hi):
    """Slab test: does each ray (origin + t direction, t > 0) pass through the box?"""
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (np.asarray(lo) - origin) / direction
        t2 = (np.asarray(hi) - origin) / direction
    near = np.nanmax(np.minimum(t1, t2), axis=1)
    far = np.nanmin(np.maximum(t1, t2), axis=1)
    return (far >= np.maximum(near, 0)) & (far > 0)


def _terrain_clearance(points, half):
    """The least height of each sun ray above the course's ground (its smooth formula), over the
    square; negative where the ground is in the way."""
    least = np.full(len(points), np.inf)
    for t in np.arange(4.0, 250.0, 0.5):  # from 4 m: the first metres graze its own slope
        p = points + t * SUN
        inside = (np.abs(p[:, 0]) <= half) & (np.abs(p[:, 2]) <= half)
        gap = p[:, 1] - height_field(p[:, 0], p[:, 2])
        least = np.where(inside, np.minimum(least, gap), least)
    return least


def test_shadows_fall_where_the_sun_ray_says(golf):
    """Ground fragments: lit exactly when a numpy ray towards sun.json's sun clears the boxes and
    the terrain, wherever that answer is unambiguous (trees, alpha-cut, are left out)."""
    r, _, normal_lit, albedo, position = golf
    ground = (position[..., 3] > 0.5) & (np.abs(albedo - GRASS).max(axis=-1) < 1e-6)
    p = position[..., :3][ground].astype(np.float64)
    n = normal_lit[..., :3][ground].astype(np.float64)
    lit = normal_lit[..., 3][ground] > 0.5
    d = np.broadcast_to(SUN, p.shape)
    blocked = np.zeros(len(p), bool)
    ambiguous = (n @ SUN) < 0.05
    for lo, hi in r.golf.boxes:
        lo, hi = np.asarray(lo), np.asarray(hi)
        blocked |= _ray_box(p, d, lo + MARGIN, hi - MARGIN)
        ambiguous |= _ray_box(p, d, lo - MARGIN, hi + MARGIN) & ~_ray_box(
            p, d, lo + MARGIN, hi - MARGIN
        )
    for base, height, width in r.golf.trees:
        base = np.asarray(base)
        reach = np.array([width / 2 + MARGIN, 0.0, width / 2 + MARGIN])
        ambiguous |= _ray_box(p, d, base - reach - [0, MARGIN, 0], base + reach + [0, height, 0])
    clearance = _terrain_clearance(p, r.golf.half)
    blocked |= clearance < -MARGIN
    ambiguous |= np.abs(clearance) <= MARGIN
    sure = ~ambiguous
    by_box = blocked & sure & (clearance > MARGIN)
    assert sure.mean() > 0.5 and by_box.sum() > 50  # the clubhouse's shadow is in view
    np.testing.assert_array_equal(lit[sure], ~blocked[sure])
