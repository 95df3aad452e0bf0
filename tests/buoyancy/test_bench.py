"""The test bench (bakeshop.buoyancy.bench.float_body): its arguments, and one short float of
a box whose draft and heave frequency are known in closed form."""

import math

import numpy as np
import pytest

from bakeshop.buoyancy.bench import float_body
from bakeshop.buoyancy.forces import ForceModel
from bakeshop.buoyancy.shapes import make_shape
from bakeshop.errors import ArgumentError
from tests.tolerances import BUOYANCY_ARCHIMEDES_RTOL, BUOYANCY_FLOAT64


def test_a_mesh_or_a_shape_is_needed_but_not_both():
    with pytest.raises(ArgumentError):
        float_body(density=500.0)
    with pytest.raises(ArgumentError):
        float_body(make_shape("box"), shape="box", density=500.0)


def test_a_tilt_that_is_not_finite_is_refused():
    with pytest.raises(ArgumentError):
        float_body(shape="box", density=500.0, tilt=float("nan"))


@pytest.mark.slow
def test_a_floating_box_reports_its_draft_and_heave_frequency():
    model = ForceModel()
    fps, solver_hz = 30.0, 60.0
    result = float_body(shape="box", density=500.0, resolution=6, seconds=3.0, fps=fps,
                        solver_hz=solver_hz, release_height=0.0)  # fmt: skip
    s = result.summary
    # a 1 m cube at half the density of water: half under, water-plane area 1 m^2
    assert s["archimedes_draft_m"] == pytest.approx(0.5, rel=BUOYANCY_ARCHIMEDES_RTOL)
    omega = math.sqrt(model.rho_water * model.gravity * 1.0 / 500.0)
    assert s["heave_omega_rad_s"] == pytest.approx(omega, rel=BUOYANCY_ARCHIMEDES_RTOL)
    assert s["omega_dt"] == pytest.approx(omega / solver_hz, rel=BUOYANCY_ARCHIMEDES_RTOL)
    steps = result.trace.time.size
    assert result.clearance.shape == (steps,)
    assert len(result.fleet) == 1
    # released with its lowest point at the surface: the first recorded clearance is 0
    assert result.clearance[0] == pytest.approx(0.0, abs=BUOYANCY_FLOAT64)
    assert np.all(np.isfinite(result.clearance))


@pytest.mark.slow
def test_a_sinking_body_has_no_heave_frequency():
    result = float_body(shape="box", density=3000.0, resolution=4, seconds=0.5)
    assert result.summary["archimedes_draft_m"] is None
    assert result.summary["heave_omega_rad_s"] is None
    assert result.summary["omega_dt"] is None
