"""``bakeshop resize``: energy-preserving resize of an image."""

from __future__ import annotations

import click

from bakeshop.cli._common import (
    INPUT,
    OUTPUT,
    parse_size,
    refuse_overwriting_inputs,
)


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=INPUT)
@click.argument("target", type=OUTPUT)
@click.option(
    "--size",
    required=True,
    metavar="WxH",
    help="Output size; a single W keeps the aspect ratio (height rounded).",
)
def resize(source, target, size):
    """Resize SOURCE to TARGET with energy-preserving area resampling.

    Each output texel is the exact mean of the input over its footprint (the exact box filter
    for integer factors, area-weighted otherwise), so the image's mean is preserved to float32
    rounding: the way to bring huge artist images down to real-time sizes without losing or
    gaining light. Values are resampled as stored: resize linear (HDR) data, not sRGB pictures.

    \b
    Example:
      bakeshop resize probe_12k.exr probe_4k.exr --size 4096x2048
      bakeshop resize probe.hdr small.hdr --size 360
    """
    from bakeshop.image import resize_area
    from bakeshop.io import read_image, write_image

    refuse_overwriting_inputs(target, source)
    wanted = parse_size(size)
    image = read_image(source)
    h, w = image.shape[:2]
    if isinstance(wanted, int):
        wanted = (wanted, max(1, round(h * wanted / w)))
    out = resize_area(image, wanted)
    write_image(target, out)
    click.echo(f"wrote {target}: {w}x{h} -> {wanted[0]}x{wanted[1]} (mean preserved)")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(resize)
