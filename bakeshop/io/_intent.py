"""What a write meant to store, and the open verification sessions: the small state that
:func:`~bakeshop.io.atomic_path` and the writers share with :mod:`bakeshop.io.verify`.

It lives apart from the checks so that the writers can declare their intent without importing
the readers the checks use (the readers import the writers' modules).
"""

from __future__ import annotations

import contextlib
import json
import os
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from bakeshop.errors import FormatError

__all__ = ["check_written", "intent", "session", "verifying"]

_lock = threading.Lock()
_sessions: list[dict] = []
_local = threading.local()


def verifying() -> bool:
    """True while a verification session is open (in any thread; an intent declared in a
    thread no session watches is simply not used)."""
    return bool(_sessions)


@contextlib.contextmanager
def session(
    check: Callable[..., dict],
    log: str | os.PathLike | None = None,
    *,
    this_thread: bool = False,
    guard: Callable[[Path, Path], object] | None = None,
) -> Iterator[list[dict]]:
    """Within the block, every completed :func:`~bakeshop.io.atomic_path` write (with
    ``this_thread``, of the calling thread only) is passed to ``guard(target, tmp)`` (which
    raises to refuse the target) and then to ``check(tmp, kind, data, **context)`` (which returns a
    record with ``ok`` and ``reason``) before it is renamed; yields the list of records."""
    state: dict[str, Any] = {
        "check": check,
        "guard": guard,
        "records": [],
        "log": None if log is None else os.fspath(log),
        "thread": threading.get_ident() if this_thread else None,
    }
    with _lock:
        _sessions.append(state)
    try:
        yield state["records"]
    finally:
        with _lock:  # by identity: two sessions may be equal
            _sessions[:] = [s for s in _sessions if s is not state]


@contextlib.contextmanager
def intent(target: str | os.PathLike, kind: str, data: object, **context: object) -> Iterator[None]:
    """Within the block, a write of ``target`` is meant to hold ``data`` (of ``kind``:
    ``"image"``, ``"mips"``, ``"blocks"``, ``"json"``, ``"text"``); ``context`` says how it
    is stored (codec options, sample type). An outer intent for the same target wins (a JSON
    document written through :func:`~bakeshop.io.write_text` is checked as JSON)."""
    intents = _intents()
    key = os.path.abspath(os.fspath(target))
    if not verifying() or key in intents:
        yield
        return
    intents[key] = (kind, data, context)
    try:
        yield
    finally:
        intents.pop(key, None)


def _intents() -> dict:
    if not hasattr(_local, "intents"):
        _local.intents = {}
    return _local.intents


def check_written(tmp: Path, target: Path) -> None:
    """Called by :func:`~bakeshop.io.atomic_path` with a complete temporary file: check it
    against the target's intent, record the result, raise :class:`FormatError` naming the
    target when it fails. Does nothing outside a session."""
    me = threading.get_ident()
    with _lock:
        sessions = [s for s in _sessions if s["thread"] in (None, me)]
    if not sessions:
        return
    for state in sessions:
        if state["guard"] is not None:
            state["guard"](target, tmp)
    kind, data, context = _intents().get(os.path.abspath(os.fspath(target)), (None, None, {}))
    record = sessions[-1]["check"](tmp, kind, data, **context)
    record["file"] = os.fspath(target)
    for state in sessions:
        state["records"].append(record)
        if state["log"] is not None:
            with open(state["log"], "a", encoding="utf-8") as f:
                f.write(json.dumps(record) + "\n")
    if not record["ok"]:
        raise FormatError(f"the file written does not reload: {record['reason']}", target)
