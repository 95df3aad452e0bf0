"""Time and memory of merging brackets and unwrapping mirror balls, against OpenCV in one run.

Jobs (each in a fresh subprocess, after one small warm-up that loads the compiled kernels):

- ``merge-6mp``: 7 brackets of 3000x2000, 8-bit, 2 stops apart (1/4000 s to 1 s);
- ``merge-24mp``: 9 brackets of 6000x4000, 8-bit, 1.5 stops apart.

For each, bakeshop's ``recover_response`` (Debevec-Malik, stratified samples) plus
``merge_stack``, against OpenCV's ``CalibrateDebevec`` plus ``MergeDebevec`` (its defaults: 70
random samples, lambda 10) on the same frames, with the quality of both against the known
radiance (multi-exposure PSNR and log2 RMSE over the pixels some frame saw, after one global
scale). The frames are synthetic: the embedded default probe resized to the frame, shot by the
test camera of ``tests/photo/synthetic.py`` (gamma 2.2 with a shoulder, 0.5 code of noise).

- ``unwrap-6mp``: a 3000x2000 HDR photo of a mirror ball (radius 900 px) found and unwrapped
  to a 2048x1024 latlong; ``two-views``: two such photos merged. The peer is OpenCV's
  ``remap`` given the same maps (what a hand-written unwrap costs once its maps exist).

"cpu" is the process's CPU time over the job (all threads); peak is the resident high-water
mark (``VmHWM``, reset before the job) minus the resident size before it: the memory the job
added on top of its loaded frames.

Run: ``.venv/bin/python benchmarks/bench_photo.py`` (several minutes; ~8 GB at its peak).
"""

from __future__ import annotations

import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import peers

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

JOBS = {
    "merge-6mp": {"size": (3000, 2000), "times": (1 / 4000) * 4.0 ** np.arange(7)},
    "merge-24mp": {"size": (6000, 4000), "times": (1 / 4000) * 2.0 ** (1.5 * np.arange(9))},
}


def memory(field: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    return 0


def reset_peak() -> None:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def make_frames(job: str, workdir: Path) -> None:
    import cv2

    from tests.photo import synthetic

    w, h = JOBS[job]["size"]
    truth = cv2.resize(synthetic.default_probe(), (w, h), interpolation=cv2.INTER_LINEAR)
    times = JOBS[job]["times"]
    gain = 0.18 * 60 / 0.5
    codes = np.empty((len(times), h, w, 3), np.uint8)
    rng = np.random.default_rng(0)
    for j, t in enumerate(times):
        for r0 in range(0, h, 500):
            x = truth[r0 : r0 + 500] * np.float32(gain * t)
            z = synthetic.camera_curve(x) + rng.normal(0, 0.5 / 255, x.shape)
            codes[j, r0 : r0 + 500] = np.clip(np.rint(z * 255), 0, 255)
    np.save(workdir / f"{job}.npy", codes)
    np.save(workdir / f"{job}-truth.npy", truth * np.float32(gain))


def make_balls(workdir: Path) -> None:
    from bakeshop.photo.mirrorball import ball_directions
    from tests.photo import synthetic

    h, w, r = 2000, 3000, 900.0
    for k, (cx, cy) in enumerate([(1500.3, 1000.6), (1480.7, 1020.2)]):
        ys, xs = np.mgrid[0:h, 0:w].astype(np.float32) + 0.5
        a, b = (xs - cx) / r, (cy - ys) / r
        inside = a * a + b * b < 1
        d = ball_directions(np.where(inside, a, 0), np.where(inside, b, 0), "physical")
        photo = np.where(inside[..., None], synthetic.smooth_probe(d), 0.3).astype(np.float32)
        np.save(workdir / f"ball{k}.npy", photo)


def child(job: str, tool: str, workdir: Path) -> dict:
    """Run one job in this process and return its figures."""
    if job.startswith("merge"):
        codes = np.load(workdir / f"{job}.npy")
        times = JOBS[job]["times"]
        if tool == "opencv":
            import cv2

            frames = [codes[j] for j in range(len(codes))]  # views: no copy (OpenCV reads BGR)
            t32 = times.astype(np.float32)
        else:
            from bakeshop.photo import make_stack, merge_stack, recover_response
    else:
        photos = [np.load(workdir / f"ball{k}.npy") for k in range(2 if job == "two-views" else 1)]
        if tool == "opencv":
            import cv2

            from bakeshop.photo import find_ball
            from bakeshop.photo.mirrorball import ball_coordinates, layout_directions
        else:
            from bakeshop.photo import best_yaw, find_ball, merge_views, unwrap
    before = memory("VmRSS")
    reset_peak()
    cpu0 = time.process_time()
    t0 = time.perf_counter()
    if job.startswith("merge"):
        if tool == "opencv":
            curve = cv2.createCalibrateDebevec().process(frames, t32)
            result = cv2.createMergeDebevec().process(frames, t32, curve)
        else:
            stack = make_stack(codes, times)
            response = recover_response(stack.codes, stack.exposures)
            result = merge_stack(stack, response).radiance
    else:
        if tool == "opencv":
            circle = find_ball(photos[0])
            dirs, _ = layout_directions("latlong", 1024)
            ab = ball_coordinates(dirs, "hdrshop").astype(np.float32)
            mx = circle.x + ab[..., 0] * np.float32(circle.radius) - 0.5
            my = circle.y - ab[..., 1] * np.float32(circle.radius) - 0.5
            result = cv2.remap(photos[0], mx, my, cv2.INTER_LINEAR)
        elif job == "two-views":
            circles = [find_ball(p) for p in photos]
            yaw, _, _ = best_yaw(photos, circles)
            result, _ = merge_views(photos, circles, yaws_deg=[0, yaw], size=1024)
        else:
            result = unwrap(photos[0], find_ball(photos[0]), size=1024)
    seconds = time.perf_counter() - t0
    cpu = time.process_time() - cpu0
    peak = memory("VmHWM") - before
    out = {"job": job, "tool": tool, "seconds": seconds, "cpu": cpu, "peak": peak}
    if job.startswith("merge"):
        from bakeshop.photo import log2_rmse, multi_exposure_psnr, relative_scale

        truth = np.load(workdir / f"{job}-truth.npy")
        r = result  # OpenCV was given the frames in our channel order: no flip
        step = 4  # quality on every 4th row and column (the figures change in the 3rd digit)
        r, t = r[::step, ::step], truth[::step, ::step]
        seen = (codes[:, ::step, ::step] < 250).all(-1).any(0)
        r = r / relative_scale(r, t, seen)
        out["mpsnr"] = multi_exposure_psnr(r, t, mask=seen)
        out["log2"] = log2_rmse(r, t, mask=seen)
    return out


def warm_up() -> None:
    from bakeshop.photo import find_ball, make_stack, merge_stack, recover_response, unwrap

    rng = np.random.default_rng(0)
    codes = rng.integers(0, 256, (3, 64, 64, 3), dtype=np.uint8)
    stack = make_stack(codes, [1.0, 2.0, 4.0])
    merge_stack(stack, recover_response(stack.codes, stack.exposures, samples=64))
    ys, xs = np.mgrid[0:64, 0:64]
    photo = np.where(((xs - 32) ** 2 + (ys - 30) ** 2 < 400)[..., None], 1.0, 0.2)
    unwrap(photo.astype(np.float32), find_ball(photo.astype(np.float32)), size=16)


def run(job: str, tool: str, workdir: Path) -> dict:
    code = (
        f"import sys, json; from pathlib import Path; sys.path.insert(0, {str(ROOT)!r});"
        "import benchmarks.bench_photo as b; b.warm_up();"
        f"print(json.dumps(b.child({job!r}, {tool!r}, Path({str(workdir)!r}))))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    if done.returncode:
        raise RuntimeError(done.stderr)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    found = peers.Peers(["opencv"])
    if found.present("opencv"):
        import cv2

        opencv = f"OpenCV {cv2.__version__}"
    else:
        opencv = "OpenCV absent"
    tools = ("bakeshop", "opencv") if found.present("opencv") else ("bakeshop",)
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"{os.sysconf('SC_PAGE_SIZE') * os.sysconf('SC_PHYS_PAGES') / 2**30:.0f} GiB; "
        f"{opencv}, numpy {np.__version__}; "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"
    )
    with tempfile.TemporaryDirectory(prefix="bench_photo_") as tmp:
        workdir = Path(tmp)
        rows = []
        for job in JOBS:
            make_frames(job, workdir)
            w, h = JOBS[job]["size"]
            n = len(JOBS[job]["times"])
            frames_mb = n * w * h * 3 / 2**20
            for tool in tools:
                rows.append(run(job, tool, workdir) | {"frames_mb": frames_mb})
            (workdir / f"{job}.npy").unlink()
        make_balls(workdir)
        for job in ("unwrap-6mp", "two-views"):
            for tool in tools if job == "unwrap-6mp" else ("bakeshop",):
                rows.append(run(job, tool, workdir) | {"frames_mb": 0.0})
    print(
        f"{'job':<11} {'tool':<9} {'seconds':>8} {'cpu':>7} {'x bakeshop':>10} "
        f"{'peak MiB':>9} {'frames MiB':>10} {'mPSNR dB':>9} {'log2 RMSE':>9}"
    )
    base = {}
    for r in rows:
        if r["tool"] == "opencv":
            found.measured("opencv", r["job"])
        base.setdefault(r["job"], r["seconds"])
        quality = f"{r['mpsnr']:>9.2f} {r['log2']:>9.4f}" if "mpsnr" in r else f"{'':>9} {'':>9}"
        print(
            f"{r['job']:<11} {r['tool']:<9} {r['seconds']:>8.2f} {r['cpu']:>7.2f} "
            f"{r['seconds'] / base[r['job']]:>10.2f} {r['peak'] / 2**20:>9.0f} "
            f"{r['frames_mb']:>10.0f} {quality}"
        )
    parent = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
    print(f"max RSS of the parent: {parent} MiB")
    found.finish()


if __name__ == "__main__":
    main()
