"""Pictures of floating runs (matplotlib, drawn off-screen): a trace and the matrix grid, as
``(H, W, 3)`` uint8 pictures (:func:`bakeshop.io.write_image` saves them)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from bakeshop.figures import new_figure, to_rgb

if TYPE_CHECKING:
    from bakeshop.buoyancy.matrix import Matrix


def plot_trace(
    time: np.ndarray,
    clear: np.ndarray,
    *,
    labels: Sequence[str],
    title: str,
    draft: Sequence[float | None] | None = None,
) -> np.ndarray:
    """The clearance (height of the lowest point above the water, m) of each body over time
    (s); ``draft`` (optional, m per body) is drawn as the expected settled clearance
    ``-draft``. Every line is named in the legend. Returns the picture, ``(H, W, 3)`` uint8."""
    entries = len(labels) * (2 if draft is not None else 1) + 1  # in the legend, below
    columns = 3 if max(map(len, labels)) <= 30 else 2
    rows = -(-entries // columns)
    height = 3.4 + 0.16 * rows  # inches; a legend row of 7-point text is about 0.16 in
    fig = new_figure(8, height, dpi=90)
    ax = fig.subplots()
    ax.axhline(0.0, color="k", lw=0.8, alpha=0.6, label="water surface")
    for b, label in enumerate(labels):
        (line,) = ax.plot(time, clear[:, b], lw=1.2, label=label)
        settled = None if draft is None else draft[b]
        if settled is not None:
            rest = "at rest (Archimedes draft)" + (f": {label}" if len(labels) > 1 else "")
            ax.axhline(-settled, color=line.get_color(), lw=0.8, ls=":", label=rest)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("lowest point above water (m)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    fig.legend(fontsize=7, loc="lower center", ncol=columns, frameon=False)
    fig.tight_layout(rect=(0, (0.16 * rows + 0.05) / height, 1, 1))
    return to_rgb(fig)


def plot_grid(matrix: Matrix, *, forces: str = "per-frame") -> np.ndarray:
    """The matrix as a grid of clearance traces: treatments down, frame rates across, one line
    per shape, for one force mode. Returns the picture, ``(H, W, 3)`` uint8."""
    keys = [k for k in matrix.clearances if k[0] == forces]
    treatments = list(dict.fromkeys(k[1] for k in keys))
    rates = sorted({k[2] for k in keys})
    height = 1.7 * len(treatments) + 0.3  # inches, with a row of legend below the grid
    fig = new_figure(2.6 * len(rates), height, dpi=80)
    axes = fig.subplots(len(treatments), len(rates), sharex=True, sharey=True, squeeze=False)
    for i, treatment in enumerate(treatments):
        for j, fps in enumerate(rates):
            ax = axes[i, j]
            time, clear = matrix.clearances[(forces, treatment, fps)]
            for b, shape in enumerate(matrix.shapes):
                ax.plot(time, np.clip(clear[:, b], -3, 3), lw=0.7, label=shape)
            ax.axhline(0.0, color="k", lw=0.5, alpha=0.5, label="water surface")
            ax.set_ylim(-2.6, 2.0)
            if i == 0:
                ax.set_title(f"{fps} fps", fontsize=9)
            if j == 0:
                ax.set_ylabel(treatment, fontsize=8)
            ax.tick_params(labelsize=7)
    fig.legend(
        *axes[0, 0].get_legend_handles_labels(),
        fontsize=7,
        loc="lower center",
        ncol=len(matrix.shapes) + 1,
        frameon=False,
    )
    fig.suptitle(
        f"lowest point above water (m) vs time (s), forces {forces}\n"
        "rows: damping + stabiliser; columns: frame rate",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0.3 / height, 1, 1))
    return to_rgb(fig)
