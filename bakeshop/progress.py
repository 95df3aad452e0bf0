"""Progress reporting that library code may call and only the command line switches on.

Library functions wrap long loops in :func:`track` and long single steps in :func:`step`; both
are silent (and free) unless :func:`enable` was called, which the ``bakeshop`` command does.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")

_console = None


def enable(console=None) -> None:
    """Show progress bars on ``console`` (a :class:`rich.console.Console`, stderr by default)."""
    global _console
    if console is None:
        from rich.console import Console

        console = Console(stderr=True)
    _console = console


def disable() -> None:
    """Silence progress reporting again."""
    global _console
    _console = None


def _progress():
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    return Progress(
        SpinnerColumn(),
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=_console,
        transient=True,
    )


def track(items: Iterable[T], description: str, total: int | None = None) -> Iterator[T]:
    """Iterate over ``items``, showing a progress bar when progress is enabled."""
    if _console is None:
        yield from items
        return
    if total is None and hasattr(items, "__len__"):
        total = len(items)
    with _progress() as bar:
        task = bar.add_task(description, total=total)
        for item in items:
            yield item
            bar.advance(task)


@contextlib.contextmanager
def step(description: str):
    """Show a spinner with elapsed time around one long step when progress is enabled."""
    if _console is None:
        yield
        return
    with _console.status(description, spinner="dots"):
        yield
