"""Small text documents written beside the images: JSON sidecars and shader snippets."""

from __future__ import annotations

import json
import os

from bakeshop.errors import FormatError
from bakeshop.io._files import atomic_path


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8, with a final newline) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text if text.endswith("\n") else text + "\n")


def write_json(path: str | os.PathLike, document) -> None:
    """Write a JSON document (plain dicts, lists, numbers and strings) to ``path`` atomically,
    indented by one space per level."""
    write_text(path, json.dumps(document, indent=1))


def read_json(path: str | os.PathLike):
    """Read a JSON document; :class:`~bakeshop.errors.FormatError` naming the file when it is
    not one."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (ValueError, UnicodeDecodeError) as e:
        raise FormatError(f"not a JSON document ({e})", path) from None
