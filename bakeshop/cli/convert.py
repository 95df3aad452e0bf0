"""``bakeshop convert``: any image format to any other."""

from __future__ import annotations

import click
import numpy as np

from bakeshop.cli._common import (
    INPUT,
    OUTPUT,
    is_ldr,
    parse_options,
    refuse_overwriting_inputs,
    writer_option,
)
from bakeshop.errors import ArgumentError


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=INPUT)
@click.argument("target", type=OUTPUT)
@click.option(
    "--exposure",
    "-e",
    type=float,
    default=0.0,
    show_default=True,
    help="Exposure in EV (stops) applied before writing: values are multiplied by 2^EV.",
)
@click.option(
    "--linear",
    is_flag=True,
    help="Writing an 8/16-bit format: skip the sRGB encoding (write clamped linear values).",
)
@click.option(
    "--srgb-decode",
    is_flag=True,
    help="Reading an 8/16-bit format into a float one: decode sRGB to linear values.",
)
@writer_option(
    "A writer option, repeatable: EXR pixel_type=half|float, compression=zip|piz|...; "
    "PNG bits=8|16; JPEG quality=1..100; TGA rle=true; PFM byteorder=<|>."
)
def convert(source, target, exposure, linear, srgb_decode, options):
    """Convert SOURCE to TARGET, any supported format to any other (by extension: .hdr .pfm
    .exr .tga .png .jpg).

    Float to 8/16-bit (for example .hdr to .png): applies --exposure, clamps to [0, 1] and
    sRGB-encodes (IEC 61966-2-1), and says so; --linear skips the encoding. 8/16-bit files are
    read as their stored values scaled to [0, 1], never linearised unless --srgb-decode. Alpha
    is dropped, with a note, when the target format stores none (.hdr, .pfm, .jpg).

    \b
    Example:
      bakeshop convert probe.hdr probe.exr -O compression=piz
      bakeshop convert probe.exr preview.png --exposure -2
      bakeshop convert albedo.png albedo.exr --srgb-decode
    """
    from bakeshop.image import exposure as apply_exposure
    from bakeshop.image import srgb_decode as decode
    from bakeshop.image import srgb_encode
    from bakeshop.io import ALPHA_EXTENSIONS, read_image, write_image

    refuse_overwriting_inputs(target, source)
    writer_options = parse_options(options)
    src_hdr = not is_ldr(source)
    dst_hdr = not is_ldr(target)
    image = read_image(source)
    steps = []
    if image.shape[2] == 4 and target.suffix.lower() not in ALPHA_EXTENSIONS:
        image = image[:, :, :3]
        steps.append(f"alpha dropped: {target.suffix} stores none")
    if srgb_decode:
        if src_hdr:
            raise ArgumentError("--srgb-decode applies to 8/16-bit inputs only", source)
        image = decode(image)
        steps.append("sRGB-decoded")
    if exposure:
        image = apply_exposure(image, exposure)
        steps.append(f"exposure {exposure:+g} EV")
    if not dst_hdr:
        image = np.clip(np.nan_to_num(image, nan=0.0, posinf=1.0), 0.0, 1.0)
        steps.append("clamped to [0, 1]")
        if src_hdr and not linear:
            image = srgb_encode(image)
            steps.append("sRGB-encoded")
    write_image(target, image, **writer_options)
    h, w, c = image.shape
    how = f" ({', '.join(steps)})" if steps else ""
    click.echo(f"wrote {target}: {w}x{h}x{c}{how}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(convert)
