"""The ``bakeshop water`` group and the number type its options share."""

from __future__ import annotations

import math

import click

CONTEXT = {"max_content_width": 100}

#: Largest amount of frame data an atlas or array output may gather in memory, bytes.
GATHER_LIMIT = 4 << 30


class Number(click.ParamType):
    """A finite float in [low, high] (open ends by flag); NaN and infinities are refused."""

    name = "number"

    def __init__(self, low=None, high=None, *, low_open=False, high_open=False, allow_inf=False):
        self.low, self.high = low, high
        self.low_open, self.high_open = low_open, high_open
        self.allow_inf = allow_inf

    def convert(self, value, param, ctx):
        """The value as a float within the bounds, or a click failure naming them."""
        if isinstance(value, float):
            v = value
        else:
            try:
                v = float(value)
            except (TypeError, ValueError):
                self.fail(f"{value!r} is not a number", param, ctx)
        if math.isnan(v) or (math.isinf(v) and not self.allow_inf):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        if self.low is not None and (v < self.low or (self.low_open and v == self.low)):
            self.fail(f"{value!r} is below the range {self._range()}", param, ctx)
        if self.high is not None and (v > self.high or (self.high_open and v == self.high)):
            self.fail(f"{value!r} is above the range {self._range()}", param, ctx)
        return v

    def _range(self) -> str:
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        return f"{'(' if self.low_open else '['}{lo}, {hi}{')' if self.high_open else ']'}"


def _int_range(low, high):
    return click.IntRange(low, high)


@click.group(context_settings=CONTEXT)
def water():
    """Water textures an engine loads: tileable, time-looping ocean normal maps (with heights,
    slopes, displacement and foam), impact ripples, and underwater murk constants.

    Every command writes a JSON sidecar (units SI: metres, seconds) and preview PNGs.

    \b
    Example:
      bakeshop water ocean ocean/ --wind 8 --size 64 --resolution 256 --period 8
      bakeshop water ripples ripples/ --drop-diameter 0.004 --drop-speed 6
      bakeshop water murk murk/ --water-type IB
    """
