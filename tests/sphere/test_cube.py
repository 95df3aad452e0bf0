"""Cube face sets and pictures: conventions and crosses/strips as arrangements of faces."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.sphere import cube_to_faces, cube_to_view, faces_to_cube, layout, view_to_cube
from bakeshop.sphere.cube import FACE_BASES, VIEWS


@pytest.fixture
def cube():
    return np.random.default_rng(0).random((6, 5, 5, 3)).astype(np.float32)


@pytest.mark.parametrize("view", list(VIEWS))
def test_views_round_trip_and_leave_unused_squares_empty(cube, view):
    picture = cube_to_view(cube, view)
    np.testing.assert_array_equal(view_to_cube(picture, view), cube)
    _, valid = layout(view).directions(picture.shape[:2])
    assert np.all(picture[~valid] == 0)
    assert valid.sum() == 6 * 25


@pytest.mark.parametrize("convention", ["opengl", "vulkan", "directx"])
def test_conventions_invert(cube, convention):
    np.testing.assert_array_equal(
        faces_to_cube(cube_to_faces(cube, convention=convention), convention=convention), cube
    )


def test_opengl_and_vulkan_are_the_internal_cube(cube):
    for convention in ("opengl", "vulkan"):
        np.testing.assert_array_equal(cube_to_faces(cube, convention=convention), cube)


def test_directx_face_f_holds_the_mirrored_directions():
    """Texel (i, j) of directx face F shows our direction (x, y, -z), where (x, y, z) is
    OpenGL's direction of face F at that texel (the table of DESIGN.md)."""
    s = 6
    dirs, _ = layout("cube").directions((6, s, s))
    dx = cube_to_faces(dirs, convention="directx")
    t = 2 * (np.arange(s) + 0.5) / s - 1
    sc, tc = np.meshgrid(t, t)
    for f in range(6):
        n, u, v = FACE_BASES[f]
        gl = n + sc[..., None] * u + tc[..., None] * v
        gl /= np.linalg.norm(gl, axis=-1, keepdims=True)
        np.testing.assert_allclose(dx[f], gl * [1, 1, -1], atol=1e-12)


def test_bad_convention_and_shape(cube):
    with pytest.raises(ArgumentError, match="convention"):
        cube_to_faces(cube, convention="metal")
    with pytest.raises(ArgumentError, match="cube"):
        cube_to_faces(cube[:5])
