"""Floating dynamics with the built-in integrator, against hydrostatics and small-oscillation
theory, and the trampoline failure with its causes and fixes."""

import numpy as np
import pytest

from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import energy, summarize
from bakeshop.buoyancy.shapes import SHAPES, make_shape
from bakeshop.buoyancy.state import axis_angle_quaternion, quaternion_to_matrix
from bakeshop.buoyancy.stepping import release, simulate
from bakeshop.buoyancy.water import Water
from bakeshop.errors import ArgumentError, BakeshopError
from tests.buoyancy.helpers import (
    UNDAMPED,
    assert_energy_bounded,
    cylinder_draft,
    heave_period,
    sphere_draft,
)
from tests.tolerances import BUOYANCY_DRAFT_RTOL, BUOYANCY_PERIOD_RTOL

WATER = Water()
FIX = ForceModel(damping="team", stabilize="predict")


def test_equilibrium_drafts():
    bodies = [
        make_body(make_shape("box", size=(2, 0.5, 1)), 500, resolution=8),
        make_body(make_shape("sphere"), 300, resolution=16),
        make_body(make_shape("cylinder"), 300, resolution=16),
    ]
    fleet = pack(bodies)
    trace = simulate(fleet, release(fleet, WATER, height=-0.2), WATER, FIX, seconds=20)
    rows = summarize(fleet, trace, WATER, FIX)
    expected = [0.25, sphere_draft(0.5, 300), cylinder_draft(0.5, 300)]
    for row, draft in zip(rows, expected, strict=True):
        assert row["draft_m"] == pytest.approx(draft, rel=BUOYANCY_DRAFT_RTOL)
        assert row["archimedes_draft_m"] == pytest.approx(draft, rel=1e-3)
        assert row["settle_time_s"] is not None and row["times_left_water"] == 0


def test_undamped_heave_period():
    """Flat box (stable face-up): T = 2 pi sqrt(m / (rho g A_wp)), added mass neglected."""
    fleet = pack([make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=8)])
    trace = simulate(fleet, release(fleet, WATER, height=-0.2), WATER, UNDAMPED, seconds=12)
    expected = 2 * np.pi * np.sqrt(250 / (1000 * 9.81 * 1.0))
    assert heave_period(trace) == pytest.approx(expected, rel=BUOYANCY_PERIOD_RTOL)


def test_per_substep_results_do_not_depend_on_frame_rate():
    fleet = pack([make_body(make_shape("peep"), 400, resolution=8)])
    start = release(fleet, WATER, height=-0.6, quaternions=[axis_angle_quaternion((1, 0, 1), 20)])
    runs = [
        simulate(fleet, start, WATER, FIX, seconds=3, fps=fps, forces="per-substep")
        for fps in (10, 25, 60, 144)
    ]
    n = min(len(r.time) for r in runs)
    for run in runs[1:]:
        np.testing.assert_allclose(run.position[:n], runs[0].position[:n], atol=1e-12)
        np.testing.assert_allclose(run.quaternion[:n], runs[0].quaternion[:n], atol=1e-12)
    # ... and converge with the solver rate at first order (semi-implicit Euler's O(h) error)
    reference = simulate(fleet, start, WATER, FIX, seconds=3, solver_hz=480)
    errors = []
    for hz in (60, 120):
        run = simulate(fleet, start, WATER, FIX, seconds=3, solver_hz=hz)
        ref_y = np.interp(run.time, reference.time, reference.position[:, 0, 1])
        errors.append(np.abs(run.position[:, 0, 1] - ref_y).max())
    assert errors[0] < 0.05
    assert 0.3 * errors[0] < errors[1] < 0.6 * errors[0]


@pytest.mark.slow
def test_trampoline_is_real_and_the_team_fix_works():
    bodies = [make_body(make_shape(name), 500, resolution=8) for name in SHAPES]
    fleet = pack(bodies)
    deep = release(fleet, WATER, height=-2.0)
    raw = simulate(fleet, deep, WATER, UNDAMPED, seconds=8, fps=10, forces="per-frame")
    physical = simulate(fleet, deep, WATER, UNDAMPED, seconds=8, fps=60, forces="per-substep")
    raw_rows = summarize(fleet, raw, WATER, UNDAMPED)
    physical_rows = summarize(fleet, physical, WATER, UNDAMPED)
    for r, p in zip(raw_rows, physical_rows, strict=True):
        assert r["times_left_water"] > 0
        # the per-frame jumps are far beyond what the undamped physics itself does
        assert r["max_jump_m"] > 2 * p["max_jump_m"]
    for forces in ("per-frame", "per-substep"):
        for fps in (10, 20, 30, 60):
            fixed = simulate(fleet, deep, WATER, FIX, seconds=8, fps=fps, forces=forces)
            for row in summarize(fleet, fixed, WATER, FIX):
                assert row["times_left_water"] == 0, (forces, fps)


def test_cause_one_semi_implicit_euler_is_unstable_above_omega_dt_2():
    """A 2 cm plank (density 500): omega = sqrt(g / 0.01 m) = 31 rad/s. With its 2 cm columns
    the model has the same stiffness; omega h = 3.1 at 10 Hz (unstable), 0.52 at 60 Hz."""
    fleet = pack([make_body(make_shape("box", size=(1, 0.02, 1)), 500, resolution=50)])
    start = release(fleet, WATER, height=-0.005)
    slow = simulate(fleet, start, WATER, UNDAMPED, seconds=3, fps=10, solver_hz=10)
    fast = simulate(fleet, start, WATER, UNDAMPED, seconds=3, fps=60, solver_hz=60)
    # the instability grows until the clamped columns saturate (a bounded limit cycle)
    assert np.abs(slow.position[:, 0, 1]).max() > 5 * 0.005
    # bounded by the release offset, up to the integrator's 1 / sqrt(1 - (omega h / 2)^2) = 1.035
    assert np.abs(fast.position[:, 0, 1]).max() < 0.005 * 1.05


def test_cause_two_held_forces_pump_energy():
    """Box heaving with omega dT = 0.63 < 2 at 10 fps: stable, yet forces held over the frame
    add energy every cycle; recomputed per substep the energy stays put."""
    fleet = pack([make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=8)])
    start = release(fleet, WATER, height=-0.2)
    held = simulate(fleet, start, WATER, UNDAMPED, seconds=6, fps=10, forces="per-frame")
    fresh = simulate(fleet, start, WATER, UNDAMPED, seconds=6, fps=10, forces="per-substep")
    e_held = energy(fleet, held, WATER, UNDAMPED)[:, 0]
    e_fresh = energy(fleet, fresh, WATER, UNDAMPED)[:, 0]
    oscillation = (0.5 * 250 * fresh.velocity[:, 0, 1] ** 2).max()
    assert e_held[-60:].mean() - e_held[:60].mean() > 1.0 * oscillation
    assert abs(e_fresh[-60:].mean() - e_fresh[:60].mean()) < 0.02 * oscillation


def test_energy_bounded_over_a_minute_builtin():
    fleet = pack([make_body(make_shape("box", size=(1, 0.5, 1)), 500, resolution=8)])
    trace = simulate(fleet, release(fleet, WATER, height=-0.2), WATER, UNDAMPED, seconds=60)
    assert_energy_bounded(fleet, trace)


def tilt_after(fleet, trace, body=0):
    """Angle (degrees) between the body's up axis and the world's up at the end."""
    up = quaternion_to_matrix(trace.quaternion[-1, body])[:, 1]
    return np.degrees(np.arccos(np.clip(abs(up[1]), 0, 1)))


def test_flat_box_is_righted_and_cube_tips_as_hydrostatics_says():
    flat = make_body(make_shape("box", size=(2, 0.5, 1)), 500, resolution=12)
    cubes = [make_body(make_shape("box"), rho, resolution=8) for rho in (500, 150, 850)]
    fleet = pack([flat, *cubes])
    tilts = [axis_angle_quaternion((1, 0, 0), a) for a in (25, 3, 3, 3)]
    start = release(fleet, WATER, height=-0.1, quaternions=tilts)
    trace = simulate(fleet, start, WATER, FIX, seconds=25)
    assert tilt_after(fleet, trace, 0) < 1.0  # righted
    assert tilt_after(fleet, trace, 1) > 20.0  # relative density 0.5: tips off its face
    assert tilt_after(fleet, trace, 2) < 1.0  # 0.15 < 0.21: stable face-up
    assert tilt_after(fleet, trace, 3) < 1.0  # 0.85 > 0.79: stable face-up


def test_velocity_clamp_limits_speed_while_partly_submerged():
    fleet = pack([make_body(make_shape("sphere"), 300, resolution=8)])
    model = ForceModel(damping="none", stabilize="clamp", clamp_speed=0.5)
    trace = simulate(fleet, release(fleet, WATER, height=-2.5), WATER, model, seconds=4)
    partly = (trace.submerged_points > 0) & (trace.submerged_points < len(fleet.points))
    speed = np.linalg.norm(trace.velocity[:, 0], axis=1)
    assert partly[:, 0].any() and speed[partly[:, 0]].max() <= 0.5 + 1e-9
    assert speed.max() > 2.0  # rises freely while fully submerged


def test_bad_stepping_arguments():
    fleet = pack([make_body(make_shape("box"), 500, resolution=2)])
    start = release(fleet, WATER)
    with pytest.raises(ArgumentError, match="force mode"):
        simulate(fleet, start, WATER, forces="sometimes")
    with pytest.raises(ArgumentError, match="fps"):
        simulate(fleet, start, WATER, fps=0)
    with pytest.raises(ArgumentError, match="seconds"):
        simulate(fleet, start, WATER, seconds=float("nan"))
    with pytest.raises(ArgumentError, match="exceed"):
        simulate(fleet, start, WATER, seconds=1e9)
    with pytest.raises(ArgumentError, match="backend"):
        simulate(fleet, start, WATER, backend="bullet")


def test_divergence_is_reported_not_returned():
    """Angular team damping with c h = 1e5 on a spinning, neutrally buoyant, deep body: the
    spin flips and grows 1e5-fold per step until it overflows."""
    fleet = pack([make_body(make_shape("box"), 1000, resolution=2)])
    absurd = ForceModel(damping="team", stabilize="none", angular_damping=1e6)
    start = release(fleet, WATER, height=-10.0)
    start.angular_velocity[:] = (0.0, 1.0, 0.0)
    with pytest.raises(BakeshopError, match="diverged"):
        simulate(fleet, start, WATER, absurd, seconds=30, fps=10, solver_hz=10)
    with pytest.raises(ArgumentError, match="finite"):
        release(fleet, WATER, height=float("nan"))
    with pytest.raises(ArgumentError, match="quaternions"):
        release(fleet, WATER, quaternions=[[0, 0, 0, 0]])


def test_long_waves_carry_a_small_body():
    from bakeshop.buoyancy.water import Wave

    water = Water(waves=(Wave(0.2, 40.0),))
    fleet = pack([make_body(make_shape("box", size=(0.5, 0.25, 0.5)), 500, resolution=4)])
    start = release(fleet, water, height=-0.125)
    trace = simulate(fleet, start, water, FIX, seconds=30)
    y = trace.position[len(trace.time) // 2 :, 0, 1]
    amplitude = (y.max() - y.min()) / 2
    assert amplitude == pytest.approx(0.2, rel=0.1)
    period = 2 * np.pi / water.table[0, 3]
    assert heave_period(trace) == pytest.approx(period, rel=0.05)


def test_reference_drafts_at_half_density():
    """The closed-form helpers the draft tests rely on: a half-dense sphere or horizontal
    cylinder floats exactly half submerged, by symmetry."""
    assert sphere_draft(0.5, 500) == pytest.approx(0.5)
    assert cylinder_draft(0.5, 500) == pytest.approx(0.5)
