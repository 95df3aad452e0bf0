"""What every benchmark shares: which peers are here, timing in the same run, and the rule that a
peer that is present is measured.

A benchmark names the peers it compares with (:class:`Peers`), measures each one that is
present in the same run as bakeshop, says :meth:`Peers.measured` for each figure it got, and
ends with :meth:`Peers.finish`: an absent peer is reported as not measured (never replaced by a
quoted figure), and a present peer that was not measured makes the script exit 1.

Peers: ``cmgen`` (Filament's, from Debian's ``libfilament-tools``, on PATH), ``cmft`` (only when
the environment names its binary: ``CMFT=/path/to/cmftRelease``; it is built from its own
sources), and the Python packages ``py360convert``, ``opencv`` (cv2), ``oiio``
(OpenImageIO), ``openexr`` (the OpenEXR module), ``pyvips`` and ``pillow``.

Timing: :func:`alternate` runs several contenders in turn (A B C A B C ...), so that a machine
whose load changes during the run slows all of them alike, and reports the median and the range
of wall time and of CPU time (user + system of the process and its children: steadier than wall
time when other work shares the cores), and for whole processes their peak memory.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence

#: peer -> how to find it: ("exe", its name on PATH), ("env", the variable naming its binary),
#: or ("module", the Python module).
KNOWN = {
    "cmgen": ("exe", "cmgen"),
    "cmft": ("env", "CMFT"),
    "py360convert": ("module", "py360convert"),
    "opencv": ("module", "cv2"),
    "oiio": ("module", "OpenImageIO"),
    "openexr": ("module", "OpenEXR"),
    "pyvips": ("module", "pyvips"),
    "pillow": ("module", "PIL"),
}


def locate(peer: str) -> str | None:
    """The peer's executable path or module name when it is here, else None."""
    kind, name = KNOWN[peer]
    if kind == "exe":
        return shutil.which(name)
    if kind == "env":
        path = os.environ.get(name)
        return path if path and os.path.isfile(path) and os.access(path, os.X_OK) else None
    try:
        return name if importlib.util.find_spec(name) is not None else None
    except (ImportError, ValueError):
        return None


class Peers:
    """The peers one benchmark compares with, and which of them it measured."""

    def __init__(self, names: Sequence[str]):
        unknown = [n for n in names if n not in KNOWN]
        if unknown:
            raise ValueError(f"unknown peers {unknown}; known: {sorted(KNOWN)}")
        self.where = {n: locate(n) for n in names}
        self.figures: dict[str, list[str]] = {n: [] for n in names}

    def present(self, name: str) -> bool:
        return self.where[name] is not None

    def path(self, name: str) -> str:
        """The executable of a present peer."""
        path = self.where[name]
        if path is None:
            raise RuntimeError(f"{name} is not here")
        return path

    def measured(self, name: str, what: str) -> None:
        """Record that a figure of ``name`` (``what``: the job) was measured in this run."""
        if not self.present(name):
            raise RuntimeError(f"{name} is absent: it cannot have been measured")
        self.figures[name].append(what)

    def summary(self) -> list[str]:
        """One line per peer: measured (which jobs), or not measured because absent."""
        lines = []
        for name, where in self.where.items():
            if where is None:
                kind, key = KNOWN[name]
                how = f"set {key}=/path/to/{name}" if kind == "env" else "not installed"
                lines.append(f"{name}: not measured (absent: {how})")
            elif self.figures[name]:
                lines.append(f"{name}: measured in this run ({', '.join(self.figures[name])})")
            else:
                lines.append(f"{name}: PRESENT BUT NOT MEASURED ({where})")
        return lines

    def finish(self) -> None:
        """Print :meth:`summary`; exit 1 when a present peer has no figure from this run."""
        print("\npeers:")
        for line in self.summary():
            print("  " + line)
        missing = [n for n, w in self.where.items() if w is not None and not self.figures[n]]
        if missing:
            print(f"error: present but not measured: {', '.join(missing)}", file=sys.stderr)
            raise SystemExit(1)


def machine() -> str:
    """The processor, its cores and the load average now (figures depend on all three)."""
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            model = next((ln.split(":", 1)[1].strip() for ln in f if "model name" in ln), model)
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{model}, {os.cpu_count()} cores, load average {load:.1f}"


#: GNU time, which reports its child's peak memory: the child of a small process (a child forked
#: from this Python process would carry this process's resident memory into its own peak).
GNU_TIME = "/usr/bin/time"


@functools.cache
def _bytecode() -> None:
    """Compile bakeshop's bytecode once, as installing does (``make`` runs compileall; pip does
    for a regular install): a process that finds no .pyc compiles each module it imports, and
    with ``PYTHONDONTWRITEBYTECODE`` set it does so on every run (0.1-0.2 s of a command's
    start-up), which no user's installed bakeshop pays."""
    package = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "bakeshop")
    subprocess.run([sys.executable, "-m", "compileall", "-q", package], check=True,
                   stdout=subprocess.DEVNULL)  # fmt: skip


def run_process(cmd: Sequence[str], **kwargs) -> tuple[float, float, float]:
    """Run a whole process to its end (output discarded; non-zero exit raises): (wall s, CPU s
    of the process and its children, its peak resident memory in MB, NaN without GNU time).
    bakeshop's bytecode is compiled before the first (:func:`_bytecode`)."""
    _bytecode()
    with tempfile.TemporaryDirectory() as tmp:
        peak = os.path.join(tmp, "peak")
        timed = os.access(GNU_TIME, os.X_OK)
        full = [GNU_TIME, "-f", "%M", "-o", peak, *cmd] if timed else list(cmd)
        with open(os.path.join(tmp, "err"), "w+b") as err:
            start = time.perf_counter()
            proc = subprocess.Popen(full, stdout=subprocess.DEVNULL, stderr=err, **kwargs)
            _, status, usage = os.wait4(proc.pid, 0)
            wall = time.perf_counter() - start
            proc.returncode = os.waitstatus_to_exitcode(status)
            if proc.returncode:
                err.seek(0)
                tail = err.read()[-400:].decode(errors="replace")
                raise RuntimeError(f"{' '.join(map(str, cmd))} exited {proc.returncode}: {tail}")
        mb = float("nan")
        if timed:
            with open(peak) as f:
                mb = int(f.read().split()[-1]) / 1024  # kilobytes
    return wall, usage.ru_utime + usage.ru_stime, mb


def call(fn: Callable[[], object]) -> tuple[float, float]:
    """Time a library call in this process: (wall s, CPU s of this process, all threads)."""
    start, start_cpu = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - start, time.process_time() - start_cpu


def alternate(contenders: dict[str, Callable[[], tuple[float, ...]]], repeats: int) -> dict:
    """Run each contender ``repeats`` times, in turn; per contender: median and range of wall
    and CPU seconds (``{"wall", "wall_min", "wall_max", "cpu", "cpu_min", "cpu_max", "n"}``),
    and of peak memory in MB (``"mem"``...) when the contender reports it (a third value)."""
    samples: dict[str, dict[str, list[float]]] = {n: {} for n in contenders}
    for _ in range(repeats):
        for name, run in contenders.items():
            for key, value in zip(("wall", "cpu", "mem"), run(), strict=False):
                samples[name].setdefault(key, []).append(value)
    found: dict[str, dict] = {}
    for name, keys in samples.items():
        found[name] = {"n": repeats}
        for key, values in keys.items():
            found[name].update({key: statistics.median(values), f"{key}_min": min(values),
                                f"{key}_max": max(values)})  # fmt: skip
    return found


def spread(r: dict, key: str = "wall", digits: int = 2) -> str:
    """``'1.23 (1.20-1.31)'``: the median and range of a result of :func:`alternate`."""
    if r["n"] == 1:
        return f"{r[key]:.{digits}f}"
    return f"{r[key]:.{digits}f} ({r[key + '_min']:.{digits}f}-{r[key + '_max']:.{digits}f})"
