"""``bakeshop float``: the buoyancy test bench."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click

from bakeshop import progress
from bakeshop.cli._numbers import Fields, Integer, Number, Numbers
from bakeshop.cli._paths import INPUT, OUTPUT
from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    from bakeshop.buoyancy.water import Water

#: What each number of the summary means, and what its "-" (JSON null) means.
SUMMARY = {
    "volume_m3": ("volume of the body", ""),
    "mass_kg": ("its mass (volume x --density)", ""),
    "points": ("sample points that carry its buoyancy", ""),
    "archimedes_draft_m": (
        "depth of its lowest point at rest in calm water, exact",
        "none: it sinks (denser than water)",
    ),
    "draft_m": ("measured depth of its lowest point, last quarter of the run", ""),
    "times_left_water": ("times it came fully out of the water after first entering it", ""),
    "max_jump_m": ("highest its lowest point rose above the water after that", ""),
    "settle_time_s": (
        "when it last strayed over 1 % of its size from where it ended",
        "never: it still strays over 1 % of its size in the last quarter",
    ),
    "heave_omega_rad_s": (
        "angular frequency of small bobbing, sqrt(rho g A_waterplane / m)",
        "none: it sinks",
    ),
    "omega_dt": (
        "frequency x time a force is held; the integrator diverges above 2",
        "none: it sinks",
    ),
}


#: --waves: one wave train.
WAVE = Fields(
    {
        "amplitude": Number(0, 100),
        "wavelength": Number(0, 1e4, low_open=True),
        "direction": Number(-360, 360),
        "speed": Number(0, 1000),
    },
    required=2,
)


@click.command("float", context_settings={"max_content_width": 100})
@click.argument("mesh", required=False, type=INPUT)
@click.option("--shape", help="Built-in shape: box, sphere, capsule, cylinder, torus, peep, hull.")
@click.option(
    "--size",
    type=Numbers(1e-3, 1e3, count=(1, 3), sep="x"),
    metavar="S|XxYxZ",
    help="Longest side S, or extents XxYxZ, in metres (default: about 1 m).",
)
@click.option(
    "--density",
    type=Number(1, 1e5),
    default=500.0,
    show_default=True,
    help="Density of the body, kg/m^3 (water: 1000).",
)
@click.option(
    "--resolution",
    type=Integer(2, 256),
    default=None,
    help="Voxel cells along the longest side (default 10; 8 with --matrix).",
)
@click.option("--repair", is_flag=True, help="Try to close a mesh that is not watertight.")
@click.option(
    "--fps", type=Number(1, 1000), default=60.0, show_default=True, help="Frame rate, 1/s."
)
@click.option(
    "--solver-hz",
    type=Number(1, 10000),
    default=60.0,
    show_default=True,
    help="Solver rate, steps per second.",
)
@click.option(
    "--forces",
    type=click.Choice(["per-substep", "per-frame"]),
    default="per-substep",
    show_default=True,
    help="Recompute forces every solver step, or once per frame.",
)
@click.option(
    "--stabilize",
    type=click.Choice(["none", "predict", "clamp", "predict+clamp"]),
    default="predict",
    show_default=True,
    help="What stops the trampolining: 'predict' scales the buoyancy of a sample point by "
    "--predict-m when the point, moved on by its velocity for --predict-c times the time a force "
    "is held, would be out of the water; 'clamp' limits the speed to --clamp-speed while the body "
    "is partly in the water.",
)
@click.option(
    "--damping",
    type=click.Choice(["team", "drag", "none"]),
    default="team",
    show_default=True,
    help="Fluid friction: 'team' damps velocity and spin by --linear-damping and "
    "--angular-damping, scaled by how much of the body is wet; 'drag' is quadratic drag of the "
    "wet part (--drag-coefficient).",
)
@click.option(
    "--linear-damping",
    type=Number(0, 1000),
    default=5.0,
    show_default=True,
    help="Team damping of velocity, 1/s.",
)
@click.option(
    "--angular-damping",
    type=Number(0, 1000),
    default=5.0,
    show_default=True,
    help="Team damping of spin, 1/s.",
)
@click.option(
    "--drag-coefficient",
    type=Number(0, 100),
    default=1.0,
    show_default=True,
    help="C_d of --damping drag (about 1 for a blunt body).",
)
@click.option(
    "--predict-c",
    type=Number(1, 100, low_open=True),
    default=2.5,
    show_default=True,
    help="How far --stabilize predict looks ahead, in times a force is held.",
)
@click.option(
    "--predict-m",
    type=Number(0, 1, low_open=True, high_open=True),
    default=0.1,
    show_default=True,
    help="The factor --stabilize predict puts on the buoyancy of a point about to leave the water.",
)
@click.option(
    "--clamp-speed",
    type=Number(0, 1000),
    default=1.0,
    show_default=True,
    help="Speed limit of --stabilize clamp: largest speed of a partly submerged body, m/s.",
)
@click.option(
    "--waves",
    "waves",
    multiple=True,
    type=WAVE,
    metavar="A:L[:DIR[:SPEED]]",
    help="A wave train: amplitude m, wavelength m, direction degrees, speed m/s "
    f"(default deep water). Repeat for more. [{WAVE.describe_range()}]",
)
@click.option(
    "--seconds",
    type=Number(0, 3600, low_open=True),
    default=None,
    help="Simulated time (default 10 s; 8 s with --matrix).",
)
@click.option(
    "--release-height",
    type=Number(-1000, 1000),
    default=None,
    help="Lowest point above the water at release, m (default 0; -2 with --matrix).",
)
@click.option(
    "--tilt",
    type=Number(-360, 360),
    default=0.0,
    show_default=True,
    help="Release tilt about X, degrees.",
)
@click.option(
    "--backend",
    type=click.Choice(["builtin", "mujoco"]),
    default="builtin",
    show_default=True,
    help="Rigid-body integrator: bakeshop's own (no collisions), or MuJoCo, which collides the "
    "body's convex hull with a floor and a shore (pip install 'bakeshop[buoyancy]').",
)
@click.option(
    "--floor",
    type=Number(-1e4, 1e4),
    default=-10.0,
    show_default=True,
    help="MuJoCo floor height, m.",
)
@click.option(
    "--shore",
    type=Number(-1e4, 1e4),
    default=None,
    help="MuJoCo: X (m) where a 15 degree beach rises.",
)
@click.option("--plot", type=OUTPUT, help="Write the trace (lowest point vs time) as PNG.")
@click.option("--json", "as_json", is_flag=True, help="Print the numbers as one JSON object.")
@click.option(
    "--matrix",
    is_flag=True,
    help="Run every shape x 10/20/30/60 fps x treatment x force mode instead.",
)
@click.option(
    "--out",
    type=OUTPUT,
    default="float-matrix",
    show_default=True,
    help="With --matrix: writes OUT.md, OUT.csv and OUT.png.",
)
def float_command(
    mesh: Path | None,
    shape: str | None,
    size: tuple[float, ...] | None,
    density: float,
    resolution: int | None,
    repair: bool,
    fps: float,
    solver_hz: float,
    forces: str,
    stabilize: str,
    damping: str,
    linear_damping: float,
    angular_damping: float,
    drag_coefficient: float,
    predict_c: float,
    predict_m: float,
    clamp_speed: float,
    waves: tuple[tuple[float, ...], ...],
    seconds: float | None,
    release_height: float | None,
    tilt: float,
    backend: str,
    floor: float,
    shore: float | None,
    plot: Path | None,
    as_json: bool,
    matrix: bool,
    out: Path,
) -> int:
    """Float a mesh or a built-in shape in water and measure it: volume, mass, sample points,
    the exact Archimedes draft, the measured draft, how often it left the water after entering
    it, its highest jump and when it settled.

    \b
    Example:
      bakeshop float --shape peep --density 300 --fps 10 --forces per-frame \\
          --stabilize none --damping none --release-height -2 --plot peep.png
      bakeshop float spot.obj --density 600 --waves 0.2:8:30 --backend mujoco --json
      bakeshop float --matrix --out docs/buoyancy_matrix
    """
    from bakeshop.buoyancy.forces import ForceModel
    from bakeshop.buoyancy.water import Water, Wave

    water = Water(waves=tuple(Wave(*w) for w in waves))
    if matrix:
        if mesh is not None or shape is not None:
            raise ArgumentError("--matrix runs the built-in shapes; give no MESH or --shape")
        return _matrix(
            out,
            density,
            8.0 if seconds is None else seconds,
            8 if resolution is None else resolution,
            solver_hz,
            water,
            -2.0 if release_height is None else release_height,
        )
    from bakeshop.buoyancy.bench import float_body
    from bakeshop.buoyancy.plots import plot_trace
    from bakeshop.io import load_mesh, write_image

    model = ForceModel(
        damping=damping,
        linear_damping=linear_damping,
        angular_damping=angular_damping,
        drag_coefficient=drag_coefficient,
        stabilize=stabilize,
        predict_c=predict_c,
        predict_m=predict_m,
        clamp_speed=clamp_speed,
    )
    options = {"floor": floor, "shore": shore} if backend == "mujoco" else {}
    seconds = 10.0 if seconds is None else seconds
    if (mesh is None) == (shape is None):
        raise ArgumentError("give either a mesh file or a built-in shape, not both or neither")
    body = None
    if mesh is not None:
        with progress.step(f"reading {mesh}"):
            body = load_mesh(mesh)
    result = float_body(
        body,
        shape=shape,
        size=None if size is None else size[0] if len(size) == 1 else (size[0], size[1], size[2]),
        density=density,
        resolution=10 if resolution is None else resolution,
        model=model,
        water=water,
        fps=fps,
        solver_hz=solver_hz,
        forces=forces,
        seconds=seconds,
        release_height=0.0 if release_height is None else release_height,
        tilt=tilt,
        backend=backend,
        repair=repair,
        path=mesh,
        **options,
    )
    summary = result.summary
    if plot is not None:
        label = mesh.name if mesh is not None else str(shape)  # exactly one is given (checked)
        picture = plot_trace(
            result.trace.time,
            result.clearance[:, None],
            labels=[label],
            draft=[summary["archimedes_draft_m"]],
            title=f"{label}, {density:g} kg/m3, {fps:g} fps, forces {forces}, "
            f"damping {damping}, stabilise {stabilize}",
        )
        write_image(plot, picture)
    if as_json:
        click.echo(json.dumps(summary))
        return 0
    for key, value in summary.items():
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        meaning = SUMMARY.get(key, ("", ""))[0 if value is not None else 1]
        click.echo(f"{key:20s} {text if value is not None else '-':12s} {meaning}".rstrip())
    return 0


def _matrix(
    out: Path,
    density: float,
    seconds: float,
    resolution: int,
    solver_hz: float,
    water: Water,
    release_height: float,
) -> int:
    from bakeshop.buoyancy.matrix import run_matrix, to_csv, to_markdown
    from bakeshop.buoyancy.plots import plot_grid
    from bakeshop.io import write_image, write_text

    result = run_matrix(
        density=density,
        seconds=seconds,
        resolution=resolution,
        solver_hz=solver_hz,
        water=water,
        release_height=release_height,
    )
    write_text(f"{out}.md", to_markdown(result))
    write_text(f"{out}.csv", to_csv(result))
    write_image(f"{out}.png", plot_grid(result))
    click.echo(to_markdown(result), nl=False)
    click.echo(f"wrote {out}.md, {out}.csv, {out}.png")
    return 0


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(float_command)
