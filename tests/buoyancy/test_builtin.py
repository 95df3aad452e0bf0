"""The built-in integrator (semi-implicit Euler) against its own closed forms: free fall, a
constant push, and torque-free spin about a principal axis (the rotation by |w| t, compared with
scipy's Rotation)."""

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from bakeshop.buoyancy.builtin import BuiltinBackend
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.state import State, quaternion_to_matrix
from tests.tolerances import BUOYANCY_FLOAT64

DT = 1 / 60
G = 9.81


@pytest.fixture(scope="module")
def fleet():
    return pack([make_body(trimesh.creation.box(extents=(2.0, 0.5, 1.0)), 400.0, resolution=4)])


def _at_rest(n=1):
    return State(np.zeros((n, 3)), np.tile([1.0, 0, 0, 0], (n, 1)), np.zeros((n, 3)),
                 np.zeros((n, 3)))  # fmt: skip


def test_free_fall_follows_semi_implicit_euler_exactly(fleet):
    backend = BuiltinBackend(fleet, _at_rest(), timestep=DT, gravity=G)
    steps = 90
    for _ in range(steps):
        backend.step(np.zeros((1, 3)), np.zeros((1, 3)))
    s = backend.state()
    # v_n = -g n dt; y_n = sum of v_k dt = -g dt^2 n (n + 1) / 2 (velocity first, then position)
    assert s.velocity[0, 1] == pytest.approx(-G * steps * DT, rel=BUOYANCY_FLOAT64)
    assert s.position[0, 1] == pytest.approx(-G * DT * DT * steps * (steps + 1) / 2, rel=1e-12)
    np.testing.assert_array_equal(s.quaternion[0], [1, 0, 0, 0])


def test_a_force_that_cancels_gravity_leaves_the_body_at_rest_and_a_push_accelerates_it(fleet):
    mass = fleet.mass[0]
    backend = BuiltinBackend(fleet, _at_rest(), timestep=DT, gravity=G)
    push = np.array([[3.0, mass * G, 0.0]])  # gravity cancelled, 3 N along +X
    for _ in range(30):
        backend.step(push, np.zeros((1, 3)))
    s = backend.state()
    assert s.velocity[0, 0] == pytest.approx(3.0 / mass * 30 * DT, rel=BUOYANCY_FLOAT64)
    assert abs(s.velocity[0, 1]) < BUOYANCY_FLOAT64


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_torque_free_spin_about_a_principal_axis_turns_at_a_constant_rate(fleet, axis):
    omega = np.zeros((1, 3))
    omega[0, axis] = 2.5
    start = _at_rest()
    backend = BuiltinBackend(fleet, start, timestep=DT, gravity=0.0)
    backend.set_velocities(np.zeros((1, 3)), omega)
    steps = 45
    for _ in range(steps):
        backend.step(np.zeros((1, 3)), np.zeros((1, 3)))
    s = backend.state()
    np.testing.assert_allclose(s.angular_velocity, omega, atol=BUOYANCY_FLOAT64)
    expected = Rotation.from_rotvec(omega[0] * steps * DT).as_matrix()
    np.testing.assert_allclose(quaternion_to_matrix(s.quaternion[0]), expected, atol=1e-10)
    assert np.linalg.norm(s.quaternion[0]) == pytest.approx(1.0, abs=BUOYANCY_FLOAT64)


def test_the_backend_keeps_its_own_copy_of_the_state(fleet):
    start = _at_rest()
    backend = BuiltinBackend(fleet, start, timestep=DT, gravity=G)
    backend.step(np.zeros((1, 3)), np.zeros((1, 3)))
    assert start.velocity[0, 1] == 0.0  # the caller's state is untouched
    snapshot = backend.state()
    snapshot.position[:] = 99.0
    assert backend.state().position[0, 1] != 99.0
