"""``bakeshop convert``: any image format to any other."""

from __future__ import annotations

import click

from bakeshop.cli._common import (
    INPUT,
    OUTPUT,
    parse_options,
    picture_options,
    refuse_overwriting_inputs,
    stored_bits,
    write_any,
    writer_option,
)
from bakeshop.errors import ArgumentError


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=INPUT)
@click.argument("target", type=OUTPUT)
@click.option(
    "--srgb-decode",
    is_flag=True,
    help="Reading an 8/16-bit format into a float one: decode sRGB to linear values.",
)
@writer_option(
    "A writer option, repeatable: EXR pixel_type=half|float, compression=zip|piz|...; "
    "PNG bits=8|16; JPEG quality=1..100; TGA rle=true; PFM byteorder=<|>."
)
@picture_options()
def convert(source, target, srgb_decode, options, picture):
    """Convert SOURCE to TARGET, any supported format to any other (by extension: .hdr .pfm
    .exr .tga .png .jpg).

    Float to 8/16-bit (for example .hdr to .png) follows the display rule of every command
    (docs/tonemap.md): --exposure (default 0; a float TARGET is scaled by it too), --tonemap
    (default none: clamp to [0, 1]), sRGB encoding (IEC 61966-2-1; --linear skips it), 8 bits
    (--bits 16 for more; 16 by default for --linear), said in one line and recorded in the
    file. 8/16-bit files are read as their stored values scaled to [0, 1], never linearised
    unless --srgb-decode; between 8/16-bit formats the values are kept as stored and the depth
    follows SOURCE (a 16-bit PNG stays 16-bit; TGA and JPEG hold 8, which is said). Alpha is
    dropped, with a note, when the target format stores none (.hdr, .pfm, .jpg).

    \b
    Example:
      bakeshop convert probe.hdr probe.exr -O compression=piz
      bakeshop convert probe.exr preview.png --exposure -2
      bakeshop convert probe.exr preview.jpg --exposure auto --tonemap aces
      bakeshop convert albedo.png albedo.exr --srgb-decode
    """
    from bakeshop.image import srgb_decode as decode
    from bakeshop.io import ALPHA_EXTENSIONS, read_image

    refuse_overwriting_inputs(target, source)
    writer_options = parse_options(options)
    image, meta = read_image(source, with_metadata=True)
    bits = stored_bits(meta)
    steps = []
    if image.shape[2] == 4 and target.suffix.lower() not in ALPHA_EXTENSIONS:
        image = image[:, :, :3]
        steps.append(f"alpha dropped: {target.suffix} stores none")
    if srgb_decode:
        if bits is None:
            raise ArgumentError("--srgb-decode applies to 8/16-bit inputs only", source)
        colour = min(image.shape[2], 3)
        image = image.copy()
        image[..., :colour] = decode(image[..., :colour])
        steps.append("sRGB-decoded")
    line = write_any(
        target,
        image,
        picture,
        inputs=[bits],
        linear=bits is None or srgb_decode,
        options=writer_options,
    )
    if line:
        steps.append(line)
    h, w, c = image.shape
    how = f" ({', '.join(steps)})" if steps else ""
    click.echo(f"wrote {target}: {w}x{h}x{c}{how}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(convert)
