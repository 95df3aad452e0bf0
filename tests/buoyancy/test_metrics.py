"""What the test bench measures (bakeshop.buoyancy.metrics), on traces whose answers are known
in closed form: clearance of a box at set poses, energy of a body at rest above, across and
below the surface, and the bench's summary of a body held still or thrown out of the water."""

import numpy as np
import pytest
import trimesh

from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import clearance, energy, summarize
from bakeshop.buoyancy.state import axis_angle_quaternion, quaternion_to_matrix
from bakeshop.buoyancy.stepping import Trace
from bakeshop.buoyancy.water import Water, Wave
from tests.tolerances import BUOYANCY_ARCHIMEDES_RTOL, BUOYANCY_FLOAT64

MODEL = ForceModel()


@pytest.fixture(scope="module")
def cube():
    """A 1 m cube of density 500 kg/m^3: it floats half in, half out."""
    return pack([make_body(trimesh.creation.box(extents=(1, 1, 1)), 500.0, resolution=6)])


def _trace(time, heights, *, quaternion=(1.0, 0.0, 0.0, 0.0), velocity=None, spin=None):
    """A one-body trace with the centre of mass at (0, height, 0)."""
    time = np.asarray(time, dtype=np.float64)
    s = time.size
    position = np.zeros((s, 1, 3))
    position[:, 0, 1] = heights
    q = np.broadcast_to(np.asarray(quaternion, dtype=np.float64), (s, 1, 4)).copy()
    v = np.zeros((s, 1, 3)) if velocity is None else np.broadcast_to(velocity, (s, 1, 3)).copy()
    w = np.zeros((s, 1, 3)) if spin is None else np.broadcast_to(spin, (s, 1, 3)).copy()
    return Trace(time, position, q, v, w, np.zeros((s, 1), dtype=np.int64))


def test_clearance_is_the_lowest_corner_above_calm_water(cube):
    trace = _trace([0.0, 1.0], [2.0, -0.25])
    np.testing.assert_allclose(clearance(cube, trace, Water()), [[1.5], [-0.75]])
    # turned 45 degrees about Z, the lowest edge is half a diagonal below the centre
    tilted = _trace([0.0], [2.0], quaternion=axis_angle_quaternion((0, 0, 1), 45.0))
    expected = 2.0 - np.sqrt(2) / 2
    np.testing.assert_allclose(clearance(cube, tilted, Water()), [[expected]], atol=1e-12)


def test_clearance_is_measured_from_the_wave_under_the_lowest_point(cube):
    water = Water(level=0.3, waves=(Wave(amplitude=0.2, wavelength=8.0, direction=30.0),))
    q = axis_angle_quaternion((1.0, 0.3, 0.7), 25.0)  # one corner lowest
    trace = _trace([0.0, 0.5, 1.25], [1.0, 1.1, 0.9], quaternion=q)
    corners = np.array(np.meshgrid([-0.5, 0.5], [-0.5, 0.5], [-0.5, 0.5])).reshape(3, -1).T
    world = corners @ quaternion_to_matrix(q).T
    low = world[np.argmin(world[:, 1])]
    y = low[1] + trace.position[:, 0, 1]
    expected = y - water.height(low[0], low[2], trace.time)
    np.testing.assert_allclose(clearance(cube, trace, water)[:, 0], expected, atol=1e-12)


def test_energy_above_the_water_is_kinetic_plus_gravity(cube):
    body = cube.bodies[0]
    spin = np.array([0.0, 0.0, 3.0])  # about a principal axis: (1/2) I_zz w^2
    trace = _trace([0.0], [4.0], velocity=[1.0, -2.0, 0.5], spin=spin)
    g = MODEL.gravity
    expected = 0.5 * body.mass * 5.25 + 0.5 * body.inertia[2, 2] * 9.0 + body.mass * g * 4.0
    assert energy(cube, trace, Water(), MODEL)[0, 0] == pytest.approx(expected, rel=1e-12)


def test_energy_of_a_submerged_body_has_the_constant_buoyancy_potential(cube):
    # deep under water every column is full: the buoyancy is rho g V upward whatever the depth,
    # so its potential is rho g V (level - y) (up to the columns' centroid, the centre here)
    body = cube.bodies[0]
    level, y = 0.0, -5.0
    volume = cube.volumes.sum()
    g, rho = MODEL.gravity, MODEL.rho_water
    expected = body.mass * g * y + rho * g * volume * (level - y)
    got = energy(cube, _trace([0.0], [y]), Water(level=level), MODEL)[0, 0]
    assert got == pytest.approx(expected, rel=1e-9)


def test_a_body_held_at_its_draft_is_summarised_as_settled(cube):
    time = np.linspace(0.0, 4.0, 41)
    (row,) = summarize(cube, _trace(time, np.zeros_like(time)), Water(), MODEL)
    assert row["draft_m"] == pytest.approx(0.5, abs=BUOYANCY_FLOAT64)
    assert row["archimedes_draft_m"] == pytest.approx(0.5, rel=BUOYANCY_ARCHIMEDES_RTOL)
    assert row["mass_kg"] == pytest.approx(500.0, rel=BUOYANCY_FLOAT64)
    assert row["volume_m3"] == pytest.approx(1.0, rel=BUOYANCY_FLOAT64)
    assert row["points"] == len(cube.bodies[0].points)
    assert row["times_left_water"] == 0
    assert row["max_jump_m"] == 0.0
    assert row["settle_time_s"] == 0.0


def test_a_body_thrown_out_once_is_counted_once(cube):
    time = np.linspace(0.0, 10.0, 101)
    heights = np.zeros_like(time)
    heights[10:20] = 2.0  # out of the water from t = 1 to t = 1.9 (clearance 1.5 m)
    (row,) = summarize(cube, _trace(time, heights), Water(), MODEL)
    assert row["times_left_water"] == 1
    assert row["max_jump_m"] == pytest.approx(1.5)
    assert row["settle_time_s"] == pytest.approx(2.0)  # the first step back at the draft
    assert row["draft_m"] == pytest.approx(0.5)


def test_a_body_still_moving_at_the_end_has_not_settled(cube):
    time = np.linspace(0.0, 8.0, 81)
    (row,) = summarize(cube, _trace(time, 0.2 * np.sin(3 * time)), Water(), MODEL)
    assert row["settle_time_s"] is None


def test_a_body_that_sinks_has_no_archimedes_draft():
    lead = pack([make_body(trimesh.creation.box(extents=(1, 1, 1)), 11340.0, resolution=4)])
    time = np.linspace(0.0, 1.0, 11)
    (row,) = summarize(lead, _trace(time, -3.0 - time), Water(), MODEL)
    assert row["archimedes_draft_m"] is None
