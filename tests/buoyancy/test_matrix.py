"""The experiment matrix (bakeshop.buoyancy.matrix): one small run, its rows, and the CSV and
Markdown it is reported as (read back with the csv module)."""

import csv
import io

import numpy as np
import pytest

from bakeshop.buoyancy.matrix import COLUMNS, TREATMENTS, Matrix, run_matrix, to_csv, to_markdown
from bakeshop.errors import ArgumentError


@pytest.fixture(scope="module")
def small():
    return run_matrix(shapes=("box", "sphere"), frame_rates=(30, 60), treatments=("none", "team"),
                      modes=("per-frame",), seconds=1.0, resolution=4)  # fmt: skip


@pytest.mark.slow
def test_a_run_has_a_row_per_shape_and_cell(small):
    assert small.shapes == ("box", "sphere")
    assert len(small.rows) == 2 * 2 * 2
    cells = {(r["forces"], r["treatment"], r["fps"]) for r in small.rows}
    assert cells == {("per-frame", t, f) for t in ("none", "team") for f in (30, 60)}
    assert set(small.clearances) == cells
    for row in small.rows:
        assert set(row) == set(COLUMNS)
    time, clear = small.clearances[("per-frame", "none", 30)]
    assert clear.shape == (time.size, 2)


@pytest.mark.slow
def test_the_csv_reads_back_as_the_rows(small):
    rows = list(csv.DictReader(io.StringIO(to_csv(small))))
    assert len(rows) == len(small.rows)
    for got, row in zip(rows, small.rows, strict=True):
        assert tuple(got) == COLUMNS
        assert got["shape"] == row["shape"] and int(got["fps"]) == row["fps"]
        assert float(got["mass_kg"]) == pytest.approx(row["mass_kg"], rel=1e-5)
        expected = "" if row["settle_time_s"] is None else row["settle_time_s"]
        assert (got["settle_time_s"] == "") == (expected == "")


def _fake(rows):
    return Matrix(("a", "b"), rows, {})


def _row(treatment, fps, left, jump):
    return {"forces": "per-frame", "treatment": treatment, "fps": fps,
            "times_left_water": left, "max_jump_m": jump}  # fmt: skip


def test_markdown_counts_the_shapes_that_left_the_water():
    rows = [_row("none", 30, 2, 1.25), _row("none", 30, 0, 0.0), _row("none", 60, 0, 0.0),
            _row("none", 60, 0, 0.0), _row("team", 30, 0, 0.0), _row("team", 30, 1, 0.5),
            _row("team", 60, 0, 0.0), _row("team", 60, 0, 0.0)]  # fmt: skip
    lines = to_markdown(_fake(rows)).splitlines()
    assert lines[0] == "| forces | treatment | 30 fps | 60 fps |"
    assert lines[2] == "| per-frame | none | 1/2 left, 1.25 m | 0/2 |"
    assert lines[3] == "| per-frame | team | 1/2 left, 0.50 m | 0/2 |"
    assert len(lines) == 4


def test_csv_writes_none_as_empty_and_floats_to_six_digits():
    row = dict.fromkeys(COLUMNS, None) | {"shape": "box", "fps": 30, "mass_kg": 1 / 3,
                                           "draft_m": float("nan")}  # fmt: skip
    (got,) = csv.DictReader(io.StringIO(to_csv(_fake([row]))))
    assert got["mass_kg"] == "0.333333"
    assert got["draft_m"] == "nan"
    assert got["settle_time_s"] == ""
    assert got["fps"] == "30"


@pytest.mark.parametrize("bad", [{"treatments": ("none", "magic")}, {"modes": ("sometimes",)}])
def test_unknown_treatments_and_modes_are_refused_before_running(bad):
    with pytest.raises(ArgumentError):
        run_matrix(shapes=("box",), **bad)


def test_every_treatment_names_a_damping_and_a_stabiliser():
    assert all(len(v) == 2 for v in TREATMENTS.values())
    assert np.unique(list(TREATMENTS.values()), axis=0).shape[0] == len(TREATMENTS)
