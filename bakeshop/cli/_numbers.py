"""Number types of the command line.

**Every option and argument that holds a number has one of the types of this module**
(:class:`Number`, :class:`Integer`, :class:`Size`, :class:`Numbers`, :class:`Direction`,
:class:`Exposure`, :class:`MemorySize`): finite (NaN and the infinities are refused), within a
range that the option's ``--help`` states (click prints it: ``[default: 256; 1<=x<=4096]``), and
refused when parsed, in one line, before the command runs. The range is the one in which the
command makes sense; what a value inside it costs (memory, time) is estimated by the library
before it starts (:mod:`bakeshop.resources`). ``tests/cli/test_limits.py`` walks the command
tree and holds every command to this.
"""

from __future__ import annotations

import math
import re
from typing import Any

import click

from bakeshop.errors import ArgumentError

# --- numbers ------------------------------------------------------------------------------------

#: Largest side of an output image in pixels (a 65536 x 32768 latlong is 2^31 texels, 25 GB
#: of float32 RGB: past memory, where the chunked commands take over).
IMAGE_SIDE = 1 << 16


def _g(value: float) -> str:
    """A bound for people: ``4096``, ``0.001``, ``1e+06``."""
    return f"{value:g}" if isinstance(value, float) else str(value)


class Number(click.FloatRange):
    """A finite number in ``[low, high]`` (``low_open``/``high_open`` exclude an end), shown
    in ``--help`` as click shows a range. NaN is refused (click's :class:`click.FloatRange`
    lets it through, since every comparison with NaN is false), and so are the infinities
    unless ``allow_inf`` (where infinity means something: deep water). Both ends must be
    given unless ``allow_inf``: a number without an upper bound has no meaning for a
    command."""

    name = "number"

    def __init__(
        self,
        low: float,
        high: float | None,
        *,
        low_open: bool = False,
        high_open: bool = False,
        allow_inf: bool = False,
    ):
        if low is None or (high is None and not allow_inf):
            raise TypeError("a Number needs both bounds (an open upper bound needs allow_inf)")
        super().__init__(low, high, min_open=low_open, max_open=high_open)
        self.allow_inf = allow_inf

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if math.isnan(number) or (math.isinf(number) and not self.allow_inf):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return super().convert(number, param, ctx)

    def _describe_range(self) -> str:
        if self.min is None:  # refused by __init__
            raise TypeError("a Number needs a lower bound")
        low = f"{_g(float(self.min))}{'<' if self.min_open else '<='}"
        if self.max is None:
            return f"x{'>' if self.min_open else '>='}{_g(float(self.min))}"
        return f"{low}x{'<' if self.max_open else '<='}{_g(float(self.max))}"

    def describe_range(self) -> str:
        """The range as ``--help`` shows it: ``0<x<=1000``."""
        return self._describe_range()


class Integer(click.IntRange):
    """An integer in ``[low, high]`` (both required), shown in ``--help``."""

    name = "integer"

    def __init__(self, low: int, high: int):
        super().__init__(int(low), int(high))

    def describe_range(self) -> str:
        """The range as ``--help`` shows it: ``1<=x<=4096``."""
        return self._describe_range()


class Size(click.IntRange):
    """``N`` or ``WxH`` (with ``pair``): integers from ``low`` to ``high`` (each side); parsed
    to ``N`` or ``(W, H)``. ``--help`` states the range of each number."""

    name = "integer"

    def __init__(self, high: int = IMAGE_SIDE, *, pair: bool = True, low: int = 1):
        super().__init__(int(low), int(high))
        self.pair = pair

    # click types an IntRange's value as int; a size may be a pair
    def convert(  # type: ignore[override]
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> int | tuple[int, int]:
        if isinstance(value, (int, tuple)):
            return value
        parts = str(value).strip().lower().split("x")
        try:
            numbers = [int(p) for p in parts]
        except ValueError:
            numbers = []
        if not 1 <= len(numbers) <= (2 if self.pair else 1):
            wanted = "N or WxH" if self.pair else "N"
            self.fail(f"{value!r} is not a size: expected {wanted} (whole numbers)", param, ctx)
        numbers = [super(Size, self).convert(n, param, ctx) for n in numbers]
        return numbers[0] if len(numbers) == 1 else (numbers[0], numbers[1])

    def describe_range(self) -> str:
        """The range of each number, as ``--help`` shows it."""
        return self._describe_range()


class Numbers(Number):
    """``count`` numbers (any of ``count`` when it is a tuple; any number of them when None)
    separated by ``sep``, each a :class:`Number` in the range given: ``YAW,PITCH,ROLL``,
    ``UxV`` or ``T1,T2,...``. Parsed to a tuple of floats; one number stands for all of them
    when ``repeat`` (``4`` is ``4x4``); with ``fractions``, ``1/250`` is a number."""

    name = "numbers"

    def __init__(
        self,
        low: float,
        high: float | None,
        *,
        count: int | tuple[int, ...] | None = 3,
        sep: str = ",",
        repeat: bool = False,
        fractions: bool = False,
        **kwargs: bool,
    ) -> None:
        super().__init__(low, high, **kwargs)
        self.counts = None if count is None else count if isinstance(count, tuple) else (count,)
        self.sep = sep
        self.repeat = repeat
        self.fractions = fractions

    # click types a FloatRange's value as float; this type parses several
    def convert(  # type: ignore[override]
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[float, ...]:
        if isinstance(value, tuple):
            return value
        parts = str(value).strip().lower().split(self.sep)
        if self.counts is not None:
            counts = (*self.counts, 1) if self.repeat else self.counts
            if len(parts) not in counts:
                wanted = " or ".join(map(str, sorted(set(counts))))
                if param is not None and param.metavar:
                    wanted = f"{param.metavar}, {wanted}"
                self.fail(
                    f"{value!r}: expected {wanted} numbers separated by {self.sep!r}", param, ctx
                )
        numbers = tuple(
            super(Numbers, self).convert(self._number(p.strip(), param, ctx), param, ctx)
            for p in parts
        )
        if self.counts is not None and len(numbers) == 1 and self.repeat:
            return numbers * max(self.counts)
        return numbers

    def _number(
        self, text: str, param: click.Parameter | None, ctx: click.Context | None
    ) -> str | float:
        if not self.fractions or "/" not in text:
            return text
        top, _, bottom = text.partition("/")
        try:
            return float(top) / float(bottom)
        except (ValueError, ZeroDivisionError, OverflowError):
            self.fail(f"{text!r} is not a number or a fraction like 1/250", param, ctx)


class Direction(Numbers):
    """A direction: ``+X``, ``-Y``, ``Z`` ... or ``x,y,z`` (finite, not all zero, each in
    [-1e6, 1e6]); parsed to a unit 3-tuple of floats."""

    name = "direction"
    _AXES = {"x": 0, "y": 1, "z": 2}

    def __init__(self) -> None:
        super().__init__(-1e6, 1e6, count=3)

    # click types a FloatRange's value as float; this type parses several
    def convert(  # type: ignore[override]
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[float, ...]:
        if isinstance(value, tuple):
            return value
        m = re.fullmatch(r"\s*([+-]?)([xyz])\s*", str(value).lower())
        if m:
            axis = [0.0, 0.0, 0.0]
            axis[self._AXES[m[2]]] = -1.0 if m[1] == "-" else 1.0
            return tuple(axis)
        import numpy as np  # not at the top: --version and --help load no numpy

        v = np.array(super().convert(value, param, ctx))
        length = float(np.linalg.norm(v))
        if length == 0:
            self.fail(
                f"{value!r} is not a direction: use +X, -X, +Y, -Y, +Z, -Z or x,y,z", param, ctx
            )
        return tuple(float(c) for c in v / length)


class Exposure(Number):
    """An exposure in stops (EV), finite and within ``[-64, 64]`` (2^64 spans any float32
    picture), or one of ``words`` (``auto``)."""

    name = "exposure"

    def __init__(self, words: tuple[str, ...] = ("auto",), limit: float = 64):
        super().__init__(-limit, limit)
        self.words = words

    # click types a FloatRange's value as float; an exposure may be a word (auto)
    def convert(  # type: ignore[override]
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float | str:
        if isinstance(value, str) and value.strip().lower() in self.words:
            return value.strip().lower()
        try:
            float(value)
        except (TypeError, ValueError):
            words = "".join(f" or {w!r}" for w in self.words)
            self.fail(f"{value!r} is not an exposure: a number of stops (EV){words}", param, ctx)
        return super().convert(value, param, ctx)


class Fields(click.ParamType):
    """Numbers separated by ``sep``, each of its own :class:`Number` type (``fields``, by
    name, in order), the first ``required`` of them needed: ``A:L[:DIR[:SPEED]]``. Parsed to
    a tuple of floats. ``--help`` must state :meth:`describe_range` (click cannot)."""

    name = "numbers"

    def __init__(self, fields: dict[str, Number], *, sep: str = ":", required: int = 1):
        self.fields = fields
        self.sep = sep
        self.required = required

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[float, ...]:
        if isinstance(value, tuple):
            return value
        parts = str(value).strip().split(self.sep)
        if not self.required <= len(parts) <= len(self.fields):
            self.fail(
                f"{value!r}: expected {self.sep.join(self.fields)} ({self.required} to "
                f"{len(self.fields)} numbers)",
                param,
                ctx,
            )
        out = []
        for (name, kind), text in zip(self.fields.items(), parts, strict=False):
            try:
                out.append(kind.convert(text.strip(), param, ctx))
            except click.BadParameter as e:
                self.fail(f"{name} in {value!r}: {e.message}", param, ctx)
        return tuple(out)

    def describe_range(self) -> str:
        """``amplitude 0<=x<=100, wavelength 0<x<=1e+04, ...``."""
        return ", ".join(f"{name} {kind.describe_range()}" for name, kind in self.fields.items())


class MemorySize(click.ParamType):
    """A memory bound: ``2GB``, ``1.5 GiB``, ``512M``, 4 MiB to 1 PB (the one parser,
    :func:`bakeshop.huge.memory.parse_memory`, that ``BAKESHOP_MEMORY`` goes through too)."""

    name = "size"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> int | str:
        from bakeshop.huge.memory import parse_memory

        try:
            parse_memory(value)
        except ArgumentError as e:
            self.fail(e.reason, param, ctx)
        return value if isinstance(value, int) else str(value)

    def describe_range(self) -> str:
        """The range, as the option's help states it."""
        return "4 MiB to 1 PB"
