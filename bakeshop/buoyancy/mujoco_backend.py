"""MuJoCo as the rigid-body engine: floating bodies that collide with each other and the shore.

The fleet becomes a generated MJCF model: one free-jointed body per floating body, with the
body's exact mass and full inertia tensor (centre of mass at the body origin) and its convex
hull as a mesh geom for contacts (MuJoCo collides meshes through their convex hulls), a floor
plane and optionally a sloping shore. The world is bakeshop's (+Y up), so gravity is (0, -g, 0).

Buoyancy enters through ``xfrc_applied`` (world-frame force and torque at the centre of mass)
before every solver step, computed from the state that step integrates. ``mj_step`` would be
wrong for this: after it, ``xpos``/``xquat`` still describe the state before the step (its
position stage ran first), so forces read from them lag one step and pump energy. The backend
therefore reads the state from ``qpos``/``qvel`` and steps with ``mj_step1`` (positions and
velocities), sets the forces, then ``mj_step2`` (accelerations and the Euler update). MuJoCo's
Euler integrator is semi-implicit, like the built-in one; with RK4 (not used) applied forces
would have to come from ``mjcb_passive`` instead, which is called at each stage.

MuJoCo's warnings (an unstable simulation ...) become Python ``RuntimeWarning`` s: its own
handler prints them on stdout, mixed into a command's output, and appends them to a
``MUJOCO_LOG.TXT`` in the working directory. The handler is MuJoCo's, process-wide: it is set
when a backend is made. A model MuJoCo refuses (a body too small or too light for its inertia)
is an :class:`~bakeshop.errors.ArgumentError` carrying MuJoCo's reason.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import mujoco
import numpy as np
from numpy.typing import ArrayLike

from bakeshop.buoyancy.state import State
from bakeshop.buoyancy.state import quaternion_to_matrix as _rotations
from bakeshop.errors import ArgumentError, BakeshopWarning

if TYPE_CHECKING:
    from bakeshop.buoyancy.mass import Fleet


def _warn(message: str) -> None:
    warnings.warn(BakeshopWarning(f"MuJoCo: {message}"), stacklevel=2)


class MujocoBackend:
    """Integrates a :class:`~bakeshop.buoyancy.mass.Fleet` with MuJoCo.

    Parameters
    ----------
    fleet : Fleet
    state : State
        Initial state.
    timestep : float
        Solver step, seconds.
    gravity : float
        m/s^2.
    floor : float
        Height (m) of the floor plane.
    shore : float or None
        X coordinate (m) where a beach rising at ``shore_slope`` towards +X leaves the floor.
    shore_slope : float
        Slope of the beach, degrees.
    friction : float
        Sliding friction coefficient of all contacts.
    """

    name = "mujoco"

    def __init__(
        self,
        fleet: Fleet,
        state: State,
        *,
        timestep: float,
        gravity: float,
        floor: float = -10.0,
        shore: float | None = None,
        shore_slope: float = 15.0,
        friction: float = 0.6,
    ) -> None:
        self.fleet = fleet
        self.xml = model_xml(
            fleet,
            timestep=timestep,
            gravity=gravity,
            floor=floor,
            shore=shore,
            shore_slope=shore_slope,
            friction=friction,
        )
        mujoco.set_mju_user_warning(_warn)
        try:
            self.model = mujoco.MjModel.from_xml_string(self.xml)
        except ValueError as e:
            lines = [line.strip() for line in str(e).splitlines() if line.strip()]
            reason = "; ".join(lines).removeprefix("Error: ")
            raise ArgumentError(f"MuJoCo cannot simulate the body: {reason}") from None
        self.data = mujoco.MjData(self.model)
        self._bodies = np.array(
            [
                mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, f"b{i}")
                for i in range(len(fleet))
            ]
        )
        q = self.data.qpos.reshape(-1, 7)
        q[:, :3] = state.position
        q[:, 3:] = state.quaternion
        self.set_velocities(state.velocity, state.angular_velocity)
        mujoco.mj_forward(self.model, self.data)

    def state(self) -> State:
        """The current state, from ``qpos``/``qvel`` (never the stale ``xpos``)."""
        q = self.data.qpos.reshape(-1, 7)
        v = self.data.qvel.reshape(-1, 6)
        quat = q[:, 3:] / np.linalg.norm(q[:, 3:], axis=1, keepdims=True)
        rot = _rotations(quat)
        return State(
            q[:, :3].copy(),
            quat,
            v[:, :3].copy(),
            np.einsum("bij,bj->bi", rot, v[:, 3:]),  # free-joint angular velocity is local
        )

    def set_velocities(self, velocity: np.ndarray, angular_velocity: np.ndarray) -> None:
        """Overwrite linear (B, 3) and angular (B, 3) world velocities."""
        q = self.data.qpos.reshape(-1, 7)
        v = self.data.qvel.reshape(-1, 6)
        v[:, :3] = velocity
        v[:, 3:] = np.einsum("bji,bj->bi", _rotations(q[:, 3:]), angular_velocity)

    def step(self, force: np.ndarray, torque: np.ndarray) -> None:
        """One solver step with ``force`` and ``torque`` (B, 3, world frame, at the centre of
        mass) applied on top of gravity and contacts."""
        mujoco.mj_step1(self.model, self.data)
        self.data.xfrc_applied[self._bodies, :3] = force
        self.data.xfrc_applied[self._bodies, 3:] = torque
        mujoco.mj_step2(self.model, self.data)


def model_xml(
    fleet: Fleet,
    *,
    timestep: float,
    gravity: float,
    floor: float,
    shore: float | None,
    shore_slope: float,
    friction: float,
) -> str:
    """The MJCF text of the fleet's scene (see :class:`MujocoBackend`)."""
    assets: list[str] = []
    bodies: list[str] = []
    mesh_names: dict[int, str] = {}
    for i, body in enumerate(fleet.bodies):
        key = id(body)
        if key not in mesh_names:
            name = mesh_names[key] = f"m{len(mesh_names)}"
            hull = body.mesh.convex_hull
            assets.append(
                f'<mesh name="{name}" vertex="{_numbers(hull.vertices)}" '
                f'face="{_numbers(hull.faces)}"/>'
            )
        t = body.inertia
        full = _numbers([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])
        bodies.append(
            f'<body name="b{i}"><freejoint/>'
            f'<inertial pos="0 0 0" mass="{float(body.mass)!r}" fullinertia="{full}"/>'
            f'<geom type="mesh" mesh="{mesh_names[key]}" friction="{friction} 0.005 0.0001"/>'
            "</body>"
        )
    ground = [
        f'<geom name="floor" type="plane" size="0 0 1" pos="0 {float(floor)!r} 0" zaxis="0 1 0" '
        f'friction="{friction} 0.005 0.0001"/>'
    ]
    if shore is not None:
        a = np.radians(shore_slope)
        ground.append(
            f'<geom name="shore" type="plane" size="0 0 1" pos="{_numbers([shore, floor, 0])}" '
            f'zaxis="{_numbers([-np.sin(a), np.cos(a), 0])}" friction="{friction} 0.005 0.0001"/>'
        )
    return (
        '<mujoco model="bakeshop-float">'
        '<compiler inertiafromgeom="false"/>'
        f'<option timestep="{float(timestep)!r}" gravity="0 {-float(gravity)!r} 0" '
        'integrator="Euler"/>'
        f"<asset>{''.join(assets)}</asset>"
        f"<worldbody>{''.join(ground)}{''.join(bodies)}</worldbody>"
        "</mujoco>"
    )


def _numbers(a: ArrayLike) -> str:
    return " ".join(map(repr, np.asarray(a).ravel().tolist()))
