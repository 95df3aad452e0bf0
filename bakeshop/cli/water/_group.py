"""The ``bakeshop water`` group and what its subcommands share."""

from __future__ import annotations

import click

CONTEXT = {"max_content_width": 100}

#: Largest amount of frame data an atlas or array output may gather in memory, bytes.
GATHER_LIMIT = 4 << 30
#: Bytes per texel and frame that a ripple flipbook holds: the normals and their packed copy.
RIPPLE_TEXEL_BYTES = 24


@click.group(context_settings=CONTEXT)
def water() -> None:
    """Water textures an engine loads: tileable, time-looping ocean normal maps (with heights,
    slopes, displacement and foam), impact ripples, and underwater murk constants.

    Every command writes a JSON sidecar (units SI: metres, seconds) and preview PNGs.

    \b
    Example:
      bakeshop water ocean ocean/ --wind 8 --size 64 --resolution 256 --period 8
      bakeshop water ripples ripples/ --drop-diameter 0.004 --drop-speed 6
      bakeshop water murk murk/ --water-type IB
    """
