"""A codec's options checked against its function's signature: the names it takes and, for
each, the types its annotation names (``bool``, ``int``, ``float``, ``str``, ``None``). Text
(from ``-O KEY=VALUE``) is converted by the same rule, so a typo is refused in one line and
never passed on as a truthy string."""

from __future__ import annotations

import inspect
import numbers
import os
from collections.abc import Callable
from typing import Any

import numpy as np

from bakeshop.errors import ArgumentError

#: the words a boolean option takes, in any case.
BOOLEAN_WORDS = {"true": True, "yes": True, "1": True, "false": False, "no": False, "0": False}


def checked_options(
    function: Callable[..., object], options: dict, format_name: str, path: str | os.PathLike
) -> dict:
    """``options`` as ``function`` takes them: unknown names and values of the wrong type are
    refused (naming the options it takes), text is converted to the annotated type."""
    parameters = inspect.signature(function).parameters
    if any(p.kind is p.VAR_KEYWORD for p in parameters.values()):
        return dict(options)
    accepted = {n: p.annotation for n, p in parameters.items() if p.kind is p.KEYWORD_ONLY}
    unknown = sorted(set(options) - set(accepted))
    if unknown:
        raise ArgumentError(
            f"{format_name} takes no option {', '.join(map(repr, unknown))}; "
            f"its options are: {', '.join(accepted) or 'none'}",
            path,
        )
    return {
        name: _converted(name, value, accepted[name], format_name, path)
        for name, value in options.items()
    }


def _converted(
    name: str, value: Any, annotation: Any, format_name: str, path: str | os.PathLike
) -> Any:
    """``value`` as one of the types of ``annotation`` (a string, as ``from __future__ import
    annotations`` keeps it), or ArgumentError. Annotations naming other types pass as they are."""
    if not isinstance(annotation, str):
        return value
    kinds = {k.strip() for k in annotation.split("|")}
    if not kinds <= {"bool", "int", "float", "str", "None"}:
        return value
    if isinstance(value, str):
        text = value.strip()
        if "bool" in kinds and text.lower() in BOOLEAN_WORDS:
            return BOOLEAN_WORDS[text.lower()]
        for kind in (int, float):
            if kind.__name__ in kinds:
                try:
                    return kind(text)
                except ValueError:
                    pass
        if "str" in kinds:
            return text
        if "None" in kinds and text.lower() == "none":
            return None
    elif value is None:
        if "None" in kinds:
            return None
    elif isinstance(value, (bool, np.bool_)):
        if "bool" in kinds:
            return bool(value)
    elif isinstance(value, numbers.Integral):
        if "int" in kinds:
            return int(value)
        if "float" in kinds:
            return float(value)
        if "bool" in kinds and value in (0, 1):
            return bool(value)
    elif isinstance(value, numbers.Real) and "float" in kinds:
        return float(value)
    raise ArgumentError(
        f"{format_name} option {name} takes {_describe(kinds)}, not {value!r}", path
    )


def _describe(kinds: set[str]) -> str:
    """``'true or false (yes/no, 1/0)'``, ``'an integer or none'``..."""
    words = {
        "bool": "true or false (yes/no, 1/0)",
        "int": "an integer",
        "float": "a number",
        "str": "a name",
        "None": "none",
    }
    return " or ".join(words[k] for k in ("bool", "int", "float", "str", "None") if k in kinds)
