"""The budgets of a command's job, checked from its estimate before it allocates (:func:`check`):
memory (``--memory`` where the command has it, else BAKESHOP_MEMORY, else half the memory
available: :func:`bakeshop.huge.memory.resolve_memory`) and time (the root ``--max-time``, an
hour by default). An estimate over :data:`SHOW_SECONDS` is said on stderr before the job starts.
"""

from __future__ import annotations

import os

import click

from bakeshop import progress
from bakeshop.cli._numbers import Number
from bakeshop.resources import Cost, format_seconds, require

#: the default of ``--max-time``, seconds: a longer estimate is refused.
MAX_SECONDS = 3600.0
#: a job estimated to take longer than this (seconds) says so before it starts.
SHOW_SECONDS = 10.0
_KEY = "bakeshop.max_time"


def _keep(ctx: click.Context, _: click.Parameter, value: float | None) -> None:
    ctx.meta[_KEY] = MAX_SECONDS if value is None else value


max_time_option = click.option(
    "--max-time",
    type=Number(1, None, allow_inf=True),
    metavar="S",
    expose_value=False,
    callback=_keep,
    help="Longest a command's job may be estimated to run, seconds (default: 3600); a longer "
    "one is refused before it starts, naming the options that shorten it; x>=1, inf for no "
    "limit.",
)


def check(
    cost: Cost,
    path: str | os.PathLike | None,
    lower: str,
    shorten: str,
    *,
    memory: int | str | None = None,
) -> Cost:
    """Refuse the job of ``cost`` over its memory or time budget, naming the budget and the
    options that lower its memory (``lower``) or its time (``shorten``); else say its time
    when long; return ``cost``. ``memory`` is the command's ``--memory``."""
    from bakeshop.huge.memory import resolve_memory

    ctx = click.get_current_context(silent=True)
    option = "--memory or " if ctx is not None and "memory" in ctx.params else ""
    how = (
        "--memory" if memory is not None
        else "BAKESHOP_MEMORY" if os.environ.get("BAKESHOP_MEMORY")
        else f"half the memory available; set it with {option}BAKESHOP_MEMORY"
    )  # fmt: skip
    limit = ctx.meta.get(_KEY, MAX_SECONDS) if ctx is not None else MAX_SECONDS
    allow = f"bakeshop --max-time {cost.seconds * 1.1:.0f}"
    require(
        cost,
        path,
        budget=(resolve_memory(memory), how),
        lower=lower,
        max_seconds=limit,
        shorten=f"{shorten}, or allow it with {allow}",
    )
    if cost.seconds > SHOW_SECONDS and progress.enabled():
        click.echo(
            f"bakeshop: {cost.what}: about {format_seconds(cost.seconds)} (estimated)", err=True
        )
    return cost
