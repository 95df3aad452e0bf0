"""Benchmark: buoyancy force evaluation, voxelisation, and stepping with MuJoCo.

Jobs (each in a fresh subprocess, one warm-up run, best of a few runs; peak memory is the
child's peak resident set size from ``resource.getrusage``, which includes the Python
interpreter, numpy and MuJoCo themselves, about 150-250 MB):

``forces``
    One force evaluation of 1000 bodies x 512 points (1 m boxes, voxel resolution 8, random
    poses straddling the surface, team damping and the predictive stabiliser; and the same with
    drag in two wave trains). Peer: the same model as numpy array expressions over all points.
    Figure of merit: point updates per second (target 50 M/s: 1000 bodies in a 60 Hz budget).
``voxelise``
    Sample points of the 20480-face sphere at resolution 16 with 4x4 rays per cell. Peer:
    trimesh's ``contains`` (rtree + ray tests) for the 4x4x4 sub-samples of every cell; it is
    so slow (and memory-hungry: gigabytes for a few thousand points) that it is timed on 512
    random points and scaled to the 262144 sub-samples; its volume error is then the Monte
    Carlo estimate from those 512 points.
``mujoco``
    100 floating boxes (512 points each) in MuJoCo with buoyancy recomputed every 60 Hz step
    (mj_step1, forces, mj_step2). Peers: MuJoCo stepping the same scene with no buoyancy, and
    the built-in integrator with buoyancy.

Run: .venv/bin/python benchmarks/bench_buoyancy.py [--bodies 1000]
"""

from __future__ import annotations

import argparse
import json
import platform
import resource
import subprocess
import sys
import time

import numpy as np


def _best(fn, repeats=5):
    fn()
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def _fleet(n_bodies, resolution=8):
    from bakeshop.buoyancy.mass import make_body, pack
    from bakeshop.buoyancy.shapes import make_shape
    from bakeshop.buoyancy.state import State

    body = make_body(make_shape("box"), 500, resolution=resolution)
    fleet = pack([body] * n_bodies)
    rng = np.random.default_rng(1)
    q = rng.normal(size=(n_bodies, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    side = int(np.ceil(np.sqrt(n_bodies)))
    pos = np.zeros((n_bodies, 3))
    pos[:, 0] = (np.arange(n_bodies) % side) * 2.0
    pos[:, 2] = (np.arange(n_bodies) // side) * 2.0
    pos[:, 1] = rng.uniform(-0.3, 0.3, n_bodies)
    state = State(pos, q, rng.normal(size=(n_bodies, 3)), rng.normal(size=(n_bodies, 3)))
    return fleet, state


def _numpy_forces(fleet, state, model, horizon):
    """The team-damping + predictive model as numpy expressions (flat water), for comparison."""
    from bakeshop.buoyancy.state import quaternion_to_matrix

    counts = np.diff(fleet.offsets)
    body = np.repeat(np.arange(len(fleet)), counts)
    rot = quaternion_to_matrix(state.quaternion)
    r = np.einsum("pij,pj->pi", rot[body], fleet.points)
    x = state.position[body] + r
    u = state.velocity[body] + np.cross(state.angular_velocity[body], r)
    frac = np.clip(-x[:, 1] / fleet.heights + 0.5, 0.0, 1.0)
    lift = model.rho_water * model.gravity * fleet.volumes * frac
    ahead = x[:, 1] + u[:, 1] * horizon * model.predict_c - 0.5 * fleet.heights
    lift = np.where(ahead > 0, lift * model.predict_m, lift)
    f = np.zeros_like(x)
    f[:, 1] = lift
    force = np.zeros((len(fleet), 3))
    torque = np.zeros((len(fleet), 3))
    np.add.at(force, body, f)
    np.add.at(torque, body, np.cross(r, f))
    wet = np.bincount(body, weights=frac > 0, minlength=len(fleet))
    s = np.log1p(wet) / np.log1p(counts)
    force -= (model.linear_damping * s * fleet.mass)[:, None] * state.velocity
    iw = np.einsum("bij,bjk,blk->bil", rot, fleet.inertia, rot)
    torque -= (model.angular_damping * s)[:, None] * np.einsum(
        "bij,bj->bi", iw, state.angular_velocity
    )
    return force, torque


def job_forces(n_bodies):
    from bakeshop import threads
    from bakeshop.buoyancy.forces import ForceModel, evaluate
    from bakeshop.buoyancy.water import Water, Wave

    fleet, state = _fleet(n_bodies)
    points = len(fleet.points)
    flat, waves = Water(), Water(waves=(Wave(0.3, 12.0, 20.0), Wave(0.1, 4.0, -50.0)))
    team = ForceModel()
    drag = ForceModel(damping="drag", stabilize="none")
    ours = evaluate(fleet, state, flat, team, 0.0, 1 / 60)
    ref_f, ref_t = _numpy_forces(fleet, state, team, 1 / 60)
    agree = float(np.abs(ours.force - ref_f).max() / np.abs(ref_f).max())
    t_team = _best(lambda: evaluate(fleet, state, flat, team, 0.0, 1 / 60))
    with threads.limited(1):
        t_one = _best(lambda: evaluate(fleet, state, flat, team, 0.0, 1 / 60))
    t_drag = _best(lambda: evaluate(fleet, state, waves, drag, 0.3, 1 / 60))
    t_numpy = _best(lambda: _numpy_forces(fleet, state, team, 1 / 60), repeats=2)
    return {
        "points": points,
        "team_s": t_team,
        "team_one_thread_s": t_one,
        "drag_waves_s": t_drag,
        "numpy_s": t_numpy,
        "max_rel_diff_vs_numpy": agree,
    }


def job_voxelise():
    from bakeshop.buoyancy.sampling import sample_points
    from bakeshop.buoyancy.shapes import make_shape

    mesh = make_shape("sphere")
    t_ours = _best(lambda: sample_points(mesh, resolution=16, subsamples=4), repeats=3)
    pts = sample_points(mesh, resolution=16, subsamples=4)
    samples = (16 * 4) ** 3
    # trimesh's contains (rtree + numpy ray tests, no embree) costs milliseconds and megabytes
    # per point on this mesh: time it on a random subset and scale to the full sample grid
    subset = np.random.default_rng(0).uniform(*mesh.bounds, size=(512, 3))
    t0 = time.perf_counter()
    inside = mesh.contains(subset)
    t_peer = (time.perf_counter() - t0) / len(subset) * samples
    exact = inside.mean() * np.prod(mesh.extents) / mesh.volume - 1
    return {
        "cells": 16**3,
        "samples": samples,
        "ours_s": t_ours,
        "trimesh_contains_s": t_peer,
        "ours_volume_err": float(pts.volumes.sum() / mesh.volume - 1),
        "trimesh_volume_err": float(exact),
    }


def job_mujoco(n_bodies, steps=300):
    import mujoco

    from bakeshop.buoyancy.forces import ForceModel, evaluate
    from bakeshop.buoyancy.mujoco_backend import MujocoBackend
    from bakeshop.buoyancy.stepping import make_backend
    from bakeshop.buoyancy.water import Water

    fleet, state = _fleet(n_bodies)
    state.quaternion[:] = (1, 0, 0, 0)
    state.velocity[:] = 0
    state.angular_velocity[:] = 0
    water, model = Water(), ForceModel()
    timings = {}
    for name in ("mujoco", "builtin"):
        engine = make_backend(name, fleet, state, timestep=1 / 60, gravity=9.81)

        def run(engine=engine):
            for i in range(steps):
                f = evaluate(fleet, engine.state(), water, model, i / 60, 1 / 60)
                engine.step(f.force, f.torque)

        timings[name] = _best(run, repeats=2) / steps
    bare = MujocoBackend(fleet, state, timestep=1 / 60, gravity=9.81)

    def run_bare():
        for _ in range(steps):
            mujoco.mj_step(bare.model, bare.data)

    timings["mujoco_bare"] = _best(run_bare, repeats=2) / steps
    return {"bodies": n_bodies, **{f"{k}_step_s": v for k, v in timings.items()}}


def _child(args):
    if args.job == "forces":
        out = job_forces(args.bodies)
    elif args.job == "voxelise":
        out = job_voxelise()
    else:
        out = job_mujoco(args.mujoco_bodies)
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(out))


def _run(job, args):
    cmd = [sys.executable, __file__, "--child", job, "--bodies", str(args.bodies),
           "--mujoco-bodies", str(args.mujoco_bodies)]  # fmt: skip
    done = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=1000)
    parser.add_argument("--mujoco-bodies", type=int, default=100)
    parser.add_argument("--child", dest="job")
    args = parser.parse_args()
    if args.job:
        return _child(args)
    from bakeshop import threads

    cpu = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if "model name" in line),
        platform.processor(),
    )
    print(f"machine: {cpu}, {threads.count()} threads")
    f = _run("forces", args)
    p = f["points"]
    print(f"\nforce evaluation, {args.bodies} bodies x {p // args.bodies} points ({p} points)")
    print("| implementation | time per evaluation | point updates/s | ratio | peak RSS |")
    print("|---|---|---|---|---|")
    for label, key in (("bakeshop, team + predict, flat", "team_s"),
                       ("same, one thread", "team_one_thread_s"),
                       ("bakeshop, drag, 2 wave trains", "drag_waves_s"),
                       ("numpy expressions, team + predict, flat", "numpy_s")):  # fmt: skip
        t = f[key]
        print(f"| {label} | {t * 1e3:.2f} ms | {p / t / 1e6:.0f} M | "
              f"{t / f['team_s']:.1f}x | {f['peak_rss_mb']:.0f} MB |")  # fmt: skip
    print(f"(bakeshop vs numpy: max relative difference {f['max_rel_diff_vs_numpy']:.1e})")
    v = _run("voxelise", args)
    print(f"\nvoxelisation, sphere (20480 faces), {v['cells']} cells, 4x4(x4) samples per cell")
    print("| implementation | time | ratio | volume error | peak RSS |")
    print("|---|---|---|---|---|")
    print(f"| bakeshop (vertical rays, exact along y) | {v['ours_s'] * 1e3:.1f} ms | 1.0x | "
          f"{v['ours_volume_err']:+.1e} | {v['peak_rss_mb']:.0f} MB |")  # fmt: skip
    t = v["trimesh_contains_s"]
    print(f"| trimesh contains, {v['samples']} samples (timed on 512) | {t:.0f} s | "
          f"{t / v['ours_s']:.0f}x | {v['trimesh_volume_err']:+.1e} | |")  # fmt: skip
    m = _run("mujoco", args)
    n = m["bodies"]
    print(f"\nstepping {n} floating boxes (512 points each), 60 Hz, forces every step")
    print("| engine | time per step | steps/s | peak RSS |")
    print("|---|---|---|---|")
    for label, key in (("MuJoCo + bakeshop buoyancy", "mujoco_step_s"),
                       ("MuJoCo alone (no buoyancy, free fall)", "mujoco_bare_step_s"),
                       ("built-in integrator + bakeshop buoyancy", "builtin_step_s")):  # fmt: skip
        t = m[key]
        print(f"| {label} | {t * 1e3:.2f} ms | {1 / t:.0f} | {m['peak_rss_mb']:.0f} MB |")


if __name__ == "__main__":
    main()
