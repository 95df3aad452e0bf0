"""Floating bodies: voxelised sample points, buoyancy forces, stabilisers, fixed-rate stepping,
rigid-body backends (a built-in integrator and MuJoCo) and the test bench's metrics.

The public API is here (MuJoCo's backend is imported from
:mod:`~bakeshop.buoyancy.mujoco_backend` when used). The submodules, each named for what it
holds: :mod:`~bakeshop.buoyancy.shapes` (meshes), :mod:`~bakeshop.buoyancy.sampling`
(voxelisation), :mod:`~bakeshop.buoyancy.mass` (bodies and fleets),
:mod:`~bakeshop.buoyancy.hydrostatics` (exact displaced volume and draft),
:mod:`~bakeshop.buoyancy.water`, :mod:`~bakeshop.buoyancy.forces`,
:mod:`~bakeshop.buoyancy.stepping`, :mod:`~bakeshop.buoyancy.builtin`,
:mod:`~bakeshop.buoyancy.metrics` and :mod:`~bakeshop.buoyancy.matrix`. SI units, +Y up,
water 1000 kg/m^3, g = 9.81 m/s^2.
"""

from bakeshop.buoyancy.bench import BenchResult, float_body
from bakeshop.buoyancy.builtin import BuiltinBackend
from bakeshop.buoyancy.forces import ForceModel, Forces, evaluate
from bakeshop.buoyancy.hydrostatics import archimedes_draft, submerged_volume, waterplane_area
from bakeshop.buoyancy.mass import Body, Fleet, make_body, pack
from bakeshop.buoyancy.matrix import Matrix, run_matrix, to_csv, to_markdown
from bakeshop.buoyancy.metrics import clearance, energy, summarize
from bakeshop.buoyancy.plots import plot_grid, plot_trace
from bakeshop.buoyancy.sampling import SamplePoints, sample_points
from bakeshop.buoyancy.shapes import SHAPES, closed_mesh, make_shape, resize
from bakeshop.buoyancy.state import State, axis_angle_quaternion, quaternion_to_matrix, rotation
from bakeshop.buoyancy.stepping import Trace, make_backend, release, simulate
from bakeshop.buoyancy.water import Water, Wave

__all__ = [
    "SHAPES",
    "BenchResult",
    "Body",
    "BuiltinBackend",
    "Fleet",
    "ForceModel",
    "Forces",
    "Matrix",
    "SamplePoints",
    "State",
    "Trace",
    "Water",
    "Wave",
    "archimedes_draft",
    "axis_angle_quaternion",
    "clearance",
    "closed_mesh",
    "energy",
    "evaluate",
    "float_body",
    "make_backend",
    "make_body",
    "make_shape",
    "pack",
    "plot_grid",
    "plot_trace",
    "quaternion_to_matrix",
    "release",
    "resize",
    "rotation",
    "run_matrix",
    "sample_points",
    "simulate",
    "submerged_volume",
    "summarize",
    "to_csv",
    "to_markdown",
    "waterplane_area",
]
