"""Progress reporting that library code may call and only the command line switches on.

Library functions wrap long loops in :func:`track`, long single steps in :func:`step`, and work
counted as it completes elsewhere (dask tasks) in :func:`task`; all are silent (and free)
unless :func:`enable` was called, which the ``bakeshop`` command does.

On a terminal they draw rich progress bars. When the console is not a terminal (stderr sent to a
log file, a CI job, a render farm's job log), bars would print nothing useful, so each long
job prints a line every :data:`LOG_INTERVAL` seconds instead, and one when it ends (a step
shorter than the interval prints nothing, so a quick command's stderr stays clean)::

    bakeshop: resize 16384x8192 -> 2048x1024: 37% (24/64), 12.4 s elapsed, about 21 s left
    bakeshop: resize 16384x8192 -> 2048x1024: done in 33.0 s
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from collections.abc import Iterable, Iterator, Sized
from typing import TYPE_CHECKING, TypeVar

if TYPE_CHECKING:
    from rich.console import Console
    from rich.progress import Progress, TaskID

T = TypeVar("T")

#: seconds between two log lines when the console is not a terminal (BAKESHOP_LOG_INTERVAL
#: overrides it).
LOG_INTERVAL = 5.0

#: the console progress goes to, made on first use (:func:`_get_console`), and whether progress
#: is shown at all.
_console: Console | None = None
_enabled = False
#: the rich Progress on screen (shared by nested tasks) and how many tasks use it.
_live = None
_live_users = 0
_live_lock = threading.Lock()
#: per thread: progress silenced (code running inside a dask task).
_local = threading.local()


def enable(console: Console | None = None) -> None:
    """Show progress on ``console`` (a :class:`rich.console.Console`, stderr's by default, made
    when progress is first shown): bars on a terminal, periodic log lines elsewhere."""
    global _console, _enabled
    _console, _enabled = console, True


def disable() -> None:
    """Silence progress reporting again."""
    global _console, _enabled
    _console, _enabled = None, False


def enabled() -> bool:
    """True when progress is shown in this thread (the command line, not a library call, and
    not inside a task of a chunked job)."""
    return _enabled and not getattr(_local, "quiet", False)


def _get_console() -> Console:
    """The console of :func:`enable`, stderr's made now if it gave none: importing rich costs
    about 0.05 s, which a command that shows no progress (``info``) does not pay."""
    global _console
    if _console is None:
        from rich.console import Console

        _console = Console(stderr=True)
    return _console


@contextlib.contextmanager
def silenced() -> Iterator[None]:
    """No progress from this thread while the block runs (the chunked engine wraps each task
    in it: the job reports progress per task, not the library code inside)."""
    before = getattr(_local, "quiet", False)
    _local.quiet = True
    try:
        yield
    finally:
        _local.quiet = before


def _interval() -> float:
    try:
        value = float(os.environ.get("BAKESHOP_LOG_INTERVAL", LOG_INTERVAL))
    except ValueError:
        value = LOG_INTERVAL
    return value if value > 0 else LOG_INTERVAL


def _logging() -> bool:
    return enabled() and not _get_console().is_terminal


def _seconds(t: float) -> str:
    if t < 90:
        return f"{t:.1f} s"
    if t < 5400:
        return f"{t / 60:.1f} min"
    return f"{t / 3600:.1f} h"


class Task:
    """Work of ``total`` units (None: unknown) reported as it completes: :meth:`advance` from any
    thread. Made by :func:`task`."""

    def __init__(self, description: str, total: int | None):
        self.description = description
        self.total = total
        self.completed = 0
        self.started = time.perf_counter()
        self._lock = threading.Lock()
        self._bar: Progress | None = None
        self._id: TaskID | None = None
        self._last_log = self.started

    def advance(self, amount: int = 1) -> None:
        """Count ``amount`` more units done."""
        with self._lock:
            self.completed += amount
            if self._bar is not None and self._id is not None:
                self._bar.update(self._id, completed=self.completed)
            elif _logging():
                now = time.perf_counter()
                if now - self._last_log >= _interval():
                    self._last_log = now
                    self._log(now)

    def set_total(self, total: int | None) -> None:
        """Change the number of units (dask knows it once its graph is built)."""
        with self._lock:
            self.total = total
            if self._bar is not None and self._id is not None:
                self._bar.update(self._id, total=total)

    def line(self, now: float | None = None) -> str:
        """The log line of the task's state."""
        now = time.perf_counter() if now is None else now
        elapsed = now - self.started
        text = f"bakeshop: {self.description}: "
        if self.total:
            fraction = min(1.0, self.completed / self.total)
            text += f"{100 * fraction:.0f}% ({self.completed}/{self.total}), "
            text += f"{_seconds(elapsed)} elapsed"
            if 0 < fraction < 1:
                text += f", about {_seconds(elapsed * (1 - fraction) / fraction)} left"
        else:
            text += f"{_seconds(elapsed)} elapsed"
        return text

    def _log(self, now: float) -> None:
        if _enabled:
            _get_console().print(self.line(now), markup=False, highlight=False, soft_wrap=True)


@contextlib.contextmanager
def task(description: str, total: int | None = None) -> Iterator[Task]:
    """A :class:`Task` shown while the block runs: a bar on a terminal, periodic lines in a log
    (also while nothing advances: a heartbeat every interval), and a closing line in a log."""
    t = Task(description, total)
    if not enabled():
        yield t
        return
    if not _logging():
        with _bar() as bar:
            task_id = bar.add_task(description, total=total)
            t._bar, t._id = bar, task_id
            try:
                yield t
            finally:
                bar.remove_task(task_id)
        return
    stop = threading.Event()

    def heartbeat() -> None:
        while not stop.wait(_interval()):
            with t._lock:
                now = time.perf_counter()
                if now - t._last_log >= 0.99 * _interval():
                    t._last_log = now
                    t._log(now)

    thread = threading.Thread(target=heartbeat, name="bakeshop-progress", daemon=True)
    thread.start()
    try:
        yield t
    finally:
        stop.set()
        thread.join()
    elapsed = time.perf_counter() - t.started
    if not _enabled or (elapsed < _interval() and t._last_log == t.started):
        return  # a step shorter than the interval in a log: no line
    _get_console().print(
        f"bakeshop: {description}: done in {_seconds(elapsed)}",
        markup=False,
        highlight=False,
        soft_wrap=True,
    )


@contextlib.contextmanager
def _bar() -> Iterator[Progress]:
    """The Progress on screen, started by the outermost task and shared by nested ones."""
    global _live, _live_users
    with _live_lock:
        if _live is None:
            _live = _progress()
            _live.start()
        _live_users += 1
        bar = _live
    try:
        yield bar
    finally:
        with _live_lock:
            _live_users -= 1
            if _live_users == 0:
                _live.stop()
                _live = None


def _progress() -> Progress:
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
        console=_get_console(),
        transient=True,
    )


def track(items: Iterable[T], description: str, total: int | None = None) -> Iterator[T]:
    """Iterate over ``items``, showing progress when progress is enabled."""
    if not enabled():
        yield from items
        return
    if total is None and isinstance(items, Sized):
        total = len(items)
    with task(description, total) as t:
        for item in items:
            yield item
            t.advance()


@contextlib.contextmanager
def step(description: str) -> Iterator[None]:
    """Show a spinner with elapsed time around one long step when progress is enabled (in a
    log: a line every interval while it runs, and one when it ends)."""
    if not enabled():
        yield
        return
    if _logging() or _live is not None:  # inside a bar: a line of it, not a second display
        with task(description):
            yield
        return
    with _get_console().status(description, spinner="dots"):
        yield
