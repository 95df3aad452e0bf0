"""``bakeshop warm-up``: after it, every cached numba kernel of the package is on disk, and a
command's run on another probe compiles nothing; a failure, a missing extra and a signal are
answered as every command answers them.

The kernels are found by importing every module of the package (not from the tour), and
"compiled" is read from numba's cache files in an empty ``NUMBA_CACHE_DIR``.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from bakeshop.cli import warm_up
from bakeshop.cli.main import main
from tests.cli.test_process import EXIT_SECONDS, one_error_line

DATA = Path(__file__).parents[1] / "data"

#: cached kernels no command calls, with the library function that does: the warm-up runs
#: commands, so these compile on the first such library call.
LIBRARY_ONLY = {
    "bakeshop.light.dfg._dfg_kernel": "dfg_terms at arbitrary points (the command's table: "
    "_dfg_grid)",
    "bakeshop.normals.transfer._world_to_tangent": "world_to_tangent",
    "bakeshop.water._kernels._free_spectra": "ocean_frames at free times (commands loop)",
    "bakeshop.water.cascades._sample_add": "sample_periodic",
    "bakeshop.sphere._gather.gather_plan": "a second remap of the same sizes in one process",
    "bakeshop.sphere._gather.reorder_plan": "a second remap of the same sizes into a cube "
    "picture in one process",
}

#: lists the cached kernels of every module whose cache index is missing (run in a process with
#: the warm-up's NUMBA_CACHE_DIR: numba picks a kernel's cache folder when it is decorated).
MISSING = """
import json, os
from tests.kernels import package_kernels
missing, found = [], 0
for name, kernel in package_kernels():
    if type(kernel._cache).__name__ != "FunctionCache":
        continue  # not cache=True
    if kernel.targetoptions.get("inline") == "always":
        continue  # compiled into its callers, never on its own
    found += 1
    if not os.path.exists(kernel._cache._cache_file._index_path):
        missing.append(name)
print(json.dumps({"found": found, "missing": sorted(set(missing))}))
"""


def _cache_files(folder: Path) -> dict[str, tuple[int, int]]:
    return {str(p): (p.stat().st_size, p.stat().st_mtime_ns) for p in folder.rglob("*.nb[ic]")}


@pytest.mark.slow
def test_after_the_warm_up_every_kernel_is_compiled_and_a_command_compiles_nothing(tmp_path):
    kernels, scratch, user = tmp_path / "kernels", tmp_path / "tmp", tmp_path / "user-cache"
    scratch.mkdir()
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(kernels),
        "TMPDIR": str(scratch),
        "BAKESHOP_CACHE_DIR": str(user),
    }
    bakeshop = [sys.executable, "-m", "bakeshop.cli.main", "-q"]
    done = subprocess.run([*bakeshop, "warm-up"], env=env, capture_output=True, text=True)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    assert done.stdout.startswith("warmed up: ") and "skipped" not in done.stdout
    assert list(scratch.iterdir()) == []  # the tour's folder is removed
    assert not user.exists()  # the tour's plans stayed in its folder

    found = subprocess.run([sys.executable, "-c", MISSING], env=env, cwd=DATA.parents[1],
                           capture_output=True, text=True, check=True)  # fmt: skip
    report = json.loads(found.stdout)
    assert report["found"] > 100
    assert report["missing"] == sorted(LIBRARY_ONLY)

    # a probe the tour never saw (a small, very bright sun), through commands and options the
    # tour ran on the default probe: numba's cache is only read
    before = _cache_files(kernels)
    probe = str(DATA / "quarry_01_1k.hdr")
    for command in (
        ["dims", probe, "-o", str(tmp_path / "dims")],
        ["prefilter", probe, str(tmp_path / "ggx.dds"), "--size", "32", "--mips", "4"],
        ["remap", probe, str(tmp_path / "cross.exr"), "--to", "cross-vertical", "--size", "32"],
    ):
        subprocess.run([*bakeshop, *command], env=env, check=True, capture_output=True)
    assert _cache_files(kernels) == before


@pytest.fixture
def scratch(tmp_path, monkeypatch) -> Path:
    """The folder the warm-up makes its scratch folder in."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def test_a_failing_command_stops_the_warm_up_in_one_line(scratch, monkeypatch, capfd):
    slow = "water ocean o --size 64 --resolution 512 --period 8"
    tour = (
        warm_up.Job("slow", (slow,), (10.0,)),
        warm_up.Job("bad", ("info {probe}", "info nothing.exr"), (1.0, 1.0)),
    )
    monkeypatch.setattr(warm_up, "TOUR", tour)
    started = time.monotonic()
    assert main(["-q", "warm-up", "--jobs", "2"]) == 2
    assert one_error_line(capfd) == (
        "bakeshop: error: warm-up: 'bakeshop info nothing.exr' failed: nothing.exr: no such file"
    )
    assert list(scratch.iterdir()) == []
    assert time.monotonic() - started < 30  # the slow job was stopped, not waited for


def test_a_missing_extra_is_skipped_and_named(scratch, monkeypatch, capfd):
    tour = (
        warm_up.Job("info", ("info {probe}",), (1.0,)),
        warm_up.Job(
            "fast", ("info {probe}",), (1.0,), needs=("no_such_module_here",), extra="compress"
        ),
    )
    monkeypatch.setattr(warm_up, "TOUR", tour)
    assert main(["-q", "warm-up"]) == 0
    out, err = capfd.readouterr()
    assert err == ""
    assert out.startswith("warmed up: 1 commands, ")
    assert out.endswith("s; skipped fast (needs bakeshop[compress])\n")


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_stops_every_process_of_the_tour_and_removes_its_folder(tmp_path, signum):
    env = {**os.environ, "TMPDIR": str(tmp_path)}
    parent = subprocess.Popen(
        [sys.executable, "-m", "bakeshop.cli.main", "-q", "warm-up", "--jobs", "2"],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + EXIT_SECONDS
    children: list[int] = []
    while len(children) < 2:
        assert time.monotonic() < deadline and parent.poll() is None, "no tour started"
        time.sleep(0.05)
        children = _children(parent.pid)
    parent.send_signal(signum)
    out, err = parent.communicate(timeout=EXIT_SECONDS)
    assert parent.returncode == 128 + signum
    assert err == f"bakeshop: interrupted by {signal.Signals(signum).name}\n" and out == ""
    assert list(tmp_path.iterdir()) == []
    for pid in children:
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)


def _children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (Linux's /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def test_a_child_that_does_not_stop_is_killed(scratch, monkeypatch, capfd):
    # a child compiling a kernel takes a signal only when the compile ends (up to ~20 s): the
    # warm-up's stop must not wait for it, or a second Ctrl-C kills the warm-up mid-clean-up
    stubborn: list[subprocess.Popen] = []
    start = warm_up._start

    def starting(job, k, probe, work):
        if job.name != "stubborn":
            return start(job, k, probe, work)
        code = "import signal, time; signal.signal(signal.SIGTERM, signal.SIG_IGN); time.sleep(60)"
        stubborn.append(subprocess.Popen([sys.executable, "-c", code]))
        return stubborn[-1]

    monkeypatch.setattr(warm_up, "_start", starting)
    tour = (
        warm_up.Job("stubborn", ("info {probe}",), (1.0,)),
        warm_up.Job("bad", ("info nothing.exr",), (1.0,)),
    )
    monkeypatch.setattr(warm_up, "TOUR", tour)
    started = time.monotonic()
    assert main(["-q", "warm-up", "--jobs", "2"]) == 2
    assert time.monotonic() - started < warm_up.STOP_SECONDS + 10
    assert "'bakeshop info nothing.exr' failed" in one_error_line(capfd)
    assert stubborn[0].returncode == -signal.SIGKILL
    assert list(scratch.iterdir()) == []


def test_a_child_killed_by_a_signal_is_named(tmp_path):
    log = tmp_path / "job.log"
    log.write_text("")
    assert warm_up._reason(log, -signal.SIGSEGV) == "killed by SIGSEGV"
    assert warm_up._reason(log, 3) == "exit status 3"
    log.write_text("Traceback...\nbakeshop: error: x.hdr: no such file\n")
    assert warm_up._reason(log, 2) == "x.hdr: no such file"


def test_every_command_of_the_tour_has_its_weight():
    for job in warm_up.TOUR:
        assert len(job.cpu) == len(job.commands) and min(job.cpu) > 0, job.name


def test_the_estimate_counts_weights_not_commands():
    # the tour's first job is its longest: by commands, the first one done is 1/65 of the
    # tour, and a busy machine's log said 54 minutes left when 9.5 remained
    weights = [job.cpu for job in warm_up.TOUR]
    estimate = warm_up.Estimate(sum(map(sum, weights)))
    estimate.finish(weights[0][0], weights[0][0])
    fraction = estimate.done([]) / estimate.total
    assert fraction == pytest.approx(weights[0][0] / estimate.total)
    assert fraction > 1.5 / sum(map(len, weights))  # more than one command in 65


def test_a_running_command_counts_its_cpu_time_at_the_finished_ones_rate():
    estimate = warm_up.Estimate(100.0)
    assert estimate.done([(20.0, 5.0)]) == 5.0  # nothing finished: the weights' own rate
    estimate.finish(30.0, 15.0)  # a warm cache: half the weights' CPU time
    assert estimate.done([(20.0, 5.0)]) == pytest.approx(30.0 + 10.0)
    assert estimate.done([(20.0, 50.0)]) == pytest.approx(30.0 + 18.0)  # below its weight


def _spin(seconds: float, stop_using_cpu: bool) -> subprocess.Popen:
    """A child that uses CPU for ``seconds``, then sleeps (or ends)."""
    code = (
        f"import time\nend = time.process_time() + {seconds}\n"
        "while time.process_time() < end: pass\n"
    )
    if stop_using_cpu:
        code += "time.sleep(60)\n"
    return subprocess.Popen([sys.executable, "-c", code])


def test_a_child_is_hung_when_it_uses_no_cpu_however_long_it_runs():
    job = warm_up.Job("x", ("info {probe}",), (1.0,))
    child = _spin(0.3, stop_using_cpu=True)
    try:
        watch = warm_up.Watch(child, job, 0, active=0.0)
        watch.sample(1.0)  # its start-up's CPU time
        while (cpu := warm_up.cpu_seconds(child.pid)) is not None and cpu < 0.3:
            time.sleep(0.05)
        time.sleep(0.2)
        watch.sample(2.0)
        assert not watch.hung(2.0 + warm_up.HUNG_SECONDS)  # it used CPU until 2.0
        watch.sample(3.0 + warm_up.HUNG_SECONDS)  # asleep: no more CPU
        assert watch.hung(3.0 + warm_up.HUNG_SECONDS)
    finally:
        child.kill()
        child.wait()


def test_a_slow_busy_command_is_not_stopped_and_a_hung_one_is(scratch, monkeypatch, capfd):
    # a loaded machine slows a command far past any wall-clock limit; only a child that uses no
    # CPU is stopped
    monkeypatch.setattr(warm_up, "HUNG_SECONDS", 1.0)

    def starting(job, k, probe, work):
        return _spin(1.5, stop_using_cpu=job.name == "hung")

    monkeypatch.setattr(warm_up, "_start", starting)
    monkeypatch.setattr(warm_up, "TOUR", (warm_up.Job("busy", ("info {probe}",), (1.0,)),))
    assert main(["-q", "warm-up"]) == 0
    assert capfd.readouterr().err == ""
    monkeypatch.setattr(warm_up, "TOUR", (warm_up.Job("hung", ("info x.hdr",), (1.0,)),))
    assert main(["-q", "warm-up"]) == 2
    assert one_error_line(capfd).endswith("'bakeshop info x.hdr' used no CPU for 1 s: hung")
