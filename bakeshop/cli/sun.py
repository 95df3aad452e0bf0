"""``bakeshop sun``: find and measure the sun of a probe."""

from __future__ import annotations

import json
from pathlib import Path

import click

from bakeshop.cli._common import linearise, srgb_decode_option
from bakeshop.cli._paths import ENVIRONMENT
from bakeshop.cli._probe import (
    from_option,
    read_probe,
    sun_lines,
)


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@from_option
@click.option("--json", "as_json", is_flag=True, help="Print sun.json instead.")
@srgb_decode_option
def sun(source: Path, src_layout: str | None, as_json: bool, srgb_decode: bool) -> None:
    """Find the sun of the probe IN and print its direction, size, colour and irradiance.

    The sun is the brightest compact light that stands well above the sky around it and
    dominates every other compact light; overcast, indoor and dawn probes have none, and the
    command says so (with --json it prints {"sun": null}). Directions are unit [x, y, z] with
    +Y up, -Z forward, +X right.

    \b
    Example:
      bakeshop sun probe.hdr
      bakeshop sun probe.hdr --json > sun.json
    """
    from bakeshop.light.sun import find_sun

    image, layout, _, meta = read_probe(source, src_layout, with_metadata=True)
    image, _ = linearise(image, source, meta, srgb_decode)
    found = find_sun(image, layout)
    if as_json:
        click.echo(json.dumps({"sun": None} if found is None else found.to_dict(), indent=1))
    elif found is None:
        click.echo(f"{source}: no sun (no compact light stands out from the sky)")
    else:
        click.echo(f"{source}: sun found")
        for line in sun_lines(found):
            click.echo(f"  {line}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(sun)
