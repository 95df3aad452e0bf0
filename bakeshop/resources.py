"""What a computation will need, estimated before it starts, and what the machine has.

A heavy function of bakeshop comes with a ``*_cost`` function beside it that states, from the
sizes alone and before anything is allocated, the :class:`Cost` of a call: the memory it will
hold at its peak (beyond its inputs), the work it will do and, where that is long, its
seconds. The heavy function calls :func:`require` first, so a call that cannot fit is refused
at once with the number it needs,

    bakeshop.resources.MemoryLimitError: remapping latlong 1024x512 to cube 6x9000x9000 (bilinear)
    needs about 4.96 GB of memory; 3.1 GB is left under the address-space limit (ulimit -v)

instead of being killed by the kernel (or failing deep inside numpy) minutes later. Callers
can ask first (``remap_cost(...)``) to plan, choose smaller sizes, or go by blocks
(:mod:`bakeshop.huge`).

What is available (:func:`available_memory`) is the least of: the memory the kernel reports
available (``MemAvailable``, plus free swap), the room left under the process's cgroup limit,
and the room left under its address-space and data-segment limits (``ulimit -v``, ``ulimit -d``),
each read when asked, so memory already held by the caller counts.

The estimates are upper bounds of the measured peak: ``tests/test_resources.py`` runs heavy
functions in a child process and compares the peak resident size of the call with its estimate,
and checks that each heavy function under a small budget is refused before it allocates.
"""

from __future__ import annotations

import math
import os
import resource
from typing import NamedTuple

from bakeshop.errors import BakeshopError

__all__ = [
    "Cost",
    "MemoryLimitError",
    "TimeLimitError",
    "available_memory",
    "format_bytes",
    "format_seconds",
    "memory_limits",
    "require",
]


#: a cost this small is not checked (reading the limits takes longer than such a call).
SMALL = 32 << 20


class Cost(NamedTuple):
    """The estimated cost of one call of a heavy function (see the module notes)."""

    #: bytes the call holds at its peak, beyond its inputs and what the caller already holds.
    memory: int
    #: units of work (lookups, samples, solver steps: what the function's progress counts).
    work: int
    #: what the call does, for messages: "GGX prefilter of 6x4096^2 faces, 13 levels".
    what: str
    #: the time it will take on this machine, seconds (``work`` at a measured rate per core).
    seconds: float = 0.0


class MemoryLimitError(BakeshopError, MemoryError):
    """A computation needs more memory than is available; ``needed`` and ``available`` say
    how much (bytes)."""

    def __init__(
        self, reason: str, needed: int, available: int, path: str | os.PathLike | None = None
    ) -> None:
        super().__init__(reason, path)
        self.needed = needed
        self.available = available


class TimeLimitError(BakeshopError):
    """A computation is estimated to take longer than allowed; ``needed`` and ``allowed`` say
    how long (seconds)."""

    def __init__(
        self, reason: str, needed: float, allowed: float, path: str | os.PathLike | None = None
    ) -> None:
        super().__init__(reason, path)
        self.needed = needed
        self.allowed = allowed


def seconds_of(work: float, rate: float) -> float:
    """Seconds of ``work`` units at ``rate`` units per second per core, on this machine's
    cores (the kernels run on all of them)."""
    return work / (rate * (os.cpu_count() or 1))


def format_seconds(s: float) -> str:
    """``42 s``, ``3.5 min``, ``2.1 h`` or ``3.2 days``."""
    for unit, size in (("days", 86400), ("h", 3600), ("min", 60)):
        if s >= size:
            return f"{s / size:.3g} {unit}"
    return f"{s:.2g} s" if s < 10 else f"{s:.0f} s"


def format_bytes(n: float) -> str:
    """``1.5 GB``-style text (powers of 1000, as ``--memory`` reads them)."""
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("KB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def _meminfo() -> dict[str, int]:
    out = {}
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                key, _, rest = line.partition(":")
                fields = rest.split()
                if fields and fields[0].isdigit():
                    out[key] = int(fields[0]) * 1024
    except OSError:
        pass
    return out


def _status(field: str) -> int | None:
    """A size from /proc/self/status (``VmSize``, ``VmData``), bytes."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def _read_number(path: str) -> int | None:
    try:
        with open(path) as f:
            text = f.read().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _inactive_file(stat_path: str, key: str) -> int:
    try:
        with open(stat_path) as f:
            for line in f:
                name, _, value = line.partition(" ")
                if name == key and value.strip().isdigit():
                    return int(value)
    except OSError:
        pass
    return 0


def _cgroup_room() -> int | None:
    """Bytes left under this process's cgroup memory limit (None: no limit). The page cache
    that the kernel can drop (inactive files) counts as room."""
    for limit, usage, stat, key in (
        ("memory.max", "memory.current", "memory.stat", "inactive_file"),
        (
            "memory/memory.limit_in_bytes",
            "memory/memory.usage_in_bytes",
            "memory/memory.stat",
            "total_inactive_file",
        ),
    ):
        cap = _read_number(f"/sys/fs/cgroup/{limit}")
        used = _read_number(f"/sys/fs/cgroup/{usage}")
        if cap is None or used is None or cap >= 1 << 60:  # "max", or v1's "no limit"
            continue
        return max(0, cap - used + _inactive_file(f"/sys/fs/cgroup/{stat}", key))
    return None


def memory_limits() -> dict[str, int]:
    """Every bound on new allocations that applies now, bytes: ``"memory available"`` (the
    kernel's estimate plus free swap), and when set, ``"cgroup limit"``, ``"address-space limit
    (ulimit -v)"`` and ``"data-segment limit (ulimit -d)"`` (each the room left under it)."""
    info = _meminfo()
    if "MemAvailable" in info:
        room = info["MemAvailable"] + info.get("SwapFree", 0)
    else:
        room = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")
    limits = {"memory available": room}
    cgroup = _cgroup_room()
    if cgroup is not None:
        limits["cgroup limit"] = cgroup
    for name, which, field in (
        ("address-space limit (ulimit -v)", resource.RLIMIT_AS, "VmSize"),
        ("data-segment limit (ulimit -d)", resource.RLIMIT_DATA, "VmData"),
    ):
        soft, _ = resource.getrlimit(which)
        used = _status(field)
        if soft != resource.RLIM_INFINITY and used is not None:
            limits[name] = max(0, soft - used)
    return limits


def available_memory() -> int:
    """Bytes that new allocations can take now: the least of :func:`memory_limits`."""
    return min(memory_limits().values())


def require(
    cost: Cost,
    path: str | os.PathLike | None = None,
    *,
    budget: tuple[int, str] | None = None,
    lower: str = "",
    max_seconds: float = math.inf,
    shorten: str = "",
) -> Cost:
    """Refuse ``cost`` when its memory exceeds :func:`available_memory` (or ``budget``, bytes
    and where that bound comes from, when it is less), or its time exceeds ``max_seconds``;
    return it otherwise. ``path`` is the file the computation works on, named in the error;
    ``lower`` and ``shorten`` name what lowers its memory and its time ("--size or
    --samples"), said in the error.

    Raises
    ------
    MemoryLimitError
        ``"<what> needs about 15.7 GB of memory; 11 GB is available"``, naming the limit that
        binds when it is not the machine's memory.
    TimeLimitError
        ``"<what> would take about 5.2 h (estimated), more than the limit of 1 h"``.
    """
    if cost.seconds > max_seconds:
        raise TimeLimitError(
            f"{cost.what} would take about {format_seconds(cost.seconds)} (estimated), more "
            f"than the limit of {format_seconds(max_seconds)}"
            + (f"; lower {shorten}" if shorten else ""),
            cost.seconds,
            max_seconds,
            path,
        )
    if cost.memory <= SMALL:
        return cost
    limits = memory_limits()
    if budget is not None:
        limits[budget[1]] = budget[0]
    binding = min(limits, key=lambda name: limits[name])
    available = limits[binding]
    if cost.memory <= available:
        return cost
    where = "is available" if binding == "memory available" else f"is left under the {binding}"
    if budget is not None and binding == budget[1]:
        where = f"is the budget ({binding})"
    raise MemoryLimitError(
        f"{cost.what} needs about {format_bytes(cost.memory)} of memory; "
        f"{format_bytes(available)} {where}" + (f"; lower {lower}" if lower else ""),
        cost.memory,
        available,
        path,
    )
