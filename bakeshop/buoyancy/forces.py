"""Buoyancy, fluid friction and the predictive stabiliser, evaluated per sample point.

Every sample point i of a body carries a volume V_i and stands for a vertical column of height
h_i (its cell's side, or less where the solid ends inside the cell). With the water surface eta
at the point, the submerged fraction of the column is

    f_i = clamp((eta - y_i) / h_i + 1/2, 0, 1)

(linear in depth, so the force changes continuously and exactly as the surface crosses the cell),
and the point receives Archimedes' force ``rho_water * g * V_i * f_i`` upwards at its own
position; the torque about the centre of mass follows from where the points are.

Fluid friction comes in two kinds:

``team``
    The game team's damping: a force ``-c_lin * s * m * v`` and a torque ``-c_ang * s * I w``,
    scaled by ``s = log(1 + n) / log(1 + N)`` for n of the body's N points submerged, so that a few
    wet points already damp strongly and a fully submerged body gets the whole of it.
``drag``
    Quadratic drag of the submerged part: each point gets ``-1/2 rho C_d A_i |u| u`` with u its
    velocity relative to the water and a frontal area ``A_i = f_i V_i / L`` shared out by volume
    (L = V^(1/3), the body's size), so that a submerged body of volume V sees about
    ``1/2 rho C_d V^(2/3) |u| u``; rotation is resisted by the points' own velocities. Held for
    a time T (the horizon), explicit drag overshoots (reverses the velocity) once
    ``k |u| T > m``; each point's drag is therefore capped at what stops its share of the mass,
    ``rho_body V_i |u| / T``, the limit an implicit step would reach.

The predictive stabiliser (the team's hack) scales a point's buoyancy by M when the point,
moved on by its velocity for C times the time the force will be held, would be above the water:
here, when its whole column would be out. (Testing the point's centre instead would also scale
resting points whose centre is just above the surface, and sink every body deeper than
Archimedes says: 1 to 4 % for the test shapes.)
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from bakeshop import threads
from bakeshop.buoyancy import _native
from bakeshop.buoyancy.hydrostatics import GRAVITY, RHO_WATER
from bakeshop.errors import ArgumentError, validate_choice

if TYPE_CHECKING:
    from bakeshop.buoyancy.mass import Fleet
    from bakeshop.buoyancy.state import State
    from bakeshop.buoyancy.water import Water

DAMPINGS = ("team", "drag", "none")
#: Below this many points a force evaluation runs on one thread: waking a thread pool costs
#: more than the work (milliseconds on a loaded machine).
PARALLEL_MIN_POINTS = 100_000
STABILIZERS = ("none", "predict", "clamp", "predict+clamp")


@dataclass(frozen=True)
class ForceModel:
    """Choices and constants of the force model.

    Attributes
    ----------
    damping : {"team", "drag", "none"}
    linear_damping, angular_damping : float
        ``c_lin`` and ``c_ang`` of the team damping, 1/s.
    drag_coefficient : float
        ``C_d`` of the drag model.
    stabilize : {"none", "predict", "clamp", "predict+clamp"}
    predict_c, predict_m : float
        C > 1 and 0 < M < 1 of the predictive stabiliser.
    clamp_speed : float
        Speed limit (m/s) of velocity clamping while a body is partly submerged.
    rho_water : float
        kg/m^3.
    gravity : float
        m/s^2.
    """

    damping: str = "team"
    linear_damping: float = 5.0
    angular_damping: float = 5.0
    drag_coefficient: float = 1.0
    stabilize: str = "predict"
    predict_c: float = 2.5
    predict_m: float = 0.1
    clamp_speed: float = 1.0
    rho_water: float = RHO_WATER
    gravity: float = GRAVITY

    def __post_init__(self) -> None:
        validate_choice(self.damping, DAMPINGS, "damping")
        validate_choice(self.stabilize, STABILIZERS, "stabiliser")
        if not self.predict_c > 1 or not 0 < self.predict_m < 1:
            raise ArgumentError("the predictive stabiliser needs C > 1 and 0 < M < 1")
        for name in ("linear_damping", "angular_damping", "drag_coefficient", "clamp_speed"):
            if not getattr(self, name) >= 0:
                raise ArgumentError(f"{name} must be >= 0")

    @property
    def predicts(self) -> bool:
        """True when the predictive stabiliser is on."""
        return self.stabilize in ("predict", "predict+clamp")

    @property
    def clamps(self) -> bool:
        """True when the speed clamp is on."""
        return self.stabilize in ("clamp", "predict+clamp")


@dataclass
class Forces:
    """Result of one evaluation for B bodies: ``force`` (B, 3) N and ``torque`` (B, 3) N m about
    the centre of mass (world frame, gravity excluded), ``submerged_points`` (B,) int64 and
    ``submerged_volume`` (B,) m^3."""

    force: np.ndarray
    torque: np.ndarray
    submerged_points: np.ndarray
    submerged_volume: np.ndarray


def evaluate(
    fleet: Fleet, state: State, water: Water, model: ForceModel, time: float, horizon: float
) -> Forces:
    """Buoyancy and friction on every body of ``fleet`` in ``state`` at ``time`` (s).

    ``horizon`` (s) is how long the forces will be held (the frame time in per-frame mode, the
    solver step in per-substep mode): the predictive stabiliser looks ``C * horizon`` ahead.
    """
    n = len(fleet)
    out = Forces(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n, np.int64), np.zeros(n))
    small = len(fleet.points) < PARALLEL_MIN_POINTS
    with threads.limited(1) if small else contextlib.nullcontext():
        _native.point_forces(
            fleet.offsets, fleet.points, fleet.volumes, fleet.heights, fleet.volume,
            fleet.mass, fleet.inertia,
            state.position, state.quaternion, state.velocity, state.angular_velocity,
            water.table, water.level, float(time), model.rho_water, model.gravity,
            DAMPINGS.index(model.damping), model.linear_damping, model.angular_damping,
            model.drag_coefficient, model.predicts, model.predict_c, model.predict_m,
            float(horizon), out.force, out.torque, out.submerged_points, out.submerged_volume,
        )  # fmt: skip
    return out
