"""Floating bodies: voxelised sample points, buoyancy forces, stabilisers, fixed-rate stepping,
rigid-body backends (a built-in integrator and MuJoCo) and the test bench's metrics.

Import from the submodules, each named for what it holds: :mod:`~bakeshop.buoyancy.shapes`
(meshes), :mod:`~bakeshop.buoyancy.sampling` (voxelisation), :mod:`~bakeshop.buoyancy.mass`
(bodies and fleets), :mod:`~bakeshop.buoyancy.hydrostatics` (exact displaced volume and draft),
:mod:`~bakeshop.buoyancy.water`, :mod:`~bakeshop.buoyancy.forces`,
:mod:`~bakeshop.buoyancy.stepping`, :mod:`~bakeshop.buoyancy.builtin`,
:mod:`~bakeshop.buoyancy.mujoco_backend`, :mod:`~bakeshop.buoyancy.metrics` and
:mod:`~bakeshop.buoyancy.matrix`. SI units, +Y up, water 1000 kg/m^3, g = 9.81 m/s^2.
"""
