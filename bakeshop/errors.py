"""The one exception family of bakeshop.

Every error that bad input or bad arguments can cause is a :class:`BakeshopError`, carrying the
file it concerns (when there is one) and a plain reason. The command line prints it as one line,
``bakeshop: error: <file>: <reason>``, and exits with status 2.
"""

from __future__ import annotations

import os
from collections.abc import Collection


class BakeshopError(Exception):
    """Base class: a plain ``reason`` and optionally the ``path`` it concerns."""

    def __init__(self, reason: str, path: str | os.PathLike | None = None):
        super().__init__(reason)
        self.reason = reason
        self.path = None if path is None else os.fspath(path)

    def __str__(self) -> str:
        return f"{self.path}: {self.reason}" if self.path else self.reason


class FormatError(BakeshopError, ValueError):
    """A file is truncated, corrupt, lies about its size, or is not in the format it claims."""


class UnsupportedError(BakeshopError, ValueError):
    """A well-formed file or request uses a feature that bakeshop does not support."""


class ArgumentError(BakeshopError, ValueError):
    """An argument is out of its domain: a bad layout name, size, option or array shape."""


def validate_choice(value: str, choices: Collection[object], what: str) -> str:
    """Return ``value`` if it is one of ``choices``, else raise :class:`ArgumentError` naming it.

    >>> validate_choice("bilinear", ("nearest", "bilinear"), "filter")
    'bilinear'
    """
    if value not in choices:
        raise ArgumentError(
            f"unknown {what} {value!r}; choose one of: {', '.join(map(str, choices))}"
        )
    return value
