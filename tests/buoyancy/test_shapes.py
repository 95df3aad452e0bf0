"""Built-in shapes and mesh loading: closed meshes of the advertised size; bad files refused."""

import numpy as np
import pytest
import trimesh

from bakeshop.buoyancy.shapes import SHAPES, make_shape
from bakeshop.errors import ArgumentError, BakeshopError, FormatError
from bakeshop.io import load_mesh
from tests.buoyancy.helpers import body
from tests.files import DATA


@pytest.mark.parametrize("name", SHAPES)
def test_shapes_are_closed_and_about_a_metre(name):
    mesh = make_shape(name)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume > 0
    assert mesh.extents.max() == pytest.approx(1.0, rel=1e-9)
    np.testing.assert_allclose(mesh.bounds.mean(axis=0), 0.0, atol=1e-9)


def test_size_sets_longest_side_or_extents():
    assert make_shape("sphere", size=3.0).extents.max() == pytest.approx(3.0)
    np.testing.assert_allclose(make_shape("box", size=(2, 0.5, 1)).extents, (2, 0.5, 1))
    assert make_shape("box", size=(2, 0.5, 1)).volume == pytest.approx(1.0)


def test_bad_shape_and_size():
    with pytest.raises(ArgumentError, match="unknown shape 'boat'"):
        make_shape("boat")
    for bad in (0.0, -1.0, (1, 2), float("nan")):
        with pytest.raises(ArgumentError):
            make_shape("box", size=bad)


@pytest.mark.parametrize(
    ("name", "volume"),
    [
        ("cube", 8.0),
        ("sphere", 4.1527),
        ("torus", 1.2188),
        ("spot", 0.688),
        ("fish_low_resolution", 1.1146),
    ],
)
def test_real_meshes_weld_into_closed_solids(name, volume):
    mesh = body(DATA / f"{name}.obj")
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx(volume, rel=1e-3)


def test_open_mesh_is_refused_or_repaired(tmp_path):
    box = trimesh.creation.box()
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-1])
    path = tmp_path / "open.stl"
    open_box.export(path)
    with pytest.raises(FormatError, match="not watertight"):
        body(path)
    repaired = body(path, repair=True)
    assert repaired.is_watertight and repaired.volume == pytest.approx(1.0)


def test_unreadable_files(tmp_path):
    junk = tmp_path / "junk.ply"
    junk.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99999999\n")
    with pytest.raises(BakeshopError):
        load_mesh(junk)
    with pytest.raises(FormatError, match="extension"):
        load_mesh(tmp_path / "mesh.xyz")
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing\n")
    with pytest.raises(FormatError):
        load_mesh(empty)


@pytest.mark.parametrize("suffix", [".obj", ".stl", ".ply", ".glb", ".off"])
def test_mesh_formats_round_trip(tmp_path, suffix):
    """Every advertised format through trimesh's own writers: same closed solid back."""
    peep = make_shape("peep")
    path = tmp_path / f"peep{suffix}"
    peep.export(path)
    mesh = body(path)
    assert mesh.volume == pytest.approx(peep.volume, rel=1e-6)
    np.testing.assert_allclose(mesh.center_mass, peep.center_mass, atol=1e-6)
