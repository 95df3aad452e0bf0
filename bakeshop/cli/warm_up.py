"""``bakeshop warm-up``: every command's numba kernels compiled into their cache, once.

numba compiles a kernel on its first call and keeps the machine code on disk (``cache=True``),
so a command's first run after installing costs seconds to a minute more than later runs. The
warm-up runs a tour of every command on small inputs made from the embedded default probe
(:data:`TOUR`), as separate processes, several at once, so that the compilation is paid once,
at install time. The tour covers every cached kernel of the package
(tests/cli/test_warm_up.py checks it against the kernels found in the modules).
"""

from __future__ import annotations

import importlib.util
import os
import shlex
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import click

from bakeshop import progress
from bakeshop.cli._numbers import Integer
from bakeshop.errors import BakeshopError

#: a mesh with texture coordinates for ``normals transfer``: a unit square, two triangles.
QUAD_OBJ = """v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1
f 1/1/1 3/3/1 4/4/1
"""


@dataclass(frozen=True)
class Job:
    """Command lines (without ``bakeshop``; ``{probe}`` stands for the default probe's path) run
    one after another in the tour's scratch folder, a later one reading what an earlier one
    wrote; ``cpu`` is each one's CPU seconds measured with nothing compiled (the weights of the
    progress estimate); ``needs`` names the modules of the optional ``extra`` they use."""

    name: str
    commands: tuple[str, ...]
    cpu: tuple[float, ...]
    needs: tuple[str, ...] = ()
    extra: str = ""

    def argv(self, k: int, probe: str) -> list[str]:
        """Command ``k`` as arguments."""
        return shlex.split(self.commands[k].format(probe=shlex.quote(probe)))


#: what the warm-up runs, the longest jobs first: every command, and the options that select
#: kernels of their own (layouts, filters, methods, formats), on inputs made from the default
#: probe (1024x512) and small outputs. The CPU seconds were measured one command at a time with
#: an empty NUMBA_CACHE_DIR (672 s in all, on a machine at a load of 9).
TOUR = (
    Job("bake-probe", ("bake-probe {probe} -o bake",), (213.7,)),
    Job(
        "float",
        (
            "float --shape peep --density 300 --fps 10",
            "float --shape box --density 500 --waves 0.2:8:30",
        ),
        (27.0, 2.5),
    ),
    Job(
        "light",
        (
            "irradiance {probe} dim_exact.hdr --method exact --size 32x16",
            "irradiance {probe} dim_sh.exr --method sh --sh-json sh.json --shader sh.glsl",
            "irradiance {probe} dim_sh4.exr --method sh --order 4",
            "irradiance {probe} dim.png --to cross-vertical --size 16",
            "sun {probe}",
            "dims {probe} -o dims",
            "dims {probe} -o dims_chunked --memory 64M",
            "prefilter {probe} phong.dds --brdf phong --exponent 64 --size 32",
            "prefilter {probe} ggx_{{face}}_{{mip}}.png --size 16 --mips 3",
            "dfg dfg.exr --size 16 --samples 64",
        ),
        (1.8, 29.8, 24.7, 1.8, 2.4, 3.5, 14.8, 3.0, 2.8, 1.4),
    ),
    Job(
        "codecs",
        (
            "convert {probe} probe.exr",
            "convert {probe} probe.pfm",
            "convert {probe} probe.tga",
            "convert {probe} rle.tga -O rle=true",
            "convert probe.exr probe16.png --bits 16",
            "info probe.exr probe.pfm probe.tga rle.tga probe16.png",
            "resize {probe} small.hdr --size 256x128",
            "resize probe16.png small.png --size 300x150",
            "tonemap {probe} aces.png --operator aces",
            "tonemap {probe} reinhard.jpg --operator reinhard --white 8",
        ),
        (1.1, 1.1, 1.1, 8.9, 3.1, 10.4, 5.9, 3.7, 1.5, 1.1),
    ),
    Job(
        "panoramas",
        (
            "remap {probe} ball.hdr --to mirrorball --size 256",
            "remap ball.hdr angular.exr --from mirrorball --to angular",
            "remap {probe} cross.exr --to cross-vertical --size 32 --filter area",
            "remap cross.exr back.hdr --from cross-vertical --to latlong --filter area",
            "remap {probe} octahedral.exr --to octahedral --size 64 --filter area",
            "remap {probe} paraboloid.pfm --to dual-paraboloid --size 32",
            "remap {probe} env_cube.exr --to openexr-cube --size 16",
            "unwrap ball.hdr -o unwrapped.exr --to latlong --size 128 --circle 127.5,127.5,128",
            # sizes that select kernels of their own: a .hdr over 1 MP, EXR's half floats of a
            # large image, the area filter's supersampling (over 4 M texels), out of core
            "remap {probe} large.hdr --to latlong --size 4096x2048",
            "convert large.hdr large.exr",
            "info large.exr",
            "remap large.hdr large_{{face}}.hdr --to faces --size 32 --filter area",
            "remap large.exr large_octahedral.pfm --to octahedral --size 64 --filter area",
            "remap {probe} chunked.exr --to cross-vertical --size 64 --memory 64M",
            "remap {probe} chunked.hdr --to latlong --size 512x256 --memory 64M",
        ),
        (2.9, 1.2, 4.3, 1.9, 6.1, 2.3, 2.7, 1.4, 2.2, 10.1, 1.0, 23.6, 23.1, 7.6, 2.7),
    ),
    Job(
        "water and normals",
        (
            "water ocean ocean --size 16 --resolution 32 --period 2",
            "water ocean choppy --size 16 --resolution 32 --period 2 --choppiness 0.8"
            " --outputs normal,height,foam --layout atlas",
            "water ocean cascades --size 16 --resolution 32 --period 2 --cascades 2",
            "water ocean gerstner --size 16 --resolution 32 --period 2 --method gerstner --waves 8",
            "water ripples wave --model wave --rain 4 --resolution 64 --frames 4",
            "water ripples ripples",
            "water murk murk --water-type IB",
            "fresnel {probe} fresnel.exr",
            "fresnel {probe} fresnel.png --ldr --dither --report",
            "fresnel {probe} fresnel_{{face}}.png --layout cube --size 16 --ldr",
            "normals combine ocean/ocean_normal_0000.png ocean/ocean_normal_0001.png combined.png"
            " --tile 2",
            "normals transfer quad.obj ocean/ocean_normal_0000.png triplanar.png --size 32"
            " --projection triplanar --macro combined.png",
            "normals transfer quad.obj ocean/ocean_normal_0000.png box.png --size 32"
            " --projection box",
            "normals combine ocean/ocean_normal_0000.png ocean/ocean_normal_0001.png masked.png"
            " --mask fresnel.png",
            "normals check combined.png",
            "normals convert combined.png combined_dx.png --from gl --to dx",
            "normals from-height fresnel.png from_height.png --strength 8",
        ),
        (8.9, 3.4, 2.3, 3.5, 3.8, 5.0, 2.2, 5.9, 6.0, 1.6, 8.1, 18.5, 2.2, 6.2, 0.8, 0.8, 1.5),
    ),
    Job(
        "photographs",
        (
            "tonemap {probe} bracket_0.png --operator none --exposure -4",
            "tonemap {probe} bracket_1.png --operator none --exposure 0",
            "tonemap {probe} bracket_2.png --operator none --exposure 4",
            "merge bracket_0.png bracket_1.png bracket_2.png --times 1/16,1,16 -o merged.exr"
            " --align --ghost 0.25",
        ),
        (1.1, 1.3, 1.4, 32.1),
    ),
    Job(
        "compress",
        (
            "compress {probe} probe_bc6h.dds --cube --size 32 --overflow clamp",
            "compress {probe} probe_signed.ktx2 --cube --size 16 --format bc6h-signed"
            " --overflow clamp",
            "compress {probe} env_{{mip}}_{{face}}.png --cube --size 16 --format rgbd --mips 1",
            "tonemap {probe} picture.png",
            "compress picture.png picture_bc7.dds",
            "water ocean normals --size 16 --resolution 32 --period 1",
            "compress normals/ocean_normal_0000.png normal_bc5.dds --normal",
            "bake-probe {probe} -o bake_bc --compress --cube-size 64 --specular-size 32 --mips 6",
        ),
        (14.6, 34.0, 1.4, 1.6, 18.6, 2.1, 7.3, 15.4),
        needs=("ispc_texcomp",),
        extra="compress",
    ),
)


#: seconds a child may go without using any CPU before it counts as hung. A busy machine slows
#: a child but never stops it (the scheduler gives every runnable process CPU), so there is no
#: limit on a command's wall-clock time: the install must not fail because the machine is busy.
HUNG_SECONDS = 120.0
#: seconds a stopped command is given to exit before it is killed: a child defers a signal
#: until the kernel it is compiling is done, up to ~20 s, and a second Ctrl-C must not be
#: needed (it would leave the scratch folder behind).
STOP_SECONDS = 2.0


def _available(job: Job) -> bool:
    return all(importlib.util.find_spec(m) is not None for m in job.needs)


def _start(job: Job, k: int, probe: str, work: Path) -> subprocess.Popen:
    """Command ``k`` of ``job`` as a child process in ``work``, its stderr kept in a file; the
    area filter's plans go to the scratch folder, not the user cache."""
    env = {**os.environ, "BAKESHOP_CACHE_DIR": str(work / "plan-cache")}
    argv = [sys.executable, "-m", "bakeshop.cli.main", "-q", *job.argv(k, probe)]
    with (work / f"{job.name}.log").open("wb") as log:
        return subprocess.Popen(argv, cwd=work, env=env, stdout=subprocess.DEVNULL, stderr=log)


def cpu_seconds(pid: int) -> float | None:
    """User and system CPU seconds of a running process (Linux's /proc); None where they cannot
    be read."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return None


@dataclass
class Watch:
    """A running command of the tour: its CPU seconds, and when they last grew."""

    process: subprocess.Popen
    job: Job
    k: int
    cpu: float = 0.0
    active: float = field(default_factory=time.monotonic)

    def sample(self, now: float) -> None:
        """Read the child's CPU time; where it cannot be read the child counts as working."""
        cpu = cpu_seconds(self.process.pid)
        if cpu is None or cpu > self.cpu:
            self.cpu, self.active = self.cpu if cpu is None else cpu, now

    def hung(self, now: float) -> bool:
        """True when the child has used no CPU for :data:`HUNG_SECONDS`."""
        return now - self.active > HUNG_SECONDS


class Estimate:
    """The tour's progress, in weights (CPU seconds measured with nothing compiled): a finished
    command counts its weight; a running one its CPU seconds so far, divided by the ratio of the
    finished commands' CPU seconds to their weights (a warm cache or a faster machine runs below
    the weights), and below its own weight. The remaining time is the elapsed time scaled by the
    remaining weight (:meth:`bakeshop.progress.Task.line`), so a busy machine's slowness counts
    as it is measured."""

    def __init__(self, total: float) -> None:
        self.total = total
        self.weight = 0.0  # of the finished commands
        self.cpu = 0.0  # their CPU seconds

    def finish(self, weight: float, cpu: float) -> None:
        """Count a finished command of ``weight`` that used ``cpu`` seconds."""
        self.weight += weight
        self.cpu += cpu

    def done(self, running: list[tuple[float, float]]) -> float:
        """Weight done, with the ``(weight, cpu seconds so far)`` of the running commands."""
        ratio = self.cpu / self.weight if self.weight > 0 and self.cpu > 0 else 1.0
        partial = sum(min(cpu / ratio, 0.9 * weight) for weight, cpu in running)
        return min(self.total, self.weight + partial)


#: progress units per weight (CPU second): the bar counts whole units.
UNITS = 10


def run_tour(jobs: int) -> tuple[list[Job], list[Job]]:
    """Run :data:`TOUR`, ``jobs`` processes at once: (the jobs run, those skipped for a missing
    extra). A signal or a failure stops the processes still running.

    Raises
    ------
    BakeshopError
        A command of the tour failed, or used no CPU for :data:`HUNG_SECONDS`: its error line.
    """
    from bakeshop.data import default_probe_path

    probe = str(default_probe_path())
    todo = [job for job in TOUR if _available(job)]
    waiting = list(todo)
    live: dict[Job, Watch] = {}
    estimate = Estimate(sum(sum(job.cpu) for job in todo))
    with (
        tempfile.TemporaryDirectory(prefix="bakeshop-warm-up-") as tmp,
        progress.task(
            "warm-up: compiling every command's kernels", round(UNITS * estimate.total)
        ) as task,
    ):
        work = Path(tmp)
        (work / "quad.obj").write_text(QUAD_OBJ)
        try:
            while waiting or live:
                while waiting and len(live) < jobs:
                    job = waiting.pop(0)
                    live[job] = Watch(_start(job, 0, probe, work), job, 0)
                time.sleep(0.05)
                now = time.monotonic()
                for job, watch in list(live.items()):
                    status = watch.process.poll()
                    if status is None:
                        watch.sample(now)
                        if not watch.hung(now):
                            continue
                    if status != 0:
                        log = work / f"{job.name}.log"
                        why = "failed: " + _reason(log, status) if status is not None else (
                            f"used no CPU for {HUNG_SECONDS:.0f} s: hung")  # fmt: skip
                        command = shlex.join(job.argv(watch.k, probe))
                        raise BakeshopError(f"warm-up: 'bakeshop {command}' {why}")
                    estimate.finish(job.cpu[watch.k], watch.cpu)
                    del live[job]
                    if watch.k + 1 < len(job.commands):
                        k = watch.k + 1
                        live[job] = Watch(_start(job, k, probe, work), job, k)
                running = [(w.job.cpu[w.k], w.cpu) for w in live.values()]
                task.advance(max(0, round(UNITS * estimate.done(running)) - task.completed))
        finally:
            _stop([watch.process for watch in live.values()])
    return todo, [job for job in TOUR if job not in todo]


def _reason(log: Path, status: int) -> str:
    """Why a child failed: its error line, or the signal that ended it."""
    lines = log.read_text(errors="replace").splitlines()
    if lines:
        return lines[-1].removeprefix("bakeshop: error: ")
    if status < 0:
        return f"killed by {signal.Signals(-status).name}"
    return f"exit status {status}"


def _stop(children: list[subprocess.Popen]) -> None:
    """Terminate the children, and kill those still running after :data:`STOP_SECONDS`."""
    for child in children:
        child.terminate()
    deadline = time.monotonic() + STOP_SECONDS
    for child in children:
        try:
            child.wait(max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait()


@click.command("warm-up", context_settings={"max_content_width": 100})
@click.option("--jobs", "-j", type=Integer(1, 256), default=None,
              help="Processes at once (default: the machine's cores).")  # fmt: skip
def warm_up(jobs: int | None) -> None:
    """Compile every command's numba kernels now, so that no command compiles on its first run.

    A kernel is compiled to machine code on its first call and kept on disk beside its module
    (or in NUMBA_CACHE_DIR): without this, a command's first run after installing or upgrading
    bakeshop costs seconds to a minute more than later runs. The warm-up runs every command
    on small inputs made from the embedded default probe, in a scratch folder it removes,
    several processes at once: about 5 minutes of CPU once, 3 minutes of waiting on two cores
    (a second warm-up only loads the kernels: a minute). `make demo` runs it while installing.
    Commands of an optional extra that is not installed (compress) are skipped and named.

    \b
    Example:
      bakeshop warm-up
      NUMBA_CACHE_DIR=~/.cache/bakeshop-kernels bakeshop warm-up --jobs 4
    """
    started = time.perf_counter()
    ran, skipped = run_tour(jobs or os.cpu_count() or 1)
    commands = sum(len(job.commands) for job in ran)
    line = f"warmed up: {commands} commands, {time.perf_counter() - started:.0f} s"
    skips = [f"{job.name} (needs bakeshop[{job.extra}])" for job in skipped]
    click.echo(line + (f"; skipped {', '.join(skips)}" if skips else ""))


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(warm_up)
