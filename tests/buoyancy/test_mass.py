"""Rigid bodies (bakeshop.buoyancy.mass): mass, centre of mass and inertia against the closed
forms of a uniform box, and the packing of a fleet."""

import numpy as np
import pytest
import trimesh

from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.errors import ArgumentError
from tests.tolerances import BUOYANCY_FLOAT64, BUOYANCY_VOLUME_RTOL

EXTENTS = (2.0, 0.5, 1.0)
DENSITY = 600.0


def _box(extents=EXTENTS, at=(0.0, 0.0, 0.0)):
    box = trimesh.creation.box(extents=extents)
    box.apply_translation(at)
    return box


def test_a_box_has_the_closed_form_mass_centre_and_inertia():
    a, b, c = EXTENTS
    body = make_body(_box(at=(3.0, -1.0, 0.25)), DENSITY, resolution=6)
    mass = DENSITY * a * b * c
    assert body.mass == pytest.approx(mass, rel=BUOYANCY_FLOAT64)
    assert body.volume == pytest.approx(a * b * c, rel=BUOYANCY_FLOAT64)
    np.testing.assert_allclose(body.offset, [3.0, -1.0, 0.25], atol=BUOYANCY_FLOAT64)
    inertia = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(body.inertia, inertia, atol=BUOYANCY_FLOAT64 * mass)
    # the body frame has its origin at the centre of mass
    np.testing.assert_allclose(body.mesh.center_mass, 0.0, atol=BUOYANCY_FLOAT64)


def test_the_hull_of_a_box_is_its_corners_about_the_centre_of_mass():
    body = make_body(_box(at=(1.0, 2.0, 3.0)), DENSITY, resolution=4)
    corners = np.array(np.meshgrid(*[[-e / 2, e / 2] for e in EXTENTS], indexing="ij"))
    corners = corners.reshape(3, -1).T
    hull = body.hull_vertices
    assert hull.shape == (8, 3)
    key = np.lexsort(hull.T)
    np.testing.assert_allclose(hull[key], corners[np.lexsort(corners.T)], atol=BUOYANCY_FLOAT64)


def test_sample_points_carry_the_volume():
    body = make_body(_box(), DENSITY, resolution=8)
    assert body.points.volumes.sum() == pytest.approx(body.volume, rel=BUOYANCY_VOLUME_RTOL)


@pytest.mark.parametrize("density", [0.0, -1.0, float("nan"), float("inf")])
def test_a_density_that_is_not_positive_and_finite_is_refused(density):
    with pytest.raises(ArgumentError):
        make_body(_box(), density)


def test_an_open_mesh_is_refused():
    box = _box()
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-2], process=False)
    assert not open_box.is_watertight
    with pytest.raises(ArgumentError):
        make_body(open_box, DENSITY)


def test_pack_lays_the_bodies_end_to_end():
    small = make_body(_box((1.0, 1.0, 1.0)), 500.0, resolution=4)
    large = make_body(_box(), DENSITY, resolution=6)
    fleet = pack([small, large])
    n0, n1 = len(small.points), len(large.points)
    assert len(fleet) == 2
    np.testing.assert_array_equal(fleet.offsets, [0, n0, n0 + n1])
    np.testing.assert_array_equal(fleet.points[n0:], large.points.positions)
    np.testing.assert_array_equal(fleet.volumes[:n0], small.points.volumes)
    np.testing.assert_array_equal(fleet.heights[n0:], large.points.heights)
    np.testing.assert_array_equal(fleet.mass, [small.mass, large.mass])
    np.testing.assert_array_equal(fleet.volume, [small.volume, large.volume])
    identity = np.einsum("bij,bjk->bik", fleet.inverse_inertia, fleet.inertia)
    np.testing.assert_allclose(identity, np.broadcast_to(np.eye(3), (2, 3, 3)), atol=1e-9)


def test_an_empty_fleet_is_refused():
    with pytest.raises(ArgumentError):
        pack([])
