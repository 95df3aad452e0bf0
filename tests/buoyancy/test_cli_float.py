"""``bakeshop float``: numbers, JSON, plots, the matrix files, and one-line errors."""

import json

import pytest

from bakeshop.cli.main import main
from tests.files import DATA


def test_float_json_box(capsys):
    code = main(["float", "--shape", "box", "--size", "1x0.5x1", "--density", "500",
                 "--release-height", "-0.1", "--seconds", "6", "--json"])  # fmt: skip
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["volume_m3"] == pytest.approx(0.5)
    assert out["mass_kg"] == pytest.approx(250.0)
    assert out["archimedes_draft_m"] == pytest.approx(0.25)
    assert out["draft_m"] == pytest.approx(0.25, rel=1e-2)
    assert out["times_left_water"] == 0 and out["max_jump_m"] == 0.0
    assert out["points"] > 0 and out["settle_time_s"] is not None


@pytest.mark.slow
def test_float_mesh_with_plot_mujoco_and_waves(tmp_path, capsys):
    plot = tmp_path / "trace.png"
    code = main(["float", str(DATA / "spot.obj"), "--size", "1",
                 "--density", "600", "--resolution", "6", "--seconds", "2", "--waves", "0.1:6:30",
                 "--backend", "mujoco", "--plot", str(plot)])  # fmt: skip
    assert code == 0
    text = capsys.readouterr().out
    assert "archimedes_draft_m" in text and "times_left_water" in text
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_float_matrix_writes_table_csv_and_grid(tmp_path, monkeypatch, capsys):
    from bakeshop.buoyancy import matrix

    # a small matrix: two shapes, two frame rates (the full one runs in the docs script)
    real = matrix.run_matrix

    def small(**kw):
        return real(shapes=("box", "peep"), frame_rates=(10, 60), **kw)

    monkeypatch.setattr(matrix, "run_matrix", small)
    out = tmp_path / "m"
    assert main(["float", "--matrix", "--seconds", "3", "--out", str(out)]) == 0
    md = (tmp_path / "m.md").read_text()
    assert "| per-frame | none |" in md and "10 fps" in md
    rows = (tmp_path / "m.csv").read_text().splitlines()
    assert rows[0].startswith("shape,forces,treatment,fps,volume_m3")
    assert len(rows) == 1 + 2 * 2 * 6 * 2
    assert (tmp_path / "m.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--density", "500"], "either a mesh file or a built-in shape"),
        (["--shape", "boat"], "unknown shape 'boat'"),
        (["--shape", "box", "--density", "-1"], "density"),
        (["--shape", "box", "--size", "1x2"], "1 or 3 numbers"),
        (["--shape", "box", "--waves", "1:2:3:4:5"], "(2 to 4 numbers)"),
        (["--shape", "box", "--fps", "0"], "fps"),
        (["--shape", "box", "--matrix"], "--matrix"),
        (["--shape", "box", "--release-height", "nan"], "finite"),
        (["--shape", "box", "--tilt", "inf"], "tilt"),
    ],
)
def test_float_errors_are_one_line(args, message, capsys):
    assert main(["float", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bakeshop: error:") and message in err and err.count("\n") == 1


def test_float_open_mesh(tmp_path, capsys):
    import trimesh

    box = trimesh.creation.box()
    trimesh.Trimesh(box.vertices, box.faces[:-2]).export(tmp_path / "open.stl")
    assert main(["float", str(tmp_path / "open.stl")]) == 2
    assert "not watertight" in capsys.readouterr().err


def test_the_buoyancy_extra_is_named_when_missing(tmp_path, monkeypatch, capsys):
    """mujoco and networkx are the [buoyancy] extra: without them, one line says what to install."""
    import sys

    import trimesh

    monkeypatch.setitem(sys.modules, "mujoco", None)  # "import mujoco" now fails
    monkeypatch.delitem(sys.modules, "bakeshop.buoyancy.mujoco_backend", raising=False)
    assert main(["float", "--shape", "box", "--seconds", "0.1", "--backend", "mujoco"]) == 2
    err = capsys.readouterr().err
    assert "pip install 'bakeshop[buoyancy]'" in err and err.count("\n") == 1

    monkeypatch.setitem(sys.modules, "networkx", None)
    box = trimesh.creation.box()
    trimesh.Trimesh(box.vertices, box.faces[:-2]).export(tmp_path / "open.stl")
    assert main(["float", str(tmp_path / "open.stl"), "--repair"]) == 2
    err = capsys.readouterr().err
    assert "open.stl" in err and "pip install 'bakeshop[buoyancy]'" in err
    assert err.count("\n") == 1


def test_float_text_explains_every_number(capsys):
    """Each line is key, value and what it means; a "-" (JSON null) says why it is missing."""
    from bakeshop.cli.float import SUMMARY

    args = ["float", "--shape", "box", "--seconds", "1", "--resolution", "4"]
    assert main([*args, "--density", "1500"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == list(SUMMARY)
    table = {line.split()[0]: line for line in lines}
    assert table["archimedes_draft_m"].split()[1] == "-" and "sinks" in table["archimedes_draft_m"]
    assert "never" in table["settle_time_s"]  # still falling through the water at the end
    assert all(len(line) <= 100 and len(line.split()) > 3 for line in lines)
    assert main([*args, "--json"]) == 0
    assert list(json.loads(capsys.readouterr().out)) == list(SUMMARY)


def test_a_non_manifold_mesh_says_what_is_wrong(tmp_path, capsys):
    """Two cubes sharing one edge: no hole, but that edge has four triangles."""
    import numpy as np
    import trimesh

    a = trimesh.creation.box()
    b = trimesh.creation.box()
    b.apply_translation((1, 1, 0))
    trimesh.util.concatenate([a, b]).export(tmp_path / "touching.obj")
    assert main(["float", str(tmp_path / "touching.obj")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "open edges" not in err
    assert "1 non-manifold edges (shared by 3 or more triangles)" in err
    # a hole and a fin together: both are counted
    fin = trimesh.Trimesh(np.r_[a.vertices, [[0.5, 0.5, 2]]], np.r_[a.faces[1:], [[6, 7, 8]]])
    fin.export(tmp_path / "fin.obj")
    assert main(["float", str(tmp_path / "fin.obj")]) == 2
    err = capsys.readouterr().err
    assert "open edges (of one triangle) and 1 non-manifold edges" in err


def test_a_mesh_past_the_memory_bound_is_refused_naming_the_option(monkeypatch):
    import trimesh

    from bakeshop import resources
    from bakeshop.buoyancy import bench
    from bakeshop.errors import BakeshopError

    cost = bench.float_mesh_cost(5_000_000, 10)
    assert cost.work >= 60 and cost.memory >= 4e9  # 5 million triangles: a minute and more
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": 40 << 20})
    box = trimesh.creation.box()
    with pytest.raises(BakeshopError, match="--resolution lowers") as e:
        bench.float_body(box, density=500, resolution=100, path="box.obj")
    assert e.value.path == "box.obj" and "needs about 64" in e.value.reason


def test_a_slow_mesh_says_how_long_in_its_progress(monkeypatch):
    import trimesh

    from bakeshop import progress
    from bakeshop.buoyancy import shapes

    seen, step = [], progress.step
    monkeypatch.setattr(progress, "step", lambda text: seen.append(text) or step(text))
    shapes.closed_mesh(trimesh.creation.box())
    monkeypatch.setattr(shapes, "FACE_SECONDS", 1.0)
    shapes.closed_mesh(trimesh.creation.box())
    assert seen == [
        "closing the mesh (12 triangles)",
        "closing the mesh (12 triangles, about 12 s with its sampling)",
    ]
