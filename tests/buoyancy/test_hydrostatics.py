"""Exact clipping against closed forms: displaced volumes and Archimedes drafts."""

import numpy as np
import pytest
import trimesh

from bakeshop.buoyancy.hydrostatics import archimedes_draft, submerged_volume, waterplane_area
from bakeshop.buoyancy.shapes import make_shape
from tests.buoyancy.helpers import cylinder_draft, sphere_draft
from tests.files import DATA
from tests.tolerances import BUOYANCY_ARCHIMEDES_RTOL, BUOYANCY_CLIPPING_EXACT


def test_tilted_box_volume_exact():
    """A cube on its edge (45 degrees): below y=c the section is a triangle prism, closed form."""
    box = trimesh.creation.box(extents=(1, 1, 1))
    box.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 4, (0, 0, 1)))
    low = box.bounds[0, 1]
    for depth in (0.1, 0.3, 0.7):
        assert submerged_volume(box.triangles, low + depth) == pytest.approx(
            depth**2, rel=BUOYANCY_CLIPPING_EXACT
        )
    assert submerged_volume(box.triangles, 5.0) == pytest.approx(1.0, rel=BUOYANCY_CLIPPING_EXACT)
    assert submerged_volume(box.triangles, -5.0) == 0.0


@pytest.mark.parametrize("density", [150, 500, 850])
def test_archimedes_drafts_match_analytic(density):
    box = make_shape("box", size=(2, 0.5, 1))
    assert archimedes_draft(box.triangles, density * 1.0) == pytest.approx(
        0.5 * density / 1000, rel=BUOYANCY_CLIPPING_EXACT
    )
    sphere = make_shape("sphere")
    mass = density * 4 / 3 * np.pi * 0.125
    assert archimedes_draft(sphere.triangles, mass) == pytest.approx(
        sphere_draft(0.5, density), rel=BUOYANCY_ARCHIMEDES_RTOL
    )
    cylinder = make_shape("cylinder")
    mass = density * np.pi * 0.25
    assert archimedes_draft(cylinder.triangles, mass) == pytest.approx(
        cylinder_draft(0.5, density), rel=BUOYANCY_ARCHIMEDES_RTOL
    )


def test_too_dense_to_float():
    box = make_shape("box")
    assert archimedes_draft(box.triangles, 1200.0) is None


def test_submerged_volume_matches_manifold3d_on_a_real_mesh():
    from tests.buoyancy.helpers import body, clipped_below

    mesh = body(DATA / "spot.obj")
    mesh.apply_transform(trimesh.transformations.rotation_matrix(0.5, (1, 0, 1)))
    for level in np.linspace(*mesh.bounds[:, 1], 7)[1:-1]:
        reference = clipped_below(mesh, level).volume
        # manifold3d works in float32 vertices: agreement to ~1e-6 relative
        assert submerged_volume(mesh.triangles, level) == pytest.approx(reference, rel=1e-5)


def test_waterplane_area():
    box = make_shape("box", size=(2, 0.5, 1))
    assert waterplane_area(box.triangles, 0.1) == pytest.approx(2.0, rel=1e-9)
    sphere = make_shape("sphere")
    assert waterplane_area(sphere.triangles, 0.0) == pytest.approx(np.pi * 0.25, rel=1e-3)
    assert waterplane_area(sphere.triangles, 0.3) == pytest.approx(np.pi * (0.25 - 0.09), rel=2e-3)
