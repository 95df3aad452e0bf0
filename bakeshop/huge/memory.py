"""The memory bound of a chunked job: parsing ``--memory``, its default, and planning blocks
under it (or refusing, before anything starts, with the number a job needs). What the machine
has is :func:`bakeshop.resources.available_memory` (which also counts ``ulimit -v`` and the
cgroup's limit)."""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable

from bakeshop.errors import ArgumentError, BakeshopError
from bakeshop.resources import available_memory, format_bytes

#: the default bound is this fraction of the memory the machine has available when the job
#: starts (other programs, and other developers' jobs, keep the rest).
DEFAULT_FRACTION = 0.5
#: the smallest bound accepted.
MIN_MEMORY = 4 << 20
#: the largest bound accepted (a petabyte).
MAX_MEMORY = 10**15

_UNITS = {
    "": 1,
    "b": 1,
    "k": 1e3,
    "kb": 1e3,
    "kib": 1 << 10,
    "m": 1e6,
    "mb": 1e6,
    "mib": 1 << 20,
    "g": 1e9,
    "gb": 1e9,
    "gib": 1 << 30,
    "t": 1e12,
    "tb": 1e12,
    "tib": 1 << 40,
    "p": 1e15,
    "pb": 1e15,
    "pib": 1 << 50,
}
_MEMORY = re.compile(r"\s*([0-9]*\.?[0-9]+(?:e[+-]?[0-9]+)?)\s*([a-z]*)\s*", re.IGNORECASE)


class MemoryBoundError(BakeshopError, ValueError):
    """A job cannot run within its memory bound; ``needed`` says how much it needs."""

    def __init__(self, reason: str, needed: int, path: str | os.PathLike | None = None) -> None:
        super().__init__(reason, path)
        self.needed = needed


def parse_memory(text: str | int | float) -> int:
    """Bytes of a memory size: ``"2GB"`` or ``"2 GB"`` (10^9), ``"1.5GiB"`` (2^30), ``"512M"``,
    or a number of bytes; from :data:`MIN_MEMORY` to :data:`MAX_MEMORY`. The one parser of
    ``--memory`` and ``BAKESHOP_MEMORY``."""
    if isinstance(text, (int, float)):
        value = float(text)
    else:
        m = _MEMORY.fullmatch(str(text))
        unit = m[2].lower() if m else None
        if m is None or unit not in _UNITS:
            raise ArgumentError(
                f"invalid memory size {text!r}: a number with an optional unit "
                "(B, KB, MB, GB, TB, PB in powers of 1000; KiB, MiB, GiB, TiB, PiB in powers "
                "of 1024)"
            )
        value = float(m[1]) * _UNITS[unit]
    if not math.isfinite(value) or not MIN_MEMORY <= value <= MAX_MEMORY:
        raise ArgumentError(f"a memory bound is 4 MiB to 1 PB, not {text!r}")
    return int(value)


def default_memory() -> int:
    """The default bound: :data:`DEFAULT_FRACTION` of the available memory."""
    return max(MIN_MEMORY, int(DEFAULT_FRACTION * available_memory()))


def resolve_memory(memory: int | str | None) -> int:
    """``memory`` (None, bytes or a size string) as bytes; None gives :func:`default_memory`
    (or the BAKESHOP_MEMORY environment variable when set)."""
    if memory is not None:
        return parse_memory(memory)
    variable = os.environ.get("BAKESHOP_MEMORY")
    if not variable:
        return default_memory()
    try:
        return parse_memory(variable)
    except ArgumentError as e:
        raise ArgumentError(f"BAKESHOP_MEMORY: {e.reason}") from None


def refuse(what: str, needed: int, memory: int) -> MemoryBoundError:
    """The error of a job that needs ``needed`` bytes under a bound of ``memory``."""
    return MemoryBoundError(
        f"{what} needs at least {format_bytes(needed)} of memory, more than the bound of "
        f"{format_bytes(memory)}; raise it with --memory {format_bytes(needed * 1.05)} "
        "(or BAKESHOP_MEMORY)",
        needed,
    )


def plan_blocks(
    shape: tuple[int, int],
    block_bytes: Callable[[int, int], int],
    per_task: int,
    *,
    at_least: int = 1,
    what: str = "the job",
    memory: int = 0,
    fixed: int = 0,
    workers: int = 1,
) -> tuple[int, int]:
    """Choose a block of ``(rows, columns)`` of an output of ``shape`` (h, w) whose task costs
    at most ``per_task`` bytes by ``block_bytes(rows, columns)``: rows are halved first, then
    columns; then rows are cut further until there are ``at_least`` blocks (parallelism and
    progress). Raises :func:`refuse` (with ``fixed + workers * block_bytes(1, 1)``) when even
    one texel's task does not fit."""
    h, w = shape
    rows, cols = h, w
    while block_bytes(rows, cols) > per_task:
        if rows > 1:
            rows = (rows + 1) // 2
        elif cols > 1:
            cols = (cols + 1) // 2
        else:
            raise refuse(what, fixed + workers * block_bytes(1, 1), memory)
    while rows > 1 and math.ceil(h / rows) * math.ceil(w / cols) < at_least:
        rows = (rows + 1) // 2
    return rows, cols


def blocks(shape: tuple[int, int], block: tuple[int, int]) -> list[tuple[int, int, int, int]]:
    """The ``(top, bottom, left, right)`` of each block of ``block`` (rows, columns) tiling an
    output of ``shape`` (h, w), row by row."""
    h, w = shape
    rb, cb = block
    return [
        (top, min(top + rb, h), left, min(left + cb, w))
        for top in range(0, h, rb)
        for left in range(0, w, cb)
    ]
