"""The ``bakeshop`` command as a process: signals, what reaches stderr, the one error line.

One run of the command line (:func:`run`) promises:

- **Signals clean up.** SIGINT, SIGTERM and SIGHUP become an :class:`Interrupted` exception in
  the main thread, so every ``finally`` block and every atomic write
  (:func:`bakeshop.io._files.atomic_path`) removes its temporary file; the process then exits
  with 128 + the signal number (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP), the statuses
  a shell reports for a process the signal killed. SIGINT is taken even when the parent
  ignored it: a shell script without job control starts its background commands with SIGINT
  ignored, Python keeps an inherited SIG_IGN, and so a ``kill -INT`` of such a job went
  unheard: the work finished and the command exited 0. SIGHUP stays ignored under ``nohup``.
  A signal that arrives inside a compiled kernel is raised when the kernel returns (Python runs
  its handlers between bytecodes); kernels are short enough per call for that to be prompt.
- **One line on stderr for a failure**, ``bakeshop: error: FILE: reason``, and nothing else:
  Python warnings (numpy's overflow warnings among them) and log records of the libraries
  (trimesh) raised during the run are collected, dropped when the run fails, and printed one
  line each after a run that succeeds: ``bakeshop: warning: FILE: reason`` for bakeshop's own
  (:class:`bakeshop.errors.BakeshopWarning`), ``bakeshop: warning: PACKAGE: message`` for
  another package's.
- **The file is named.** An error raised below the command line (in the library) without a file
  concerns the data the command read: it is attributed to the command's inputs, the values of
  its arguments of type :data:`INPUT` and :data:`ENVIRONMENT`, as the user typed them.
- **Partial outputs are listed.** When a run that wrote some of its files (a bake folder, six
  cube faces) fails or is interrupted, the error line ends with the files that were written.
"""

from __future__ import annotations

import contextlib
import glob
import logging
import math
import os
import re
import signal
import sys
import threading
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from types import FrameType
from typing import Any

import click

from bakeshop.errors import BakeshopError

#: signal -> whether a handler is installed even when the parent set the signal to be ignored.
SIGNALS = {signal.SIGINT: True, signal.SIGTERM: True}
if hasattr(signal, "SIGHUP"):
    SIGNALS[signal.SIGHUP] = False  # nohup's choice is kept
#: seconds after a first signal during which further signals are ignored, so that the clean-up
#: the first one started finishes; a signal after that kills the process at once.
GRACE_SECONDS = 5.0


class Interrupted(BaseException):
    """A signal received by the command line, raised in the main thread.

    A :class:`BaseException` like :class:`KeyboardInterrupt`, so that code which handles
    ``Exception`` does not swallow it, but not a subclass of it: click turns a
    KeyboardInterrupt into a blank line and an ``Abort``.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


@contextlib.contextmanager
def signals_as_exceptions() -> Iterator[list[int]]:
    """Within the block (in the main thread), the :data:`SIGNALS` raise :class:`Interrupted`.

    Yields the list of signal numbers received, in order. Elsewhere than in the main thread,
    where Python cannot install handlers, nothing changes.
    """
    received: list[int] = []
    first: list[float] = []

    def handler(signum: int, frame: FrameType | None) -> None:
        received.append(signum)
        if not first:
            first.append(time.monotonic())
            raise Interrupted(signum)
        if time.monotonic() - first[0] > GRACE_SECONDS:
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)

    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum, override_ignored in SIGNALS.items():
            current = signal.getsignal(signum)
            if current is signal.SIG_IGN and not override_ignored:
                continue
            previous[signum] = current
            signal.signal(signum, handler)
    try:
        yield received
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old if old is not None else signal.SIG_DFL)


@contextlib.contextmanager
def library_messages() -> Iterator[list[str]]:
    """Collect the Python warnings and the log records (WARNING and above) of the block.

    Yields the list of one-line messages. The warning filters in force are kept (what Python
    would have shown is collected, what it would have ignored stays ignored).
    """
    notes: list[str] = []

    class Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            notes.append(f"{record.name.partition('.')[0]}: {record.getMessage()}")

    handler = Collect(logging.WARNING)
    root = logging.getLogger()
    with warnings.catch_warnings(record=True) as caught:
        root.addHandler(handler)
        try:
            yield notes
        finally:
            root.removeHandler(handler)
            for w in caught:  # bakeshop's own name their file; another package is named
                package = _package(w.filename)
                notes.append(f"{'' if package == 'bakeshop' else package + ': '}{w.message}")


def _package(filename: str) -> str:
    """The top-level package a source file belongs to (``trimesh``, ``numpy``, ``bakeshop``)."""
    parts = Path(filename).parts
    for marker in ("site-packages", "dist-packages"):
        if marker in parts and parts.index(marker) + 1 < len(parts):
            return Path(parts[parts.index(marker) + 1]).stem
    return "bakeshop" if "bakeshop" in parts else Path(filename).stem


# --- what the command line was given -------------------------------------------------------------

_inputs: list[str] = []


class InputPath(click.ParamType):
    """An input file: checked by :func:`bakeshop.io.check_input` when the arguments are parsed
    (so a directory, named pipe, device or symbolic link loop fails at once with one line), and
    remembered as one of the run's inputs. With ``patterns``, a name holding ``{face}`` (six
    files) or a glob pattern is remembered as typed and its files are checked when read. With
    ``stores``, a ``.zarr`` directory (a chunked store) is an input too."""

    name = "file"

    def __init__(self, patterns: bool = False, stores: bool = False) -> None:
        self.patterns = patterns
        self.stores = stores

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Path:
        from bakeshop.io import check_input

        path = Path(value)
        text = str(value)
        store = self.stores and path.suffix.lower() == ".zarr" and path.is_dir()
        if not store and not (self.patterns and ("{face}" in text or glob.has_magic(text))):
            check_input(path)
        _inputs.append(text)
        record(ctx, "inputs", text)
        return path


def record(ctx: click.Context | None, kind: str, text: str) -> None:
    """Remember ``text`` as one of the ``kind`` (``"inputs"``, ``"outputs"``) of the command
    being parsed: in the click context's ``meta``, which every nested context shares, so each
    invocation has its own (see :func:`recorded`)."""
    if ctx is not None:
        ctx.meta.setdefault(f"bakeshop.{kind}", []).append(text)


def recorded(kind: str) -> list[str]:
    """The ``kind`` (``"inputs"``, ``"outputs"``) of the command running now, as typed."""
    ctx = click.get_current_context(silent=True)
    return list(ctx.meta.get(f"bakeshop.{kind}", ())) if ctx is not None else []


class ByteSize(click.ParamType):
    """A number of bytes: ``8G``, ``512M``, ``1.5GiB``, ``100000``; K, M, G, T are powers of
    1024."""

    name = "size"
    _UNITS = {"": 1, "k": 1 << 10, "m": 1 << 20, "g": 1 << 30, "t": 1 << 40}

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        if isinstance(value, int):
            return value
        match = re.fullmatch(r"\s*([0-9.eE+]+)\s*([kKmMgGtT]?)(?:i?[bB])?\s*", str(value))
        number = None
        if match is not None:
            with contextlib.suppress(ValueError):
                number = float(match[1]) * self._UNITS[match[2].lower()]
        if number is None or not math.isfinite(number) or not 1 <= number < 1 << 60:
            self.fail(
                f"{value!r} is not a size: expected bytes >= 1 such as 8G or 512M", param, ctx
            )
        return int(number)

    def describe_range(self) -> str:
        """The range, as the option's help states it."""
        return "1 byte to 1 EiB"


# --- one run ---------------------------------------------------------------------------------


def _raised_in(error: BaseException) -> str:
    """The module whose code raised ``error``."""
    tb = error.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    return tb.tb_frame.f_globals.get("__name__", "") if tb is not None else ""


def _one_line(text: str) -> str:
    """``text`` on one line: a line break after ``:`` or ``,`` becomes a space, others ``; ``."""
    joined = ""
    for line in (line.strip() for line in str(text).splitlines()):
        if line:
            joined += (" " if joined.endswith((":", ",")) else "; " if joined else "") + line
    return joined


def _bakeshop_error(error: BakeshopError) -> str:
    """``FILE: reason`` of an error, attributing a file-less error from the library to the
    run's inputs."""
    path = error.path
    if path is None and _inputs and not _raised_in(error).startswith("bakeshop.cli"):
        path = ", ".join(dict.fromkeys(_inputs))
    return f"{path}: {error.reason}" if path else error.reason


#: files named one by one in the line of a run that failed after writing some.
MAX_NAMED = 8


def _written(paths: list[Path]) -> str:
    """``'written before it: out/a.hdr, out/b.hdr (2 files)'``; names given once per folder."""
    paths = list(dict.fromkeys(paths))  # a file rewritten (a bake's manifest) is named once
    if not paths:
        return ""
    folders = {p.parent for p in paths}
    if len(paths) > MAX_NAMED:  # a bake or a frame sequence: the first ones and the last
        shown = [str(p) for p in paths[: MAX_NAMED - 2]]
        return f"; written before it: {', '.join(shown)}, ..., {paths[-1]} ({len(paths)} files)"
    if len(folders) == 1 and len(paths) > 1:
        names = f"in {paths[0].parent}/: " + ", ".join(p.name for p in paths)
    else:
        names = ", ".join(str(p) for p in paths)
    count = f" ({len(paths)} files)" if len(paths) > 1 else ""
    return f"; written before it: {names}{count}"


#: the files the running command wrote (one list, once :func:`record_command_writes` ran).
_journals: list[list[Path]] = []


def record_command_writes(ctx: click.Context) -> None:
    """Collect the files that the command about to run writes, so that a failure can name
    them. The root group calls it once a command is chosen: ``--version`` and ``--help`` end
    before it and never load :mod:`bakeshop.io` (numpy)."""
    from bakeshop.io import record_writes

    _journals.append(ctx.with_resource(record_writes()))


def run(group: click.Group, argv: list[str] | None) -> int:
    """Run ``group`` (the ``bakeshop`` command) on ``argv`` as described in the module notes;
    return the exit status: 0, 2 for bad input or arguments, 128 + N after signal N."""
    _inputs.clear()
    _journals.clear()
    status, message, received, notes = 0, None, [], []
    try:
        with signals_as_exceptions() as received, library_messages() as notes:
            status, message = _invoke(group, argv, received)
    except Interrupted as e:  # between the command's end and the handlers' removal
        received.append(e.signum)
    written = _journals[0] if _journals else []
    if received:
        tty = "\n" if sys.stderr.isatty() else ""  # after the terminal's "^C"
        name = signal.Signals(received[0]).name
        click.echo(f"{tty}bakeshop: interrupted by {name}{_written(written)}", err=True)
        return 128 + received[0]
    if message is not None:
        click.echo(f"bakeshop: error: {_one_line(message)}{_written(written)}", err=True)
        return status
    for note in dict.fromkeys(notes):
        click.echo(f"bakeshop: warning: {_one_line(note)}", err=True)
    return status


def _invoke(
    group: click.Group, argv: list[str] | None, received: list[int]
) -> tuple[int, str | None]:
    """Run the command; return its exit status and the error line's message (None if none)."""
    try:
        return group.main(args=argv, prog_name="bakeshop", standalone_mode=False) or 0, None
    except Interrupted:
        return 0, None  # the handler recorded it
    except BakeshopError as e:
        return 2, _bakeshop_error(e)
    except click.UsageError as e:
        where = e.ctx.command_path if e.ctx is not None else "bakeshop"
        return 2, f"{e.format_message()} (see '{where} --help')"
    except click.ClickException as e:
        return 2, e.format_message()
    except (click.Abort, KeyboardInterrupt):  # where no handler could be installed
        received.append(signal.SIGINT)
        return 0, None
    except MemoryError as e:  # an allocation no estimate foresaw: say what it was
        detail = str(e).strip()
        reason = "not enough memory for this command" + (
            f": {detail[:1].lower()}{detail[1:]}" if detail else ""
        )
        return 2, _bakeshop_error(BakeshopError(reason))
    except OSError as e:
        reason = e.strerror or str(e)
        return 2, f"{e.filename}: {reason}" if e.filename else reason
    except Exception:
        if not received:
            raise  # a bug: its traceback is what a report needs
        # the signal surfaced through a library as another error: it was the signal
        return 0, None
