"""Quaternion helpers of bakeshop.buoyancy.state against scipy's Rotation (an independent
implementation), and the State container."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bakeshop.buoyancy.state import State, axis_angle_quaternion, quaternion_to_matrix, rotation
from tests.tolerances import BUOYANCY_FLOAT64


def _random_quaternions(n, seed=0):
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def test_quaternion_to_matrix_is_scipys_rotation():
    q = _random_quaternions(64)
    expected = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_matrix()  # scipy: scalar last
    np.testing.assert_allclose(quaternion_to_matrix(q), expected, atol=BUOYANCY_FLOAT64)


def test_quaternion_to_matrix_keeps_leading_axes():
    q = _random_quaternions(6).reshape(2, 3, 4)
    m = quaternion_to_matrix(q)
    assert m.shape == (2, 3, 3, 3)
    np.testing.assert_allclose(m[1, 2], quaternion_to_matrix(q[1, 2]), atol=BUOYANCY_FLOAT64)


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 2, 0), (1, -1, 0.5)])
@pytest.mark.parametrize("degrees", [0.0, 30.0, -90.0, 180.0])
def test_axis_angle_quaternion_is_scipys_rotation_vector(axis, degrees):
    axis = np.asarray(axis, dtype=np.float64)
    q = axis_angle_quaternion(axis, degrees)
    assert np.linalg.norm(q) == pytest.approx(1.0, abs=BUOYANCY_FLOAT64)
    vector = np.radians(degrees) * axis / np.linalg.norm(axis)
    expected = Rotation.from_rotvec(vector).as_matrix()
    np.testing.assert_allclose(quaternion_to_matrix(q), expected, atol=BUOYANCY_FLOAT64)


def test_a_quarter_turn_about_y_takes_forward_to_left():
    # +Y up, -Z forward: turning left (counter-clockwise seen from above) takes -Z to -X
    m = quaternion_to_matrix(axis_angle_quaternion((0, 1, 0), 90.0))
    np.testing.assert_allclose(m @ [0, 0, -1], [-1, 0, 0], atol=BUOYANCY_FLOAT64)


def test_the_compiled_rotation_is_scipys_rotation():
    for q in _random_quaternions(16, seed=1):
        expected = Rotation.from_quat(q[[1, 2, 3, 0]]).as_matrix()
        np.testing.assert_allclose(rotation(*q), expected, atol=BUOYANCY_FLOAT64)


def test_state_copy_is_deep():
    s = State(np.zeros((2, 3)), np.tile([1.0, 0, 0, 0], (2, 1)), np.ones((2, 3)), np.zeros((2, 3)))
    c = s.copy()
    c.position[0, 1] = 5.0
    c.quaternion[1] = [0, 1, 0, 0]
    c.velocity += 1
    c.angular_velocity[:] = 3
    assert s.position[0, 1] == 0.0
    np.testing.assert_array_equal(s.quaternion[1], [1, 0, 0, 0])
    np.testing.assert_array_equal(s.velocity, 1.0)
    np.testing.assert_array_equal(s.angular_velocity, 0.0)
