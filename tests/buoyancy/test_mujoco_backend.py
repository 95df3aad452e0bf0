"""MuJoCo backend: agrees with the built-in integrator, conserves energy, and collides."""

import numpy as np
import pytest

from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import clearance, summarize
from bakeshop.buoyancy.mujoco_backend import MujocoBackend
from bakeshop.buoyancy.shapes import make_shape
from bakeshop.buoyancy.state import State, axis_angle_quaternion, quaternion_to_matrix
from bakeshop.buoyancy.stepping import release, simulate
from bakeshop.buoyancy.water import Water
from tests.buoyancy.helpers import UNDAMPED, assert_energy_bounded, heave_period
from tests.tolerances import BUOYANCY_BACKEND_RTOL

WATER = Water()


@pytest.fixture(scope="module")
def flat_box():
    return pack([make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=8)])


def test_state_round_trip_with_local_angular_velocity():
    fleet = pack([make_body(make_shape("capsule"), 500, resolution=4)] * 2)
    q = np.array([axis_angle_quaternion((1, 2, 3), 40), axis_angle_quaternion((0, 1, 0), -70)])
    state = State(
        np.array([[0.0, 1.0, 2.0], [3.0, -1.0, 0.5]]),
        q,
        np.array([[0.1, 0.2, 0.3], [-1.0, 0.0, 2.0]]),
        np.array([[0.5, -0.2, 0.9], [0.0, 1.5, 0.2]]),
    )
    backend = MujocoBackend(fleet, state, timestep=1 / 60, gravity=9.81)
    back = backend.state()
    for a, b in zip(
        (state.position, state.quaternion, state.velocity, state.angular_velocity),
        (back.position, back.quaternion, back.velocity, back.angular_velocity),
        strict=True,
    ):
        np.testing.assert_allclose(b, a, atol=1e-12)
    # a body spinning freely (no gravity, no forces) keeps its angular momentum: the local
    # free-joint velocity convention is handled
    backend = MujocoBackend(fleet, state, timestep=1 / 600, gravity=0.0)
    inertia = [b.inertia for b in fleet.bodies]

    def momentum(s):
        rot = quaternion_to_matrix(s.quaternion)
        return [r @ i @ r.T @ w for r, i, w in zip(rot, inertia, s.angular_velocity, strict=True)]

    before = momentum(backend.state())
    for _ in range(600):
        backend.step(np.zeros((2, 3)), np.zeros((2, 3)))
    np.testing.assert_allclose(momentum(backend.state()), before, rtol=2e-2)


def test_agrees_with_builtin_on_equilibrium_and_period(flat_box):
    start = release(flat_box, WATER, height=-0.2)
    results = {}
    for backend in ("builtin", "mujoco"):
        trace = simulate(flat_box, start, WATER, UNDAMPED, seconds=8, backend=backend)
        damped = simulate(flat_box, start, WATER, ForceModel(), seconds=10, backend=backend)
        draft = summarize(flat_box, damped, WATER, ForceModel())[0]["draft_m"]
        results[backend] = (heave_period(trace), draft)
    (p_b, d_b), (p_m, d_m) = results["builtin"], results["mujoco"]
    assert p_m == pytest.approx(p_b, rel=BUOYANCY_BACKEND_RTOL)
    assert d_m == pytest.approx(d_b, rel=BUOYANCY_BACKEND_RTOL)
    assert d_m == pytest.approx(0.25, rel=1e-2)


@pytest.mark.slow
def test_energy_bounded_over_a_minute_mujoco(flat_box):
    start = release(flat_box, WATER, height=-0.2)
    trace = simulate(flat_box, start, WATER, UNDAMPED, seconds=60, backend="mujoco")
    assert_energy_bounded(flat_box, trace)


def test_bodies_rest_on_the_floor_the_shore_and_each_other():
    heavy = make_body(make_shape("box", size=0.5), 2500, resolution=4)
    light = make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=4)
    fleet = pack([heavy, heavy, light, heavy])
    start = release(fleet, WATER, height=-0.5, spacing=3.0)
    start.position[:, 0] = [0.0, 8.0, -6.0, -6.0]  # body 1 over the beach
    start.position[3, 1] = 1.5  # body 3 dropped onto the floating body 2
    floor = -3.0
    trace = simulate(
        fleet, start, WATER, ForceModel(), seconds=6, backend="mujoco", floor=floor, shore=6.0
    )
    low = clearance(fleet, trace, WATER)[-1]
    assert low[0] == pytest.approx(floor, abs=0.02)  # sank and rests on the floor
    # body 1 rests on the beach: its hull touches the 15 degree plane rising from x = 6
    a = np.radians(15.0)
    hull = heavy.hull_vertices @ quaternion_to_matrix(trace.quaternion[-1, 1]).T
    hull += trace.position[-1, 1]
    gap = (hull - (6.0, floor, 0.0)) @ (-np.sin(a), np.cos(a), 0.0)
    assert gap.min() == pytest.approx(0.0, abs=0.02)
    assert low[1] > floor + 0.2  # held up by the beach, above the floor (friction > tan 15)
    top_of_raft = trace.position[-1, 2, 1] + 0.25
    assert low[3] == pytest.approx(top_of_raft, abs=0.02)  # sits on the floating body


def test_forces_from_poses_left_by_mj_step_pump_energy(flat_box):
    """Why the backend uses mj_step1 / forces / mj_step2: forces computed from ``xpos``/``xquat``
    after ``mj_step`` come from the state before that step, and the one-step lag drives the
    undamped heave from 5 cm to more than a metre in 20 s; the backend's way stays at 5 cm."""
    import mujoco

    from bakeshop.buoyancy.forces import evaluate

    start = release(flat_box, WATER, height=-0.2)
    right = MujocoBackend(flat_box, start, timestep=1 / 60, gravity=9.81)
    naive = MujocoBackend(flat_box, start, timestep=1 / 60, gravity=9.81)
    heights = {"right": [], "naive": []}
    for _ in range(1200):
        f = evaluate(flat_box, right.state(), WATER, UNDAMPED, 0.0, 1 / 60)
        right.step(f.force, f.torque)
        now = naive.state()
        stale = State(naive.data.xpos[1:].copy(), naive.data.xquat[1:].copy(), now.velocity,
                      now.angular_velocity)  # fmt: skip
        f = evaluate(flat_box, stale, WATER, UNDAMPED, 0.0, 1 / 60)
        naive.data.xfrc_applied[1:, :3] = f.force
        naive.data.xfrc_applied[1:, 3:] = f.torque
        mujoco.mj_step(naive.model, naive.data)
        heights["right"].append(right.state().position[0, 1])
        heights["naive"].append(naive.state().position[0, 1])
    assert np.abs(heights["right"]).max() < 0.051
    assert np.abs(heights["naive"][-120:]).max() > 1.0
