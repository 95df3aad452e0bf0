"""Small text documents written beside the images: JSON sidecars (sun, SH, camera responses,
quality reports) and shader snippets; read with clear errors, written atomically."""

from __future__ import annotations

import json
import os

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io._files import atomic_path

__all__ = ["read_json", "write_json", "write_text"]

#: a document larger than this is not one of bakeshop's.
MAX_BYTES = 64 << 20


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8, with a final newline) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text if text.endswith("\n") else text + "\n")


def write_json(path: str | os.PathLike, document: dict) -> None:
    """Write a JSON object (plain dicts, lists, finite numbers and strings) to ``path``
    atomically, indented by one space per level."""
    write_text(path, json.dumps(document, indent=1, allow_nan=False))


def read_json(path: str | os.PathLike) -> dict:
    """Read a JSON object from ``path``; :class:`~bakeshop.errors.FormatError` naming the file
    when it is not one (or is larger than :data:`MAX_BYTES`)."""
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
