"""JSON documents (camera responses, sun measurements): read with clear errors, written
atomically."""

from __future__ import annotations

import json
import os

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io._files import atomic_path

__all__ = ["read_json", "write_json"]

#: a document larger than this is not one of bakeshop's.
MAX_BYTES = 64 << 20


def read_json(path: str | os.PathLike) -> dict:
    """Read a JSON object from ``path``; :class:`FormatError` if it is not one."""
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise FormatError(f"{size} bytes is too large for a JSON document", path)
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise BakeshopError(e.strerror or str(e), path) from None
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise FormatError(f"not a JSON document: {e}", path) from None
    if not isinstance(doc, dict):
        raise FormatError("the JSON document is not an object", path)
    return doc


def write_json(path: str | os.PathLike, doc: dict) -> None:
    """Write ``doc`` as indented JSON, atomically (the file appears complete or not at all)."""
    text = json.dumps(doc, indent=1, allow_nan=False) + "\n"
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
