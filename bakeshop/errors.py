"""The one exception family of bakeshop.

Every error that bad input or bad arguments can cause is a :class:`BakeshopError`, carrying the
file it concerns (when there is one) and a plain reason. The command line prints it as one line,
``bakeshop: error: <file>: <reason>``, and exits with status 2.
"""

from __future__ import annotations

import os
from collections.abc import Collection


class _Located(Exception):
    """A plain ``reason`` and optionally the ``path`` it concerns."""

    def __init__(self, reason: str, path: str | os.PathLike | None = None):
        super().__init__(reason)
        self.reason = reason
        self.path = None if path is None else os.fspath(path)

    def __str__(self) -> str:
        return f"{self.path}: {self.reason}" if self.path else self.reason


class BakeshopError(_Located):
    """Base class: a plain ``reason`` and optionally the ``path`` it concerns."""


class BakeshopWarning(_Located, UserWarning):
    """Something done that the user should know of (a wider type written than asked, ...):
    a plain ``reason`` and optionally the ``path`` it concerns. The command line prints it as
    ``bakeshop: warning: <file>: <reason>``."""


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


#: letters whose spoken name starts with a vowel sound (an F, an HDR, an RG image).
_VOWEL_LETTERS = frozenset("AEFHILMNORSX")
#: vowel-spelled word starts that sound like a consonant (a unit, a one-level chain, a user).
_CONSONANT_SOUNDS = ("uni", "use", "usu", "uti", "eu", "one", "once")


def with_article(word: object) -> str:
    """``word`` after the indefinite article it takes when spoken: ``'an OpenEXR'``,
    ``'an angular'``, ``'a latlong'``, ``'an HDR'``, ``'a BC6H'``, ``'an 8x8'``,
    ``'an 11-texel'``, ``'a 1024x512'``, ``'an 800'``.

    >>> with_article("octahedral"), with_article("RG"), with_article(18)
    ('an octahedral', 'an RG', 'an 18')
    """
    text = str(word)
    head = text[:1]
    if head.isdigit():
        digits = len(text) - len(text.lstrip("0123456789"))
        # eight..., eleven, eighteen (and their thousands and millions)
        vowel = head == "8" or (text[:2] in ("11", "18") and digits % 3 == 2)
    elif text[:2].isupper():  # an acronym, spelled letter by letter
        vowel = head in _VOWEL_LETTERS
    else:
        vowel = head.lower() in "aeiou" and not text.lower().startswith(_CONSONANT_SOUNDS)
    return f"{'an' if vowel else 'a'} {text}"
