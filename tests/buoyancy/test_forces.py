"""Point forces against hydrostatics done independently (manifold3d clipping, closed forms)."""

import numpy as np
import pytest

from bakeshop.buoyancy.forces import ForceModel, evaluate
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.shapes import make_shape
from bakeshop.buoyancy.state import State, axis_angle_quaternion, quaternion_to_matrix
from bakeshop.buoyancy.water import Water, Wave
from bakeshop.errors import ArgumentError
from tests.buoyancy.helpers import clipped_below

RHO_G = 1000 * 9.81
STILL = ForceModel(damping="none", stabilize="none")


def one(body, position=(0, 0, 0), quaternion=(1, 0, 0, 0), velocity=(0, 0, 0), omega=(0, 0, 0)):
    arr = [np.array([v], dtype=np.float64) for v in (position, quaternion, velocity, omega)]
    return pack([body]), State(*arr)


def test_submerged_and_half_submerged_box():
    body = make_body(make_shape("box", size=(2, 0.5, 1)), 500, resolution=8)
    fleet, state = one(body, position=(0, -5, 0))
    f = evaluate(fleet, state, Water(), STILL, 0.0, 1 / 60)
    np.testing.assert_allclose(f.force[0], [0, RHO_G * 1.0, 0], rtol=1e-12)
    np.testing.assert_allclose(f.torque[0], 0, atol=1e-9)
    for level in (0.0, 0.07, -0.11):  # partial cells: the column model is exact for a box
        fleet, state = one(body, position=(0, -level, 0))
        f = evaluate(fleet, state, Water(), STILL, 0.0, 1 / 60)
        assert f.force[0, 1] == pytest.approx(RHO_G * 2 * (0.25 + level), rel=1e-12)
        assert f.submerged_volume[0] == pytest.approx(2 * (0.25 + level), rel=1e-12)


@pytest.mark.parametrize("degrees", [10, 25])
def test_righting_moment_matches_exact_centre_of_buoyancy(degrees):
    """Tilted flat box: point forces and torque vs the clipped solid's volume and centroid."""
    body = make_body(make_shape("box", size=(2, 0.5, 1)), 500, resolution=24)
    q = axis_angle_quaternion((1, 0, 0), degrees)
    fleet, state = one(body, position=(0, 0.05, 0), quaternion=q)
    f = evaluate(fleet, state, Water(), STILL, 0.0, 1 / 60)
    posed = body.mesh.copy()
    transform = np.eye(4)
    transform[:3, :3] = quaternion_to_matrix(q)
    transform[:3, 3] = (0, 0.05, 0)
    posed.apply_transform(transform)
    wet = clipped_below(posed, 0.0)
    lift = RHO_G * wet.volume
    moment = np.cross(wet.center_mass - (0, 0.05, 0), (0, lift, 0))
    assert f.force[0, 1] == pytest.approx(lift, rel=5e-3)
    np.testing.assert_allclose(f.torque[0], moment, atol=0.03 * abs(moment).max())
    assert f.torque[0, 0] * moment[0] > 0  # righting, not capsizing


def test_predictive_stabiliser_scales_rising_points():
    body = make_body(make_shape("box"), 500, resolution=6)
    model = ForceModel(damping="none", stabilize="predict", predict_c=2.5, predict_m=0.1)
    at_rest = evaluate(*one(body), Water(), model, 0.0, 0.1)
    sinking = evaluate(*one(body, velocity=(0, -3, 0)), Water(), model, 0.0, 0.1)
    rising = evaluate(*one(body, velocity=(0, 3, 0)), Water(), model, 0.0, 0.1)
    plain = evaluate(*one(body), Water(), STILL, 0.0, 0.1)
    # at rest, only points whose centre is above the water are scaled: none of the submerged ones
    assert at_rest.force[0, 1] == pytest.approx(plain.force[0, 1])
    assert sinking.force[0, 1] == pytest.approx(plain.force[0, 1])
    # rising at 3 m/s looks 0.75 m ahead: every wet point of the 1 m cube would be out -> M
    assert rising.force[0, 1] == pytest.approx(0.1 * plain.force[0, 1])


def test_team_damping_rises_logarithmically():
    body = make_body(make_shape("box"), 500, resolution=4)  # 64 points, 16 per layer
    model = ForceModel(damping="team", stabilize="none", linear_damping=2.0, angular_damping=3.0)
    for depth, wet_points in ((0.5 - 0.125, 16), (0.0, 32), (-2.0, 64)):
        v, w = np.array([0.3, -0.2, 0.1]), np.array([0.0, 0.4, 0.0])
        fleet, moving = one(body, position=(0, depth, 0), velocity=v, omega=w)
        fleet, still = one(body, position=(0, depth, 0))
        a = evaluate(fleet, moving, Water(), model, 0.0, 1 / 60)
        b = evaluate(fleet, still, Water(), model, 0.0, 1 / 60)
        assert a.submerged_points[0] == wet_points
        s = np.log(1 + wet_points) / np.log(65)
        np.testing.assert_allclose(a.force[0] - b.force[0], -2.0 * s * body.mass * v, atol=1e-9)
        np.testing.assert_allclose(
            a.torque[0] - b.torque[0], -3.0 * s * body.inertia @ w, atol=1e-9
        )


def test_drag_opposes_relative_velocity_and_is_quadratic():
    body = make_body(make_shape("sphere"), 500, resolution=8)
    model = ForceModel(damping="drag", stabilize="none", drag_coefficient=1.0)
    fleet, still = one(body, position=(0, -3, 0))
    base = evaluate(fleet, still, Water(), model, 0.0, 1 / 60).force[0]
    drags = []
    for speed in (0.5, 1.0):
        _, moving = one(body, position=(0, -3, 0), velocity=(speed, 0, 0))
        drags.append(evaluate(fleet, moving, Water(), model, 0.0, 1 / 60).force[0] - base)
    # 1/2 rho C_d A |u| u with A = (sum of point volumes) / V^(1/3), about V^(2/3)
    expected = 0.5 * 1000 * body.points.volumes.sum() / body.volume ** (1 / 3)
    np.testing.assert_allclose(drags[0], [-expected * 0.25, 0, 0], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(drags[1], [-expected, 0, 0], rtol=1e-9, atol=1e-9)


def test_waves_surface_matches_water_height():
    """A thin full-cell layer of points reports the wave height through its submerged volume."""
    water = Water(waves=(Wave(0.3, 12.0, 30.0), Wave(0.1, 5.0, -60.0, speed=2.0)))
    body = make_body(make_shape("box", size=(0.1, 0.1, 0.1)), 500, resolution=1)
    for x, z, t in ((0.0, 0.0, 0.0), (3.0, -2.0, 1.7), (-5.0, 4.0, 9.1)):
        eta = water.height(x, z, t)
        fleet, state = one(body, position=(x, eta - 0.01, z))  # 0.06 of the 0.1 column is wet
        f = evaluate(fleet, state, water, STILL, t, 1 / 60)
        assert f.submerged_volume[0] == pytest.approx(0.1**3 * 0.6, rel=1e-6)


def test_wave_parsing_and_limits():
    assert Wave.parse("0.2:8:30") == Wave(0.2, 8.0, 30.0)
    assert Wave.parse("0.2:8:30:3.5").speed == 3.5
    for bad in ("1", "a:b", "0.2:8:1:2:3"):
        with pytest.raises(ArgumentError):
            Wave.parse(bad)
    with pytest.raises(ArgumentError, match="steepness"):
        Wave(2.0, 4.0)
    with pytest.raises(ArgumentError):
        Wave(0.1, -4.0)
    deep = Water(waves=(Wave(0.1, 2 * np.pi),)).table[0]
    assert deep[3] == pytest.approx(np.sqrt(9.81))  # omega = sqrt(g k), k = 1


def test_bad_model_options():
    with pytest.raises(ArgumentError, match="unknown damping"):
        ForceModel(damping="viscous")
    with pytest.raises(ArgumentError, match="unknown stabiliser"):
        ForceModel(stabilize="magic")
    with pytest.raises(ArgumentError):
        ForceModel(predict_c=0.5)
