"""Whole process against whole process: the commands a user types, bakeshop and its peers, in
the same run, alternated.

Every figure is a fresh process from start to exit (start-up, decoding the input, the work,
encoding the outputs), timed by wall clock and by CPU time (user + system, every thread:
steadier than wall time when other work shares the cores), with its peak resident memory and the
load average at the start and end of each job. Peers (see ``peers.py``): Filament's
``cmgen`` on PATH (Debian: ``apt-get install libfilament-tools``) and cmft when ``CMFT`` names
its binary. A peer that is absent is reported as not measured.

Jobs (input: Poly Haven's Quarry 01, 1024x512, upsampled bilinearly to 4096x2048 for "4k" and
area-averaged to 64x32 for "64"):

- ``start``: ``bakeshop --version``, ``--help``, a command's ``--help``, ``info`` of the 1k
  probe (.hdr and .exr);
- ``dim-1k``, ``dim-4k``: diffuse irradiance. bakeshop ``irradiance`` (``auto``: exact to the
  bound of docs/irradiance.md, a 360x180 latlong DIM); cmgen ``--sh=3 --sh-irradiance`` (9 SH
  coefficients, approximate); cmft ``--filter irradiance`` (an order-5 SH, 25 coefficients,
  of the whole probe as a cube, evaluated on 6x90^2 and written as a 360x180 latlong: the size
  of bakeshop's DIM). From the 1k probe, each DIM's error against bakeshop's ``exact`` one too
  (fidelity);
- ``dims-12mp``: the same on the team's probe size, 5020x2510 (12.6 MP), with bakeshop's
  ``dims`` (the sun found and painted out, the sun DIM and the shadow DIM, four files) beside
  its single ``irradiance``;
- ``ggx-4k``: a 6x256 cube mip chain of 9 levels. bakeshop ``prefilter`` (GGX); cmgen
  ``--ibl-ld`` (GGX, importance sampled); cmft ``--filter radiance`` with its source resized
  to 6x256^2 first, the issue's setting (cmft has Phong and Blinn lobes, not GGX: ``phongbrdf``,
  gloss 10 x + 1);
- ``faces-4k``: the latlong as six 1024x1024 faces. bakeshop ``remap --to faces``; cmgen
  ``--extract``; cmft ``--filter none`` (its faces against bakeshop's, fidelity: cmft reads a
  latlong mirrored, +Z forward).
- ``area-4k``: the same faces through the area filter (``--filter area``: an energy-preserving
  average; neither peer has one), with an empty plan cache and a filled one (a source this
  large is supersampled with no matrix, so both should cost the same; docs/BENCHMARKS.md
  times the sizes that build a matrix);
- ``dims-64``, ``faces-64``: the same commands on a 64x32 probe (six 16^2 faces), whose work
  is nothing: what each command costs before its work (start-up, loading its kernels).

bakeshop runs twice per job where it builds a geometry plan: "cold" with an empty plan cache (a
new cache directory per run) and warm (the user cache directory of a previous run: a second
run at the same sizes). The kernels are compiled at install, so a first run after install
compiles nothing: cold is cold for the plan cache only.

Usage: ``python benchmarks/bench_commands.py [--repeats N] [JOB ...]`` (default: every job,
N = 3 for ``start``, the 1k and the 64x32 jobs, 1 for the larger ones; several minutes on 2 cores).
``CMFT=/path/to/cmftRelease`` adds cmft.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import peers

ROOT = Path(__file__).resolve().parents[1]
BAKESHOP = str(ROOT / ".venv" / "bin" / "bakeshop")
SOURCE = ROOT / "tests" / "data" / "quarry_01_1k.hdr"
JOBS = ["start", "dim-1k", "dim-4k", "dims-12mp", "ggx-4k", "faces-4k", "area-4k", "dims-64",
        "faces-64"]  # fmt: skip
#: input name -> (width, height).
SIZES = {"1k": (1024, 512), "4k": (4096, 2048), "12mp": (5020, 2510), "64": (64, 32)}
#: input name -> the face edge of the ``faces`` job (a quarter of the latlong's width).
FACES = {"4k": 1024, "64": 16}
#: jobs repeated 3 times by default (the short ones).
SHORT = ("start", "dim-1k", "dims-64", "faces-64")
#: jobs without a peer (neither has an area filter): a run of these alone measures no peer.
PEERLESS = ("start", "area-4k")
THREADS = 2  # cmft's CPU threads: the machine's cores


def prepare(work: Path) -> None:
    """The 1k probe as .hdr and .exr, and the larger ones as .hdr (bilinear upsampling)."""
    import cv2

    from bakeshop.io import read_image, write_image

    probe = read_image(SOURCE)
    write_image(work / "probe_1k.hdr", probe)
    write_image(work / "probe_1k.exr", probe)
    for name, size in SIZES.items():
        if name != "1k":
            how = cv2.INTER_AREA if size[0] < 1024 else cv2.INTER_LINEAR
            big = cv2.resize(probe, size, interpolation=how)
            write_image(work / f"probe_{name}.hdr", np.maximum(big, 0))


def cmft(run: peers.Peers, source: Path, out: Path, *options: str) -> list[str]:
    return [
        run.path("cmft"),
        "--input",
        str(source),
        *options,
        "--useOpenCL",
        "false",
        "--numCpuProcessingThreads",
        str(THREADS),
        "--outputNum",
        "1",
        "--output0",
        str(out),
    ]


def contenders(job: str, work: Path, run: peers.Peers) -> dict[str, list[str] | tuple]:
    """Name -> command line (or ``("cold", command)``: run with an empty plan cache)."""
    if job == "start":
        return {
            "bakeshop --version": [BAKESHOP, "--version"],
            "bakeshop --help": [BAKESHOP, "--help"],
            "bakeshop irradiance --help": [BAKESHOP, "irradiance", "--help"],
            "bakeshop info (1k .hdr)": [BAKESHOP, "info", str(work / "probe_1k.hdr")],
            "bakeshop info (1k .exr)": [BAKESHOP, "info", str(work / "probe_1k.exr")],
        }
    size = job.split("-")[1]
    src = work / f"probe_{size}.hdr"
    out = work / f"out_{job}"
    out.mkdir(exist_ok=True)
    found: dict = {}
    if job.startswith("dims"):
        found["bakeshop dims (sun + shadow DIMs)"] = [BAKESHOP, "-q", "dims", str(src), "-o",
                                                      str(out / "dims")]  # fmt: skip
    if job.startswith("dim"):
        found["bakeshop irradiance"] = [
            BAKESHOP,
            "-q",
            "irradiance",
            str(src),
            str(out / "dim.pfm"),
        ]
        if run.present("cmgen"):
            found["cmgen --sh=3 --sh-irradiance"] = [
                run.path("cmgen"), "-q", "--sh=3", "--sh-irradiance",
                f"--sh-output={out / 'sh.txt'}", str(src),
            ]  # fmt: skip
        if run.present("cmft"):
            # the whole probe as its cube (faces of height / 2), an order-5 SH of it evaluated
            # on 6x90^2 and written as a 360x180 latlong: the size of bakeshop's DIM
            found["cmft irradiance (SH order 5)"] = cmft(
                run, src, out / "cmft_irr", "--filter", "irradiance", "--srcFaceSize", "0",
                "--dstFaceSize", "90", "--output0params", "hdr,rgbe,latlong",
            )  # fmt: skip
    elif job.startswith("ggx"):
        cmd = [BAKESHOP, "-q", "prefilter", str(src), str(out / "ggx.dds"), "--size", "256",
               "--mips", "9"]  # fmt: skip
        found["bakeshop prefilter (plan cache cold)"] = ("cold", cmd)
        found["bakeshop prefilter"] = cmd
        if run.present("cmgen"):
            found["cmgen --ibl-ld (GGX)"] = [
                run.path("cmgen"), "-q", "--format=hdr", "--size=256",
                f"--ibl-ld={out / 'cmgen'}", str(src),
            ]  # fmt: skip
        if run.present("cmft"):
            found["cmft radiance (Phong, src 256)"] = cmft(
                run, src, out / "cmft_rad", "--filter", "radiance", "--srcFaceSize", "256",
                "--dstFaceSize", "256", "--excludeBase", "false", "--mipCount", "9",
                "--glossScale", "10", "--glossBias", "1", "--lightingModel", "phongbrdf",
                "--edgeFixup", "none", "--output0params", "dds,rgba16f,cubemap",
            )  # fmt: skip
    elif job.startswith("area"):
        cmd = [BAKESHOP, "-q", "remap", str(src), str(out / "f_{face}.hdr"), "--to", "faces",
               "--size", str(FACES[size]), "--filter", "area"]  # fmt: skip
        found["bakeshop remap --to faces --filter area (plan cache cold)"] = ("cold", cmd)
        found["bakeshop remap --to faces --filter area"] = cmd
    else:
        cmd = [BAKESHOP, "-q", "remap", str(src), str(out / "f_{face}.hdr"), "--to", "faces",
               "--size", str(FACES[size])]  # fmt: skip
        found["bakeshop remap --to faces (plan cache cold)"] = ("cold", cmd)
        found["bakeshop remap --to faces"] = cmd
        if run.present("cmgen"):
            found["cmgen --extract"] = [
                run.path("cmgen"), "-q", "--format=hdr", f"--size={FACES[size]}",
                f"--extract={out / 'cmgen'}", str(src),
            ]  # fmt: skip
        if run.present("cmft"):
            found["cmft (filter none)"] = cmft(
                run, src, out / "cmft_faces", "--filter", "none", "--dstFaceSize", str(FACES[size]),
                "--output0params", "hdr,rgbe,facelist",
            )  # fmt: skip
    return found


#: real SH basis to L = 2 with the Condon-Shortley phase, in cmgen's order (L00, L1-1, L10, L11,
#: L2-2, L2-1, L20, L21, L22), at unit directions (x, y, z).
def _sh_basis(x, y, z):
    return np.stack(
        [0.282095 + 0 * x, -0.488603 * y, 0.488603 * z, -0.488603 * x, 1.092548 * x * y,
         -1.092548 * y * z, 0.315392 * (3 * z * z - 1), -1.092548 * x * z,
         0.546274 * (x * x - y * y)], axis=-1,
    )  # fmt: skip


#: the 48 axis permutations and signs: frame[i] maps a direction of bakeshop's frame to a peer's.
FRAMES = [np.eye(3)[list(p)] * np.array(s)[:, None] for p in itertools.permutations(range(3))
          for s in itertools.product((1, -1), repeat=3)]  # fmt: skip
AXES = "xyz"


def _frame_name(m: np.ndarray) -> str:
    """``"x, y, -z"``: which of bakeshop's axes each of a peer's axes is."""
    return ", ".join(("-" if m[i].sum() < 0 else "") + AXES[int(np.argmax(np.abs(m[i])))]
                     for i in range(3))  # fmt: skip


def _fit_frame(lookup, dirs, ref, weights):
    """The signed axis permutation ``M`` for which the peer's values at ``M d`` (``lookup``)
    best match ``ref`` at bakeshop's directions ``d``: (relative RMS, the values, ``M``, the
    next best RMS)."""
    fits = []
    for m in FRAMES:
        got = lookup(dirs @ m.T)
        rms = np.sqrt(np.sum(weights * (got - ref) ** 2) / np.sum(weights * ref**2))
        fits.append((float(rms), got, m))
    fits.sort(key=lambda f: f[0])
    return (*fits[0], fits[1][0])


def fidelity(job: str, work: Path, ran: list[str]) -> dict[str, str]:
    """Errors of each contender's output against a reference, in the frame that fits it best of
    the 48 axis permutations and signs (a peer's frame may differ from bakeshop's, +Y up, -Z
    forward).

    ``dim-1k``: each DIM against bakeshop's ``exact`` one (the brute-force sum to rounding,
    tests/light), on the 1k probe only (``exact`` from larger probes takes minutes). cmgen's 9
    coefficients are irradiance E (not E/pi) in a frame turned 180 degrees about +Y from
    bakeshop's (its x and z negated: 15 % RMS, the next 24 %). cmft's 360x180 latlong is E/pi
    in bakeshop's frame (the identity fits best).

    ``faces-4k``: cmft's six faces (read as an OpenGL cube) against bakeshop's, both sampled
    at a 512x256 latlong's directions and compared tone-mapped (``v / (1 + v)``, so that the
    sun's few texels do not decide the fit): cmft reads a latlong mirrored, +Z forward (its z
    is bakeshop's -z).

    ``ran``: the contenders that ran; a peer that ran without writing its output is an error."""
    if job not in ("dim-1k", "faces-4k"):
        return {}
    from bakeshop.io import read_image
    from bakeshop.sphere import layout, sample

    out = work / f"out_{job}"
    lay = layout("latlong")
    if job == "faces-4k":
        faces = out / "cmft_faces_{}.hdr"
        if "cmft (filter none)" not in ran:
            return {}
        names = ["posx", "negx", "posy", "negy", "posz", "negz"]
        ours = np.stack([read_image(str(out / f"f_{n}.hdr")) for n in names])
        theirs = np.stack([read_image(str(faces).format(n)) for n in names])
        dirs = lay.directions((256, 512))[0]
        weights = lay.solid_angles((256, 512))[..., None]
        ref = sample(ours, "cube", dirs).astype(np.float64)
        ref /= 1 + ref

        def look(d):
            v = sample(theirs, "cube", d).astype(np.float64)
            return v / (1 + v)

        rms, _, m, second = _fit_frame(look, dirs, ref, weights)
        return {"cmft (filter none)": f"{rms:.1e} RMS tone-mapped off bakeshop's faces, in "
                f"the frame ({_frame_name(m)}) (next best {second:.1e})"}  # fmt: skip

    import re

    from bakeshop.light import irradiance

    ours = read_image(out / "dim.pfm").astype(np.float64)
    h, w = ours.shape[:2]
    exact = irradiance(read_image(work / "probe_1k.hdr"), "latlong", size=(w, h), method="exact")
    exact = exact.astype(np.float64)
    weights = lay.solid_angles((h, w))[..., None]
    dirs = lay.directions((h, w))[0]

    def errors(got):
        rms = np.sqrt(np.sum(weights * (got - exact) ** 2) / np.sum(weights * exact**2))
        return f"{rms:.1e} RMS, {np.max(np.abs(got - exact) / exact):.1e} max"

    found = {"bakeshop irradiance": errors(ours)}
    sh = out / "sh.txt"
    if sh.exists():
        lines = [ln for ln in sh.read_text().splitlines() if "(" in ln]
        coef = np.array([[float(v) for v in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", ln)[:3]]
                         for ln in lines])  # fmt: skip
        basis = _sh_basis(-dirs[..., 0], dirs[..., 1], -dirs[..., 2])
        found["cmgen --sh=3 --sh-irradiance"] = errors(np.maximum(basis @ coef, 0) / np.pi)
    cmft_dim = out / "cmft_irr.hdr"
    if "cmft irradiance (SH order 5)" in ran:
        theirs = read_image(cmft_dim).astype(np.float64)
        _, got, m, second = _fit_frame(lambda d: sample(theirs, "latlong", d), dirs, exact,
                                       weights)  # fmt: skip
        found["cmft irradiance (SH order 5)"] = (
            f"{errors(got)} (frame {_frame_name(m)}; next best {second:.1e} RMS)"
        )
    return found


def timer(command, cache: Path):
    """A contender for :func:`peers.alternate`: the command in a fresh process."""
    if isinstance(command, tuple):  # cold: a new, empty plan cache for each run
        _, cmd = command

        def cold():
            fresh = Path(tempfile.mkdtemp(dir=cache.parent))
            try:
                return peers.run_process(cmd, env=dict(os.environ, BAKESHOP_CACHE_DIR=str(fresh)))
            finally:
                shutil.rmtree(fresh, ignore_errors=True)

        return cold
    env = dict(os.environ, BAKESHOP_CACHE_DIR=str(cache))
    env.pop("BAKESHOP_CACHE_BYTES", None)
    return lambda: peers.run_process(command, env=env)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("jobs", nargs="*", metavar="JOB", help=", ".join(JOBS))
    parser.add_argument("--repeats", type=int, default=None)
    args = parser.parse_args()
    jobs = args.jobs or JOBS
    if set(jobs) - set(JOBS):
        parser.error(f"unknown jobs {sorted(set(jobs) - set(JOBS))}; jobs: {', '.join(JOBS)}")
    run = peers.Peers(["cmgen", "cmft"] if set(jobs) - set(PEERLESS) else [])
    print(f"machine: {peers.machine()}; input {SOURCE.name}")
    results: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        cache = work / "plan-cache"
        prepare(work)
        for job in jobs:
            repeats = args.repeats or (3 if job in SHORT else 1)
            found = contenders(job, work, run)
            # a warm-up of each bakeshop command fills the plan cache (and the page cache), untimed
            for name, command in found.items():
                if name.startswith("bakeshop") and not isinstance(command, tuple):
                    timer(command, cache)()
            load = os.getloadavg()[0]
            timed = peers.alternate({n: timer(c, cache) for n, c in found.items()}, repeats)
            load = f"load average {load:.1f} at its start, {os.getloadavg()[0]:.1f} at its end"
            for name in timed:
                for peer in ("cmgen", "cmft"):
                    if name.startswith(peer):
                        run.measured(peer, job)
            results[job] = timed
            errors = fidelity(job, work, list(timed))
            print(f"\n{job} ({repeats} run{'s' if repeats > 1 else ''} each, alternated; {load})")
            print("| command | wall s | CPU s | peak MB | wall / ours | CPU / ours | error |")
            print("|---|---|---|---|---|---|---|")
            # against bakeshop's warm run (its plan cache filled by an earlier run)
            ours = [r for n, r in timed.items() if n.startswith("bakeshop") and "cold" not in n][-1]
            for name, r in timed.items():
                ratios = (
                    "- | -"
                    if job == "start"
                    else f"{r['wall'] / ours['wall']:.2f} | {r['cpu'] / ours['cpu']:.2f}"
                )
                times = (
                    f"{peers.spread(r)} | {peers.spread(r, 'cpu')} | {peers.spread(r, 'mem', 0)}"
                )
                print(f"| {name} | {times} | {ratios} | {errors.get(name, '-')} |")
    print("\n" + json.dumps(results))
    run.finish()


if __name__ == "__main__":
    sys.exit(main())
