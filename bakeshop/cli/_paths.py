"""Path types and output safety of the command line.

**Every file argument has a path type of this module**: inputs are checked when parsed
(:class:`bakeshop.cli._process.InputPath`), output names may hold braces only as the patterns
their command writes (:class:`OutputPath`: ``{face}``, ``{mip}``, ``{frame}``), and before a
command runs, no output may be (by name, symbolic or hard link, or pattern) one of its inputs
(:func:`refuse_overwriting_inputs`, run for every command by :func:`guard_outputs`).
"""

from __future__ import annotations

import functools
import glob
import os
import re
import string
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from bakeshop.cli._process import InputPath, record, recorded
from bakeshop.errors import ArgumentError

# --- outputs that would overwrite inputs -----------------------------------------------------


def refuse_overwriting_inputs(output: str | os.PathLike, *inputs: str | os.PathLike | None) -> None:
    """Refuse, before any work, an ``output`` that would write over one of the command's inputs.

    ``output`` may be a pattern (``{face}``, ``{mip}``, ``{frame}``); the inputs are ``inputs``
    and every input the command was given (as recorded when its arguments were parsed: files,
    ``{face}`` sets, glob patterns). The output is refused when any file it may stand for *is*
    an input file: the same name, a symbolic link either way, a link through a directory, or a
    hard link (the same file on disk).

    Raises
    ------
    ArgumentError
        With the output file and the input it would overwrite.
    """
    text = os.fspath(output)
    targets = _existing_outputs(text)
    if not targets:
        return
    for typed in dict.fromkeys(
        [*(os.fspath(p) for p in inputs if p is not None), *recorded("inputs")]
    ):
        for source in _existing_inputs(typed):
            for target in targets:
                if _same_file(target, source):
                    raise ArgumentError(_overwrite_reason(text, target, typed, source), target)


def guard_outputs(group: click.Group) -> None:
    """Make every command of ``group`` (and of its sub-groups) call
    :func:`refuse_overwriting_inputs` on each of its :class:`OutputPath` arguments before it
    runs: a command gets the check by typing its outputs."""
    for command in group.commands.values():
        if isinstance(command, click.Group):
            guard_outputs(command)
        elif command.callback is not None and not hasattr(command.callback, "__guarded__"):
            command.callback = _guarded(command.callback)


def _guarded(callback: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(callback)
    def run(*args: Any, **kwargs: Any) -> Any:
        outputs = recorded("outputs")
        refuse_shared_outputs(outputs)
        for output in outputs:
            refuse_overwriting_inputs(output)
        return callback(*args, **kwargs)

    setattr(run, "__guarded__", True)  # noqa: B010 (a marker click's wrapper type lacks)
    return run


def refuse_shared_outputs(outputs: list[str]) -> None:
    """Refuse, before any work, two outputs of one command that name the same file (the same
    path, through a link or ``..``, or a name that a pattern output includes): the second write
    would replace the first.

    Raises
    ------
    ArgumentError
        With the file and the two options' values that name it.
    """
    for i, first in enumerate(outputs):
        for second in outputs[i + 1 :]:
            if _same_output(first, second):
                also = "" if first == second else f" ({first} and {second})"
                raise ArgumentError(f"two outputs name this file{also}: give each its own", second)


def _same_output(a: str, b: str) -> bool:
    """True when the output names ``a`` and ``b`` may stand for one file."""
    a_real, b_real = (os.path.normcase(os.path.realpath(t)) for t in (a, b))
    a_regex, b_regex = _output_regex(a_real), _output_regex(b_real)
    if a_regex is not None and b_regex is not None:
        return a_real == b_real
    if a_regex is not None:
        return a_regex.fullmatch(b_real) is not None
    if b_regex is not None:
        return b_regex.fullmatch(a_real) is not None
    return a_real == b_real or _same_file(a, b)


def _output_regex(text: str) -> re.Pattern[str] | None:
    """The regular expression of the files an output pattern stands for; None for a plain
    name."""
    parts = _pattern_parts(text)
    if not any(name for _, name, _ in parts):
        return None
    return re.compile(
        "".join(
            re.escape(literal) + (_field_regex(name, spec) if name else "")
            for literal, name, spec in parts
        )
    )


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _existing_inputs(typed: str) -> list[str]:
    """The existing files an input argument names: itself, its six ``{face}`` files (in both
    naming schemes), or its glob pattern's matches."""
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    if "{face}" in typed:
        names = [typed.replace("{face}", n) for n in (*FACE_NAMES, *FACE_NAMES_SHORT)]
    else:
        names = [typed, *(sorted(glob.glob(typed)) if glob.has_magic(typed) else ())]
    return [n for n in dict.fromkeys(names) if os.path.exists(n)]


def _existing_outputs(text: str) -> list[str]:
    """The existing files an output name may stand for: itself, or every file its patterns
    (:data:`PATTERNS`) may expand to."""
    regex = _output_regex(text)
    if regex is None:
        return [text] if os.path.exists(text) else []
    wildcard = "".join(
        glob.escape(literal) + ("*" if name else "") for literal, name, _ in _pattern_parts(text)
    )
    return [p for p in sorted(glob.glob(wildcard)) if regex.fullmatch(p)]


def _field_regex(name: str, spec: str) -> str:
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    if name == "face":
        return "(?:" + "|".join((*FACE_NAMES, *FACE_NAMES_SHORT)) + ")"
    if not spec or re.fullmatch(r"0?[0-9]*d", spec):
        return "-?[0-9]+"
    return "[^/]+"


def _overwrite_reason(output: str, target: str, typed: str, source: str) -> str:
    notes = []
    if output != target:
        notes.append(f"the output {output} includes it")
    if typed != source:
        notes.append(f"the input {typed} includes it")
    if os.path.abspath(target) != os.path.abspath(source):
        if os.path.realpath(target) == os.path.realpath(source):
            notes.append(f"a symbolic link makes it the input {source}")
        else:
            notes.append(f"it is a hard link to the input {source}")
    return "refusing to write over the command's own input" + (
        f" ({'; '.join(notes)})" if notes else ""
    )


# --- output names: braces are patterns ----------------------------------------------------------

#: the patterns an output name may hold, each written by the commands that take it: six cube
#: faces, the levels of a mip chain, the frames of a sequence (with a format: {frame:04d}).
PATTERNS = {
    "face": "{face} (the six cube faces: posx ... negz)",
    "mip": "{mip} (the mip level: 0, 1, ...)",
    "frame": "{frame} (the frame: 0, 1, ...; {frame:04d} pads it)",
    "scene": "{scene} (the preview's scene: sky, balls, golf)",
}


def _pattern_parts(text: str) -> list[tuple[str, str | None, str]]:
    """``(literal, field or None, format spec)`` pieces of an output name (no checks)."""
    try:
        return [(lit, name, spec or "") for lit, name, spec, _ in string.Formatter().parse(text)]
    except ValueError:
        return [(text, None, "")]


def check_output_name(text: str, allowed: tuple[str, ...] = ()) -> None:
    """Refuse an output name whose braces are not the patterns ``allowed`` (names of
    :data:`PATTERNS`): braces mark patterns and are never part of a file name; a format spec
    is allowed for ``{frame}`` only.

    Raises
    ------
    ArgumentError
        Naming the output, the brace that is wrong and the patterns the command writes.
    """
    what = (
        "braces in an output name mark the patterns "
        + " and ".join(PATTERNS[a] for a in allowed)
        + "; they cannot be part of a file name"
        if allowed
        else "this output is one file, and braces in an output name mark patterns: they "
        "cannot be part of a file name"
    )
    try:
        parts = list(string.Formatter().parse(text))
    except ValueError:
        raise ArgumentError(f"an unmatched '{{' or '}}': {what}", text) from None
    for literal, name, spec, conversion in parts:
        if "{" in literal or "}" in literal:  # '{{' or '}}'
            raise ArgumentError(f"a doubled brace: {what}", text)
        if name is None:
            continue
        field = (
            "{"
            + name
            + (f"!{conversion}" if conversion else "")
            + (f":{spec}" if spec else "")
            + "}"
        )
        if name not in allowed or conversion or (spec and name != "frame"):
            raise ArgumentError(f"{field} is not a pattern this command writes: {what}", text)
        if spec:
            try:
                format(0, spec)
            except ValueError as e:
                raise ArgumentError(f"{field}: {e}", text) from None


class OutputPath(click.Path):
    """An output file (or with ``directory``, a folder the command creates), whose name may hold
    the patterns ``fields`` (:data:`PATTERNS`) and no other brace (:func:`check_output_name`);
    remembered as one of the command's outputs, which :func:`guard_outputs` checks against its
    inputs before it runs."""

    def __init__(self, fields: tuple[str, ...] = (), *, directory: bool = False):
        super().__init__(
            dir_okay=directory, file_okay=not directory, writable=not directory, path_type=Path
        )
        self.fields = tuple(fields)
        self.directory = directory

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        check_output_name(os.fspath(value), self.fields)
        path = super().convert(value, param, ctx)
        if not self.directory:
            record(ctx, "outputs", str(path))
        return path


def parse_size(text: str | int | tuple[int, int]) -> tuple[int, int] | int:
    """Parse ``'WxH'`` into ``(width, height)`` or ``'N'`` into ``N`` (positive integers); a
    size already parsed (by :class:`Size`) is returned as it is."""
    if isinstance(text, (int, tuple)):
        return text
    try:
        parts = [int(p) for p in text.lower().split("x")]
    except ValueError:
        parts = []
    if len(parts) not in (1, 2) or min(parts) < 1:
        raise ArgumentError(f"invalid size {text!r}: expected N or WxH with positive integers")
    return parts[0] if len(parts) == 1 else (parts[0], parts[1])


#: click type for input files: a readable regular file (checked when parsed: a directory, named
#: pipe, device or symbolic link loop fails at once), remembered as one of the run's inputs.
INPUT = InputPath()
#: click type for an input environment: one file, or six named with {face} (checked on reading).
ENVIRONMENT = InputPath(patterns=True)
#: click type for an input environment that may also be a .zarr store (the chunked commands).
ENVIRONMENT_SOURCE = InputPath(patterns=True, stores=True)
#: click type for input frames: files or glob patterns (each match checked on reading).
FRAMES = InputPath(patterns=True)
#: click type for an input image that may also be a .zarr store (a directory).
SOURCE = InputPath(stores=True)
#: click type for output files (one file: no brace in the name).
OUTPUT = OutputPath()
#: click type for an output environment: one file, or a cube's six files with {face}.
OUTPUT_FACES = OutputPath(("face",))
#: click type for an output mip chain: one container, or files with {mip} (and {face}).
OUTPUT_CHAIN = OutputPath(("mip", "face"))
#: click type for output frames: one file, or a sequence with {frame} ({frame:04d}).
OUTPUT_FRAMES = OutputPath(("frame",))
#: click type for an output directory (the commands create it when missing).
OUT_DIR = OutputPath(directory=True)
