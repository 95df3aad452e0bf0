"""Small helpers shared by the command modules: argument types, option builders, input checks
and output safety."""

from __future__ import annotations

import os
from pathlib import Path

import click
import numpy as np

from bakeshop.cli._process import InputPath
from bakeshop.errors import ArgumentError


def refuse_overwriting_inputs(output: str | os.PathLike, *inputs: str | os.PathLike) -> None:
    """Raise :class:`ArgumentError` when ``output`` is one of ``inputs`` (same file on disk)."""
    out = Path(output)
    for path in inputs:
        p = Path(path)
        if out.resolve() == p.resolve() or (out.exists() and p.exists() and out.samefile(p)):
            raise ArgumentError("refusing to write over the command's own input", output)


def parse_size(text: str) -> tuple[int, int] | int:
    """Parse ``'WxH'`` into ``(width, height)`` or ``'N'`` into ``N`` (positive integers)."""
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
#: click type for input frames: files or glob patterns (each match checked on reading).
FRAMES = InputPath(patterns=True)
#: click type for an input image that may also be a .zarr store (a directory).
SOURCE = InputPath(stores=True)
#: click type for output files.
OUTPUT = click.Path(dir_okay=False, writable=True, path_type=Path)
#: click type for an output directory (the commands create it when missing).
OUT_DIR = click.Path(file_okay=False, path_type=Path)


def _parse_value(text: str):
    lowered = text.lower()
    if lowered in ("true", "yes", "on"):
        return True
    if lowered in ("false", "no", "off"):
        return False
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_options(pairs: tuple[str, ...]) -> dict:
    """``('compression=piz', 'bits=16')`` -> ``{'compression': 'piz', 'bits': 16}``."""
    options = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise ArgumentError(f"invalid option {pair!r}: expected KEY=VALUE")
        options[key.strip().replace("-", "_")] = _parse_value(value.strip())
    return options


def writer_option(help: str):
    """The repeatable ``-O/--option KEY=VALUE`` writer option (read with :func:`parse_options`)."""
    return click.option("-O", "--option", "options", multiple=True, metavar="KEY=VALUE", help=help)


def out_dir_option(help: str):
    """The ``--out-dir``/``-o`` option of commands that write a set of files."""
    return click.option("--out-dir", "-o", required=True, type=OUT_DIR, help=help)


def float_format_option(help: str):
    """The ``--format`` option (hdr, exr, pfm) of commands that write a set of float images."""
    return click.option(
        "--format",
        "fmt",
        type=click.Choice(("hdr", "exr", "pfm")),
        default="hdr",
        show_default=True,
        help=help,
    )


def convention_option(help: str):
    """The ``--convention`` option: the engine whose cube face set is read or written."""
    from bakeshop.sphere import CONVENTIONS

    return click.option(
        "--convention",
        type=click.Choice(CONVENTIONS),
        default="opengl",
        show_default=True,
        help=help,
    )


def is_ldr(path) -> bool:
    """True when ``path``'s format stores 8-bit display-encoded pictures (PNG, JPEG, TGA)."""
    from bakeshop.io import HDR_CODECS, codec_for

    return codec_for(path) not in HDR_CODECS


def require_hdr(path) -> None:
    """Raise :class:`ArgumentError` unless ``path`` is a linear HDR format (.hdr, .exr, .pfm)."""
    if is_ldr(path):
        raise ArgumentError(
            "this command takes linear HDR input (.hdr, .exr, .pfm); 8-bit pictures hold "
            "display-encoded values (decode with 'bakeshop convert --srgb-decode' first)",
            path,
        )


def parse_exposure(text: str | None) -> float | str | None:
    """``None``, ``'auto'`` or a number of stops."""
    if text is None or text.strip().lower() == "auto":
        return None if text is None else "auto"
    try:
        ev = float(text)
    except ValueError:
        ev = float("nan")
    if not np.isfinite(ev):
        raise ArgumentError(f"invalid exposure {text!r}: a number of stops (EV) or 'auto'")
    return ev
