"""Voxelised sample points: volumes and centroids against the mesh's exact integrals."""

import numpy as np
import pytest
import trimesh

from bakeshop.buoyancy.mass import make_body
from bakeshop.buoyancy.sampling import sample_points
from bakeshop.buoyancy.shapes import SHAPES, make_shape
from bakeshop.errors import ArgumentError
from tests.buoyancy.helpers import body
from tests.files import DATA
from tests.tolerances import BUOYANCY_VOLUME_RTOL


@pytest.mark.parametrize("name", SHAPES)
@pytest.mark.parametrize("resolution", [6, 12])
def test_point_volumes_sum_to_mesh_volume(name, resolution):
    mesh = make_shape(name)
    points = sample_points(mesh, resolution=resolution)
    assert points.volumes.sum() == pytest.approx(mesh.volume, rel=BUOYANCY_VOLUME_RTOL)
    centroid = points.volumes @ points.positions / points.volumes.sum()
    np.testing.assert_allclose(centroid, mesh.center_mass, atol=0.01 * mesh.extents.max())
    assert np.all(points.volumes > 0) and np.all(points.volumes <= points.cell**3 * (1 + 1e-9))


@pytest.mark.parametrize("name", ["cube", "spot", "fish_low_resolution", "torus"])
def test_real_meshes(name):
    mesh = body(DATA / f"{name}.obj")
    points = sample_points(mesh, resolution=10)
    assert points.volumes.sum() == pytest.approx(mesh.volume, rel=BUOYANCY_VOLUME_RTOL)


def test_volumes_match_brute_force_inside_test():
    """Each cell's volume against trimesh's own inside test on a fine grid (independent code)."""
    mesh = trimesh.creation.torus(0.375, 0.125, major_sections=32, minor_sections=12)
    mesh.apply_transform(trimesh.transformations.rotation_matrix(0.4, (1, 1, 0)))
    pts = sample_points(mesh, resolution=4, subsamples=8)
    lo = mesh.bounds[0]
    cell = pts.cell
    n = 8
    grid = (np.arange(n) + 0.5) / n
    for p, v in zip(pts.positions[::5], pts.volumes[::5], strict=True):
        corner = lo + np.floor((p - lo) / cell) * cell
        sub = corner + cell * np.stack(np.meshgrid(grid, grid, grid, indexing="ij"), -1).reshape(
            -1, 3
        )
        brute = mesh.contains(sub).mean() * cell**3
        assert v == pytest.approx(brute, abs=0.06 * cell**3)


def test_rotated_box_volume_exact_along_rays():
    box = trimesh.creation.box(extents=(1.0, 0.3, 0.6))
    box.apply_transform(trimesh.transformations.rotation_matrix(0.3, (0, 1, 0)))
    pts = sample_points(box, resolution=8, subsamples=8)
    assert pts.volumes.sum() == pytest.approx(0.18, rel=2e-3)


def test_body_mass_properties_against_closed_form():
    body = make_body(make_shape("box", size=(2, 0.5, 1)), 500)
    assert body.mass == pytest.approx(500.0)
    np.testing.assert_allclose(
        body.inertia, np.diag([500 / 12 * (0.25 + 1), 500 / 12 * (4 + 1), 500 / 12 * (4 + 0.25)])
    )
    sphere = make_body(make_shape("sphere"), 1000)
    np.testing.assert_allclose(
        sphere.inertia, np.eye(3) * 0.4 * sphere.mass * 0.25, rtol=2e-3, atol=1e-9
    )
    np.testing.assert_allclose(sphere.mesh.center_mass, 0.0, atol=1e-12)


def test_bad_arguments():
    mesh = make_shape("box")
    for bad in (0, 1.5, 5000):
        with pytest.raises(ArgumentError):
            sample_points(mesh, resolution=bad)
    with pytest.raises(ArgumentError):
        sample_points(mesh, subsamples=0)
    with pytest.raises(ArgumentError, match="density"):
        make_body(mesh, float("nan"))
    with pytest.raises(ArgumentError, match="density"):
        make_body(mesh, -3)
    inverted = mesh.copy()
    inverted.invert()
    with pytest.raises(ArgumentError, match="outward"):
        make_body(inverted, 500)
    with pytest.raises(ArgumentError, match="closed"):
        make_body(trimesh.Trimesh(mesh.vertices, mesh.faces[:-1]), 500)
