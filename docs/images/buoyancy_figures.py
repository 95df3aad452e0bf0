"""Make the pictures and tables of docs/buoyancy.md.

Pictures (docs/images/): buoyancy_shapes.png (the built-in shapes' sample points),
buoyancy_trampoline.png (a peep released 2 m deep: the failure and the fixes),
buoyancy_causes.png (the two causes: omega*dt > 2, and held forces pumping energy),
buoyancy_waves.png (three shapes in two wave trains, MuJoCo), buoyancy_matrix.png (the matrix,
per-frame forces). Tables: docs/buoyancy_matrix.csv (every
run) and the Markdown summary, printed.

Run: ``.venv/bin/python docs/images/buoyancy_figures.py`` (about a minute).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.matrix import run_matrix, to_csv, to_markdown
from bakeshop.buoyancy.metrics import clearance, energy
from bakeshop.buoyancy.plots import plot_grid, plot_trace
from bakeshop.buoyancy.shapes import SHAPES, make_shape
from bakeshop.buoyancy.stepping import release, simulate
from bakeshop.buoyancy.water import Water
from bakeshop.io import write_image

HERE = Path(__file__).resolve().parent
WATER = Water()


def shapes_figure():
    fig = plt.figure(figsize=(14, 2.4), dpi=80)
    for i, name in enumerate(SHAPES):
        body = make_body(make_shape(name), 500, resolution=10)
        p, v = body.points.positions, body.points.volumes
        ax = fig.add_subplot(1, len(SHAPES), i + 1, projection="3d")
        ax.scatter(p[:, 0], -p[:, 2], p[:, 1], c=v / v.max(), s=4, cmap="viridis", vmin=0, vmax=1)
        ax.set_title(f"{name}: {len(p)} points", fontsize=9)
        ax.set_box_aspect((1, 1, 1))
        lim = 0.55
        ax.set(xlim=(-lim, lim), ylim=(-lim, lim), zlim=(-lim, lim))
        ax.set_axis_off()
        ax.view_init(elev=20, azim=-60)
    fig.tight_layout()
    fig.savefig(HERE / "buoyancy_shapes.png")
    plt.close(fig)


def trampoline_figure():
    fleet = pack([make_body(make_shape("peep"), 500, resolution=8)])
    start = release(fleet, WATER, height=-2.0)
    runs = [
        ("per-frame 10 fps, no damping, no stabiliser", 10, "per-frame", "none", "none"),
        ("per-substep 60 Hz, no damping (the physics)", 10, "per-substep", "none", "none"),
        ("per-frame 10 fps, team damping", 10, "per-frame", "team", "none"),
        ("per-frame 10 fps, team damping + predict", 10, "per-frame", "team", "predict"),
    ]
    curves = []
    for _, fps, mode, damping, stabilize in runs:
        model = ForceModel(damping=damping, stabilize=stabilize)
        trace = simulate(fleet, start, WATER, model, seconds=8, fps=fps, forces=mode)
        curves.append(clearance(fleet, trace, WATER)[:, 0])
    write_image(HERE / "buoyancy_trampoline.png", plot_trace(
        trace.time, np.stack(curves, 1),
        labels=[r[0] for r in runs],
        title="peep, 500 kg/m3, released with its lowest point 2 m deep",
    ))  # fmt: skip


def causes_figure():
    undamped = ForceModel(damping="none", stabilize="none")
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.2), dpi=80)
    plank = pack([make_body(make_shape("box", size=(1, 0.02, 1)), 500, resolution=50)])
    start = release(plank, WATER, height=-0.005)
    for hz in (60, 20, 10):
        trace = simulate(plank, start, WATER, undamped, seconds=2, fps=hz, solver_hz=hz)
        omega_h = np.sqrt(9.81 / 0.01) / hz
        a.plot(trace.time, trace.position[:, 0, 1] * 100, label=f"{hz} Hz: omega h = {omega_h:.2f}")
    a.set(xlabel="time (s)", ylabel="centre of mass height (cm)")
    a.set_title("cause 1: 2 cm plank, omega = sqrt(g/draft) = 31 rad/s", fontsize=9)
    a.legend(fontsize=7)
    a.grid(alpha=0.3)
    box = pack([make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=8)])
    start = release(box, WATER, height=-0.2)
    for fps, mode in ((10, "per-frame"), (20, "per-frame"), (10, "per-substep")):
        trace = simulate(box, start, WATER, undamped, seconds=10, fps=fps, forces=mode)
        e = energy(box, trace, WATER, undamped)[:, 0]
        b.plot(trace.time, e - e[0], label=f"{mode}, {fps} fps (60 Hz solver)")
    b.set(xlabel="time (s)", ylabel="energy gained (J)")
    b.set_title("cause 2: forces held over substeps pump energy (box, omega dT = 0.63)", fontsize=9)
    b.legend(fontsize=7)
    b.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(HERE / "buoyancy_causes.png")
    plt.close(fig)


def waves_figure():
    """Hull, peep and torus in two wave trains, MuJoCo backend: heave follows the surface."""
    from bakeshop.buoyancy.water import Wave

    water = Water(waves=(Wave(0.25, 10.0, 0.0), Wave(0.08, 3.5, 60.0)))
    names = ("hull", "peep", "torus")
    fleet = pack([make_body(make_shape(n), 400, resolution=10) for n in names])
    start = release(fleet, water, height=-0.1)
    trace = simulate(fleet, start, water, ForceModel(), seconds=12, fps=30, backend="mujoco")
    fig, axes = plt.subplots(1, 3, figsize=(12, 2.8), dpi=80, sharey=True)
    for b, (ax, name) in enumerate(zip(axes, names, strict=True)):
        x, z = trace.position[:, b, 0], trace.position[:, b, 2]
        ax.plot(trace.time, water.height(x, z, trace.time), color="tab:blue", lw=1, label="water")
        ax.plot(trace.time, trace.position[:, b, 1], color="tab:red", lw=1, label="centre of mass")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("time (s)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("height (m)")
    axes[0].legend(fontsize=7)
    fig.suptitle(
        "two wave trains (0.25 m x 10 m, 0.08 m x 3.5 m at 60 degrees), MuJoCo", fontsize=9
    )
    fig.tight_layout()
    fig.savefig(HERE / "buoyancy_waves.png")
    plt.close(fig)


def matrix_outputs():
    matrix = run_matrix()
    (HERE.parent / "buoyancy_matrix.csv").write_text(to_csv(matrix))
    write_image(HERE / "buoyancy_matrix.png", plot_grid(matrix))
    print(to_markdown(matrix))  # noqa: T201


if __name__ == "__main__":
    shapes_figure()
    trampoline_figure()
    causes_figure()
    waves_figure()
    matrix_outputs()
