"""Small text documents written beside the images: JSON sidecars (sun, SH, camera responses,
quality reports) and shader snippets; read with clear errors, written atomically."""

from __future__ import annotations

import json
import math
import os

import numpy as np

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io import _intent
from bakeshop.io._files import atomic_path, open_input

__all__ = ["read_json", "write_json", "write_text"]

#: a document larger than this is not one of bakeshop's.
MAX_BYTES = 64 << 20


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8, with a final newline) to ``path`` atomically."""
    with _intent.intent(path, "text", text), atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text if text.endswith("\n") else text + "\n")


def _plain(value: object) -> object:
    """Numpy scalars and arrays as Python numbers and lists, paths as strings, non-finite
    floats as null (JSON has neither NaN nor infinity)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def write_json(path: str | os.PathLike, document: dict) -> None:
    """Write a JSON object to ``path`` atomically, indented by one space per level; numpy
    values become plain numbers and lists, NaN and infinities null."""
    with _intent.intent(path, "json", document):
        write_text(path, json.dumps(_plain(document), indent=1, allow_nan=False))


def _finite_float(text: str) -> float:
    """A JSON number as a float64, refused where none holds it (``1e999``, a 400-digit
    integer, ``NaN``, ``Infinity``): no document of bakeshop holds one, and its readers would
    turn it into an infinity or fail on it."""
    if len(text) <= 400:  # a longer one is refused before Python parses 5000 digits
        value = float(text)
        if math.isfinite(value):
            return value
    shown = text if len(text) <= 20 else f"{text[:12]}... ({len(text)} characters)"
    raise ValueError(f"the number {shown} is not a finite float64")


def _json_int(text: str) -> int:
    """A JSON integer, refused where no float64 holds it (as :func:`_finite_float`)."""
    _finite_float(text)
    return int(text)


def read_json(path: str | os.PathLike) -> dict:
    """Read a JSON object from ``path``; :class:`~bakeshop.errors.FormatError` naming the file
    when it is not one (or is larger than :data:`MAX_BYTES`, nested too deeply for Python's
    parser, or holds a number that no float64 holds). Only a regular file is read."""
    with open_input(path) as f:
        size = os.fstat(f.fileno()).st_size
        if size > MAX_BYTES:
            raise FormatError(f"{size} bytes is too large for a JSON document", path)
        try:
            data = f.read(MAX_BYTES + 1)
        except OSError as e:
            raise BakeshopError(e.strerror or str(e), path) from None
    try:
        doc = json.loads(
            data.decode("utf-8"),
            parse_float=_finite_float,
            parse_int=_json_int,
            parse_constant=_finite_float,
        )
    except RecursionError:
        raise FormatError("not a JSON document: nested too deeply", path) from None
    except ValueError as e:  # bad UTF-8, bad JSON, a number no float64 holds
        raise FormatError(f"not a JSON document: {e}", path) from None
    if not isinstance(doc, dict):
        raise FormatError("the JSON document is not an object", path)
    return doc
