"""Pictures of floating runs (matplotlib, drawn off-screen): a trace and the matrix grid."""

from __future__ import annotations

import os

import numpy as np

from bakeshop.io._files import atomic_path


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_trace(path: str | os.PathLike, time, clear, *, labels, title: str, draft=None) -> None:
    """Draw the clearance (height of the lowest point above the water, m) of each body over
    time (s) into a PNG at ``path``; ``draft`` (optional, m per body) is drawn as the expected
    settled clearance ``-draft``."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6), dpi=90)
    for b, label in enumerate(labels):
        (line,) = ax.plot(time, clear[:, b], lw=1.2, label=label)
        if draft is not None and draft[b] is not None:
            ax.axhline(-draft[b], color=line.get_color(), lw=0.8, ls=":")
    ax.axhline(0.0, color="tab:blue", lw=0.8, alpha=0.5)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("lowest point above water (m)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    if len(labels) > 1:
        ax.legend(fontsize=7, loc="lower left", ncol=2 if len(labels) > 2 else 1)
    fig.tight_layout()
    _save(fig, path)


def plot_grid(path: str | os.PathLike, matrix, *, forces: str = "per-frame") -> None:
    """The matrix as a grid of clearance traces: treatments down, frame rates across, one line
    per shape, for one force mode."""
    plt = _pyplot()
    keys = [k for k in matrix.clearances if k[0] == forces]
    treatments = list(dict.fromkeys(k[1] for k in keys))
    rates = sorted({k[2] for k in keys})
    fig, axes = plt.subplots(
        len(treatments), len(rates), figsize=(2.6 * len(rates), 1.7 * len(treatments)),
        dpi=80, sharex=True, sharey=True, squeeze=False,
    )  # fmt: skip
    for i, treatment in enumerate(treatments):
        for j, fps in enumerate(rates):
            ax = axes[i, j]
            time, clear = matrix.clearances[(forces, treatment, fps)]
            for b, shape in enumerate(matrix.shapes):
                ax.plot(time, np.clip(clear[:, b], -3, 3), lw=0.7, label=shape)
            ax.axhline(0.0, color="k", lw=0.5, alpha=0.5)
            ax.set_ylim(-2.6, 2.0)
            if i == 0:
                ax.set_title(f"{fps} fps", fontsize=9)
            if j == 0:
                ax.set_ylabel(treatment, fontsize=8)
            ax.tick_params(labelsize=7)
    axes[0, -1].legend(fontsize=6, loc="upper right")
    fig.suptitle(f"lowest point above water (m) vs time (s), forces {forces}", fontsize=9)
    fig.tight_layout()
    _save(fig, path)


def _save(fig, path) -> None:
    plt = _pyplot()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
