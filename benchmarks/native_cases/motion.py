"""Before/after cases of the motion slice's kernels (issue 32): the old JIT (main before the port)
against the C++ kernels of bakeshop.water and bakeshop.buoyancy. Each case runs a function
whose name and signature exist in both trees; the inputs are made here, outside the thunks."""

from __future__ import annotations

import importlib
from collections.abc import Callable

import numpy as np

from bakeshop.buoyancy.builtin import BuiltinBackend
from bakeshop.buoyancy.forces import ForceModel, evaluate
from bakeshop.buoyancy.mass import make_body, pack
from bakeshop.buoyancy.metrics import clearance
from bakeshop.buoyancy.sampling import sample_points
from bakeshop.buoyancy.shapes import make_shape
from bakeshop.buoyancy.state import State
from bakeshop.buoyancy.stepping import release, simulate
from bakeshop.buoyancy.water import Water, Wave
from bakeshop.water.amplitudes import mode_normals
from bakeshop.water.spectra import Spectrum

# bakeshop.water re-exports functions named like its modules (ocean): import the modules
ocean = importlib.import_module("bakeshop.water.ocean")
gerstner = importlib.import_module("bakeshop.water.gerstner")
cascades = importlib.import_module("bakeshop.water.cascades")
ripples = importlib.import_module("bakeshop.water.ripples")
textures = importlib.import_module("bakeshop.water.textures")


def cases() -> list[tuple[str, Callable[[], object]]]:
    rng = np.random.default_rng(32)
    out: list[tuple[str, Callable[[], object]]] = []

    # --- water ---------------------------------------------------------------------------------
    mx = rng.integers(-2048, 2048, 2_000_000)
    my = rng.integers(-2048, 2048, 2_000_000)
    out.append(("water.amplitudes mode_normals 2M modes", lambda: mode_normals(7, mx, my)))

    sea = ocean.ocean(Spectrum(), size=256.0, resolution=256, seed=3, loop_period=16.0)
    looping = ocean.fit_to_frames(sea, 32, alias="drop")
    out.append(
        (
            "water.ocean ocean_fields loop 256^2 x 32 frames, choppy normals",
            lambda: ocean.ocean_fields(looping, frames=32, fields=("normal",), choppiness=0.8),
        )
    )
    times = np.linspace(0.0, 3.0, 16)
    out.append(
        (
            "water.ocean ocean_fields free times 256^2 x 16, flat normals",
            lambda: ocean.ocean_fields(sea, times=times, fields=("normal", "height")),
        )
    )

    waves = gerstner.gerstner_waves(sea, 32)
    gx, gy = np.meshgrid(np.linspace(0, 256, 256), np.linspace(0, 256, 256))
    out.append(
        (
            "water.gerstner gerstner 32 waves at 256^2 points",
            lambda: gerstner.gerstner(waves, gx, gy, 1.25, choppiness=0.6),
        )
    )

    field = rng.normal(size=(512, 512, 3))
    sx = rng.uniform(-500, 500, 1_000_000)
    sy = rng.uniform(-500, 500, 1_000_000)
    out.append(
        (
            "water.cascades sample_periodic 512^2x3 field at 1M points",
            lambda: cascades.sample_periodic(field, 64.0, sx, sy),
        )
    )

    sim = ripples.WaveEquation(resolution=512, size=20.0, speed=1.0, dt=0.02, damping=0.05)
    sim.add_impact(10.0, 10.0, amplitude=0.02, width=0.5)
    out.append(("water.ripples WaveEquation.step 512^2 x 40 steps", lambda: sim.step(40)))

    normals = ocean.ocean_fields(sea, times=[0.0], fields=("normal",), choppiness=0.5)["normal"][0]
    big = np.ascontiguousarray(np.tile(normals, (8, 8, 1)).astype(np.float32))  # 2048^2
    out.append(("water.textures shade 2048x2048", lambda: textures.shade(big)))

    # --- buoyancy ------------------------------------------------------------------------------
    hull = make_shape("hull")
    out.append(
        (
            "buoyancy.sampling sample_points hull resolution 96",
            lambda: sample_points(hull, resolution=96, subsamples=4),
        )
    )

    body = make_body(make_shape("peep"), 400.0, resolution=72)  # about 57k points
    fleet = pack([body] * 4)
    water = Water(level=0.0, waves=(Wave(0.2, 8.0, 30.0), Wave(0.05, 3.0, -60.0)))
    q = rng.normal(size=(4, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    state = State(rng.normal(scale=0.2, size=(4, 3)), q, rng.normal(size=(4, 3)),
                  rng.normal(size=(4, 3)))  # fmt: skip
    drag = ForceModel(damping="drag")
    out.append(
        (
            f"buoyancy.forces evaluate drag, 4 bodies, {len(fleet.points)} points, x3",
            lambda: [evaluate(fleet, state, water, drag, 0.5 * i, 1 / 60) for i in range(3)],
        )
    )

    small = pack([make_body(make_shape(n), 500.0, resolution=10) for n in ("box", "sphere")])
    start = release(small, water, height=0.2)
    out.append(
        (
            f"buoyancy simulate builtin 2 bodies ({len(small.points)} points) 5 s at 240 Hz",
            lambda: simulate(small, start, water, ForceModel(), seconds=5.0, solver_hz=240.0),
        )
    )
    trace = simulate(small, start, water, ForceModel(), seconds=20.0, solver_hz=240.0)
    out.append(
        (
            f"buoyancy.metrics clearance of {trace.position.shape[0]} steps",
            lambda: clearance(small, trace, water),
        )
    )
    backend = BuiltinBackend(pack([body] * 64), State(
        np.zeros((64, 3)), np.tile([1.0, 0, 0, 0], (64, 1)), np.zeros((64, 3)),
        rng.normal(size=(64, 3))), timestep=1 / 240, gravity=9.81)  # fmt: skip
    push = rng.normal(size=(64, 3))
    out.append(
        (
            "buoyancy.builtin BuiltinBackend.step 64 bodies x 5000",
            lambda: [backend.step(push, push) for _ in range(5000)],
        )
    )
    return out
