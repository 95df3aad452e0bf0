"""The test bench: float one body and measure it (what ``bakeshop float`` runs)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from bakeshop import progress
from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.hydrostatics import waterplane_area
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import clearance, summarize
from bakeshop.buoyancy.shapes import FACE_BYTES, FACE_SECONDS, closed_mesh, make_shape, resize
from bakeshop.buoyancy.state import axis_angle_quaternion, quaternion_to_matrix
from bakeshop.buoyancy.stepping import release, simulate
from bakeshop.buoyancy.water import Water
from bakeshop.errors import ArgumentError
from bakeshop.resources import Cost, require

if TYPE_CHECKING:
    import os

    import trimesh

    from bakeshop.buoyancy.mass import Fleet
    from bakeshop.buoyancy.stepping import Trace
    from bakeshop.io.mesh import Mesh


#: Bytes per cell of the voxel grid (volume, moment, area; the rays' crossings).
CELL_BYTES = 64


def float_mesh_cost(faces: int, resolution: int) -> Cost:
    """What closing and sampling a mesh of ``faces`` triangles with ``resolution`` cells along
    its longest side (at most ``resolution**3`` cells) hold at their peak; ``work`` is the
    estimated time in seconds."""
    memory = FACE_BYTES * faces + CELL_BYTES * resolution**3
    what = (
        f"floating a mesh of {faces:,} triangles at {resolution} cells along its longest side "
        "(--resolution lowers the cells; a mesh of fewer triangles the rest)"
    )
    return Cost(memory, int(FACE_SECONDS * faces + 0.5), what)


@dataclass
class BenchResult:
    """``summary`` (the numbers, see :func:`bakeshop.buoyancy.metrics.summarize`, plus
    ``heave_omega_rad_s`` and ``omega_dt``), the :class:`~bakeshop.buoyancy.stepping.Trace`,
    the ``clearance`` (S,) of the body over it, and the fleet."""

    summary: dict
    trace: Trace
    clearance: np.ndarray
    fleet: Fleet


def float_body(
    mesh: Mesh | trimesh.Trimesh | None = None,
    *,
    shape: str | None = None,
    size: float | tuple[float, float, float] | None = None,
    density: float,
    resolution: int = 10,
    model: ForceModel | None = None,
    water: Water | None = None,
    fps: float = 60.0,
    solver_hz: float = 60.0,
    forces: str = "per-substep",
    seconds: float = 10.0,
    release_height: float = 0.0,
    tilt: float = 0.0,
    backend: str = "builtin",
    repair: bool = False,
    path: str | os.PathLike | None = None,
    **backend_options: Any,
) -> BenchResult:
    """Float a mesh or built-in shape once and measure it.

    ``mesh`` is what :func:`bakeshop.io.load_mesh` reads, in metres, closed here by
    :func:`~bakeshop.buoyancy.shapes.closed_mesh` (with ``repair``; errors name ``path``);
    ``size`` rescales it (see :func:`~bakeshop.buoyancy.shapes.resize`).

    ``tilt`` (degrees) turns the body about the X axis before release; ``release_height`` is
    the height (m) of its lowest point above the water then. ``omega_dt`` in the summary is the
    small-oscillation heave frequency ``sqrt(rho g A_wp / m)`` times the time a force is held
    (the solver step, or the frame in per-frame mode): semi-implicit Euler diverges above 2.
    """
    if shape is not None and mesh is None:
        mesh = make_shape(shape, size=size)
    elif mesh is not None and shape is None:
        require(float_mesh_cost(len(mesh.faces), resolution), path)
        mesh = resize(closed_mesh(mesh, repair=repair, path=path), size)
    else:
        raise ArgumentError("give either a mesh or a built-in shape, not both or neither")
    if not np.isfinite(tilt):
        raise ArgumentError(f"tilt must be a finite number of degrees, got {tilt}")
    model = ForceModel() if model is None else model
    water = Water() if water is None else water
    with progress.step(f"mass and sample points ({resolution} cells along the longest side)"):
        body = make_body(mesh, density, resolution=resolution)
    fleet = pack([body])
    start = release(
        fleet, water, height=release_height, quaternions=[axis_angle_quaternion((1, 0, 0), tilt)]
    )
    trace = simulate(
        fleet, start, water, model, seconds=seconds, fps=fps, solver_hz=solver_hz,
        forces=forces, backend=backend, **backend_options,
    )  # fmt: skip
    summary = summarize(fleet, trace, water, model)[0]
    omega = None
    if summary["archimedes_draft_m"] is not None:
        tri = body.mesh.triangles @ quaternion_to_matrix(trace.quaternion[-1, 0]).T
        level = tri[:, :, 1].min() + summary["archimedes_draft_m"]
        omega = float(
            np.sqrt(model.rho_water * model.gravity * waterplane_area(tri, level) / body.mass)
        )
    hold = 1.0 / (fps if forces == "per-frame" else solver_hz)
    summary["heave_omega_rad_s"] = omega
    summary["omega_dt"] = None if omega is None else omega * max(hold, 1.0 / solver_hz)
    return BenchResult(summary, trace, clearance(fleet, trace, water)[:, 0], fleet)
