"""Fixed-rate stepping: frames of length dT, a solver at a fixed rate, and the force modes.

Each frame adds dT to an accumulator; the solver takes steps of ``h = 1 / solver_hz`` while the
accumulator holds a whole step (the classic fixed-timestep loop, so the physics does not depend
on the frame rate). Forces are

``per-substep``
    recomputed from the state being integrated before every solver step;
``per-frame``
    computed once per frame, from the state at the frame's start, and held for all of that
    frame's solver steps (the constraint the game team's engine imposed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.buoyancy.forces import ForceModel, evaluate
from bakeshop.buoyancy.state import State, quaternion_to_matrix
from bakeshop.errors import (
    ArgumentError,
    BakeshopError,
    UnsupportedError,
    validate_choice,
    with_article,
)
from bakeshop.resources import Cost, require

if TYPE_CHECKING:
    from bakeshop.buoyancy.builtin import BuiltinBackend
    from bakeshop.buoyancy.mass import Fleet
    from bakeshop.buoyancy.mujoco_backend import MujocoBackend
    from bakeshop.buoyancy.water import Water

FORCE_MODES = ("per-substep", "per-frame")
BACKENDS = ("builtin", "mujoco")
#: Longest simulation accepted, in solver steps and in frames (a typo should not run for a day).
MAX_STEPS = 5_000_000
#: Bytes of the trace per solver step and body (time, position, quaternion, velocity, angular
#: velocity, submerged points).
TRACE_BYTES = 8 * (1 + 3 + 4 + 3 + 3 + 1)
#: Bytes per sample point of one force evaluation's work arrays.
POINT_BYTES = 256


@dataclass
class Trace:
    """What a simulation recorded after every solver step (S steps, B bodies).

    Attributes
    ----------
    time : (S,) float64
        Seconds since release (the initial state is row 0, at t = 0).
    position, velocity, angular_velocity : (S, B, 3) float64
    quaternion : (S, B, 4) float64
    submerged_points : (S, B) int64
        Submerged points in the force evaluation that drove the step (held in per-frame mode).
    """

    time: np.ndarray
    position: np.ndarray
    quaternion: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    submerged_points: np.ndarray

    def state(self, step: int) -> State:
        """The recorded :class:`State` after ``step`` solver steps."""
        return State(
            self.position[step].copy(),
            self.quaternion[step].copy(),
            self.velocity[step].copy(),
            self.angular_velocity[step].copy(),
        )


def release(
    fleet: Fleet,
    water: Water,
    *,
    height: float = 0.0,
    quaternions: ArrayLike | None = None,
    spacing: float = 3.0,
) -> State:
    """Initial :class:`State`: bodies at rest in a row along X, ``spacing`` metres apart.

    Parameters
    ----------
    height : float
        Height (m) of each body's lowest point above the still water level at release
        (negative: released under water).
    quaternions : (B, 4) float64, optional
        Orientations at release; identity by default.
    """
    n = len(fleet)
    if not (np.isfinite(height) and np.isfinite(spacing)):
        raise ArgumentError(f"release height and spacing must be finite, got {height}, {spacing}")
    q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)) if quaternions is None else np.array(quaternions)
    if q.shape != (n, 4) or not np.all(np.isfinite(q)) or np.any(np.linalg.norm(q, axis=1) == 0):
        raise ArgumentError(f"quaternions must be {n} finite, non-zero (w, x, y, z) rows")
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    position = np.zeros((n, 3))
    position[:, 0] = (np.arange(n) - (n - 1) / 2) * spacing
    rot = quaternion_to_matrix(q)
    for b, body in enumerate(fleet.bodies):
        lowest = (body.hull_vertices @ rot[b].T)[:, 1].min()
        position[b, 1] = water.level + height - lowest
    return State(position, q, np.zeros((n, 3)), np.zeros((n, 3)))


def make_backend(
    name: str,
    fleet: Fleet,
    state: State,
    *,
    timestep: float,
    gravity: float,
    **options: Any,
) -> BuiltinBackend | MujocoBackend:
    """Create the rigid-body backend ``builtin`` or ``mujoco`` (options go to the latter)."""
    validate_choice(name, BACKENDS, "backend")
    if name == "builtin":
        from bakeshop.buoyancy.builtin import BuiltinBackend

        return BuiltinBackend(fleet, state, timestep=timestep, gravity=gravity)
    try:
        from bakeshop.buoyancy.mujoco_backend import MujocoBackend
    except ModuleNotFoundError as e:
        if e.name != "mujoco":
            raise
        raise UnsupportedError(
            "the MuJoCo backend needs mujoco: pip install 'bakeshop[buoyancy]'"
        ) from None
    return MujocoBackend(fleet, state, timestep=timestep, gravity=gravity, **options)


def simulate(
    fleet: Fleet,
    state: State,
    water: Water,
    model: ForceModel | None = None,
    *,
    seconds: float = 10.0,
    fps: float = 60.0,
    solver_hz: float = 60.0,
    forces: str = "per-substep",
    backend: str = "builtin",
    **backend_options: Any,
) -> Trace:
    """Run the fixed-timestep loop and record every solver step.

    Parameters
    ----------
    fleet : Fleet
    state : State
        Initial state (see :func:`release`).
    water : Water
    model : ForceModel, optional
        Default: team damping and the predictive stabiliser.
    seconds : float
        Simulated time; the number of frames is ``round(seconds * fps)``.
    fps : float
        Frame rate: the frame time is ``dT = 1 / fps``.
    solver_hz : float
        Solver rate: the step is ``h = 1 / solver_hz``.
    forces : {"per-substep", "per-frame"}
    backend : {"builtin", "mujoco"}
    **backend_options
        Passed to the MuJoCo backend (e.g. ``floor``).

    Returns
    -------
    Trace
    """
    validate_choice(forces, FORCE_MODES, "force mode")
    model = ForceModel() if model is None else model
    for name, value in (("fps", fps), ("solver_hz", solver_hz), ("seconds", seconds)):
        if not (np.isfinite(value) and value > 0):
            raise ArgumentError(f"{name} must be a positive number, got {value!r}")
    frame, h = 1.0 / fps, 1.0 / solver_hz
    cost = require(simulate_cost(fleet, seconds=seconds, fps=fps, solver_hz=solver_hz))
    n_frames = max(int(round(seconds * fps)), 1)
    n_steps = cost.work
    engine = make_backend(
        backend, fleet, state, timestep=h, gravity=model.gravity, **backend_options
    )
    n = len(fleet)
    rows = n_steps + 1
    trace = Trace(
        time=np.arange(rows) * h,
        position=np.empty((rows, n, 3)),
        quaternion=np.empty((rows, n, 4)),
        velocity=np.empty((rows, n, 3)),
        angular_velocity=np.empty((rows, n, 3)),
        submerged_points=np.zeros((rows, n), np.int64),
    )
    _record(trace, 0, engine.state())
    points_per_body = np.diff(fleet.offsets)
    accumulator, step, held = 0.0, 0, None
    for _ in progress.track(range(n_frames), f"simulating {seconds:g} s ({n_steps:,} steps)"):
        accumulator += frame
        if forces == "per-frame":
            held = evaluate(fleet, engine.state(), water, model, step * h, frame)
        while accumulator >= h * (1 - 1e-9) and step < n_steps:
            f = (
                held
                if held is not None
                else evaluate(fleet, engine.state(), water, model, step * h, h)
            )
            engine.step(f.force, f.torque)
            step += 1
            accumulator -= h
            after = engine.state()
            if model.clamps:
                partly = (f.submerged_points > 0) & (f.submerged_points < points_per_body)
                after.velocity[partly] = _clamp(after.velocity[partly], model.clamp_speed)
                engine.set_velocities(after.velocity, after.angular_velocity)
            _record(trace, step, after)
            trace.submerged_points[step] = f.submerged_points
        last = (trace.position[step], trace.velocity[step], trace.angular_velocity[step])
        if not all(np.all(np.isfinite(a)) for a in last):
            raise BakeshopError(
                f"the simulation diverged at t = {step * h:.3g} s: a force held too long for "
                "the body's stiffness (omega * dt > 2); raise the solver rate or the resolution"
            )
    return trace


def simulate_cost(fleet: Fleet, *, seconds: float, fps: float, solver_hz: float) -> Cost:
    """What :func:`simulate` holds (the trace: :data:`TRACE_BYTES` per step and body, and one
    force evaluation's work: :data:`POINT_BYTES` per sample point) and the solver steps it
    takes (``work``).

    Raises
    ------
    ArgumentError
        When the frames or the solver steps exceed :data:`MAX_STEPS`.
    """
    for count, what in ((seconds * fps, "frames"), (seconds * solver_hz, "solver steps")):
        if not count <= MAX_STEPS:  # NaN too
            raise ArgumentError(
                f"{seconds:g} s at {fps:g} fps with {with_article(format(solver_hz, 'g'))} Hz "
                f"solver is {count:.3g} "
                f"{what}: they exceed the limit of {MAX_STEPS:,}"
            )
    frames = max(int(round(seconds * fps)), 1)
    steps = int(np.floor(frames * (1.0 / fps) / (1.0 / solver_hz) + 1e-9))
    points = int(fleet.offsets[-1])
    memory = (steps + 1) * len(fleet) * TRACE_BYTES + POINT_BYTES * points
    bodies = f"{len(fleet)} bod{'y' if len(fleet) == 1 else 'ies'}"
    what = f"simulating {seconds:g} s of {bodies} ({steps:,} steps, {points:,} points)"
    return Cost(memory, steps, what)


def _clamp(velocity: np.ndarray, limit: float) -> np.ndarray:
    speed = np.linalg.norm(velocity, axis=-1, keepdims=True)
    return velocity * np.minimum(1.0, limit / np.maximum(speed, 1e-300))


def _record(trace: Trace, i: int, s: State) -> None:
    trace.position[i] = s.position
    trace.quaternion[i] = s.quaternion
    trace.velocity[i] = s.velocity
    trace.angular_velocity[i] = s.angular_velocity
