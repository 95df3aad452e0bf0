"""JSON sidecars: the small documents that travel beside texture sets (what a set holds, its
units and how it was made), written atomically like every other bakeshop output."""

from __future__ import annotations

import json
import math
import os

import numpy as np

from bakeshop.io._files import atomic_path

__all__ = ["write_json", "read_json", "write_text"]


def _plain(value):
    """numpy scalars and arrays as Python numbers and lists; non-finite floats as null."""
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
    """Write ``document`` as indented UTF-8 JSON, atomically. numpy values become plain
    numbers and lists; NaN and infinities become null (JSON has neither)."""
    text = json.dumps(_plain(document), indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write UTF-8 text (a shader snippet, a note beside a texture set), atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)


def read_json(path: str | os.PathLike) -> dict:
    """Read a JSON document (a sidecar)."""
    with open(path, encoding="utf-8") as f:
        return json.load(f)
