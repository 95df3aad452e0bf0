"""The team's experiment done properly: every shape x frame rate x treatment x force mode.

A *treatment* is a damping and a stabiliser together (see :data:`TREATMENTS`). Each cell of the
matrix releases all shapes at once (they do not interact in the built-in backend) from deep
water and records the test bench's numbers for each.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bakeshop import progress
from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import clearance, summarize
from bakeshop.buoyancy.shapes import SHAPES, make_shape
from bakeshop.buoyancy.stepping import FORCE_MODES, release, simulate
from bakeshop.buoyancy.water import Water
from bakeshop.errors import validate_choice

#: Treatments: name -> (damping, stabiliser).
TREATMENTS = {
    "none": ("none", "none"),
    "team": ("team", "none"),
    "team+predict": ("team", "predict"),
    "team+clamp": ("team", "clamp"),
    "drag": ("drag", "none"),
    "drag+predict": ("drag", "predict"),
}
#: The frame rates the team cared about.
FRAME_RATES = (10, 20, 30, 60)
#: Columns of the CSV, in order.
COLUMNS = (
    "shape", "forces", "treatment", "fps", "volume_m3", "mass_kg", "points",
    "archimedes_draft_m", "draft_m", "times_left_water", "max_jump_m", "settle_time_s",
)  # fmt: skip


@dataclass
class Matrix:
    """Rows (one dict per shape and cell, keys :data:`COLUMNS`) and, per cell
    ``(forces, treatment, fps)``, the time axis and the (S, B) clearance of every shape."""

    shapes: tuple[str, ...]
    rows: list[dict]
    clearances: dict


def run_matrix(
    *,
    shapes: Sequence[str] = SHAPES,
    frame_rates: Sequence[float] = FRAME_RATES,
    treatments: Sequence[str] = tuple(TREATMENTS),
    modes: Sequence[str] = FORCE_MODES,
    density: float = 500.0,
    release_height: float = -2.0,
    seconds: float = 8.0,
    resolution: int = 8,
    solver_hz: float = 60.0,
    water: Water | None = None,
) -> Matrix:
    """Run the matrix with the built-in backend (see the module docstring)."""
    for t in treatments:
        validate_choice(t, tuple(TREATMENTS), "treatment")
    for m in modes:
        validate_choice(m, FORCE_MODES, "force mode")
    water = Water() if water is None else water
    fleet = pack([make_body(make_shape(s), density, resolution=resolution) for s in shapes])
    start = release(fleet, water, height=release_height)
    cells = [(m, t, f) for m in modes for t in treatments for f in frame_rates]
    rows, clearances = [], {}
    for mode, treatment, fps in progress.track(cells, "floating the matrix"):
        damping, stabilize = TREATMENTS[treatment]
        model = ForceModel(damping=damping, stabilize=stabilize)
        trace = simulate(
            fleet, start, water, model, seconds=seconds, fps=fps, solver_hz=solver_hz, forces=mode
        )
        clearances[(mode, treatment, fps)] = (trace.time, clearance(fleet, trace, water))
        for shape, summary in zip(shapes, summarize(fleet, trace, water, model), strict=True):
            rows.append(
                {"shape": shape, "forces": mode, "treatment": treatment, "fps": fps} | summary
            )
    return Matrix(tuple(shapes), rows, clearances)


def to_csv(matrix: Matrix) -> str:
    """Every row of the matrix as CSV text."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in matrix.rows:
        writer.writerow({k: _fmt(row[k]) for k in COLUMNS})
    return out.getvalue()


def to_markdown(matrix: Matrix) -> str:
    """Summary table: per force mode and treatment (rows) and frame rate (columns), how many
    shapes ever left the water after entering it, and the highest jump (m) among them."""
    fps_list = sorted({r["fps"] for r in matrix.rows})
    keys = list(dict.fromkeys((r["forces"], r["treatment"]) for r in matrix.rows))
    n = len(matrix.shapes)
    lines = [
        "| forces | treatment | " + " | ".join(f"{f} fps" for f in fps_list) + " |",
        "|---|---|" + "---|" * len(fps_list),
    ]
    for mode, treatment in keys:
        cells = []
        for fps in fps_list:
            sel = [
                r for r in matrix.rows
                if (r["forces"], r["treatment"], r["fps"]) == (mode, treatment, fps)
            ]  # fmt: skip
            left = sum(r["times_left_water"] > 0 for r in sel)
            jump = max(r["max_jump_m"] for r in sel)
            cells.append(f"{left}/{n} left, {jump:.2f} m" if left else f"0/{n}")
        lines.append(f"| {mode} | {treatment} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _fmt(value: object) -> object:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}" if np.isfinite(value) else "nan"
    return value
