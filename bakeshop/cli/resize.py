"""``bakeshop resize``: energy-preserving resize of an image."""

from __future__ import annotations

from pathlib import Path

import click

from bakeshop.cli._common import PictureRule, alpha_option, fit_alpha, picture_options, write_any
from bakeshop.cli._huge import chunked, engine, memory_option, open_fitted, scheduler_option
from bakeshop.cli._numbers import Size
from bakeshop.cli._paths import OUTPUT, SOURCE, parse_size, refuse_overwriting_inputs
from bakeshop.io import stored_bits


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=SOURCE)
@click.argument("target", type=OUTPUT)
@click.option(
    "--size",
    required=True,
    type=Size(),
    metavar="WxH",
    help="Output size; a single W keeps the aspect ratio (height rounded).",
)
@alpha_option
@picture_options()
@memory_option
@scheduler_option
def resize(
    source: Path,
    target: Path,
    size: int | tuple[int, int],
    alpha: str | None,
    picture: PictureRule,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    """Resize SOURCE to TARGET with energy-preserving area resampling.

    Each output texel is the exact mean of the input over its footprint (the exact box filter
    for integer factors, area-weighted otherwise), so the image's mean is preserved to float32
    rounding: the way to bring huge artist images down to real-time sizes without losing or
    gaining light. Values are resampled as stored: resize linear (HDR) data, not sRGB pictures.
    An 8/16-bit TARGET keeps the depth of an 8/16-bit SOURCE; from float data it follows the
    display rule of every command (docs/tonemap.md: --exposure, --tonemap, sRGB, --bits).

    Images larger than memory (.pfm, .hdr, .exr, .tif, .zarr) are resized block by block within
    --memory, bit-identical to the in-memory result; a .zarr, .tif, .pfm, .hdr or .exr output is
    written by strips, so it may be larger than memory too (docs/huge-images.md).

    \b
    Example:
      bakeshop resize probe_12k.exr probe_4k.exr --size 4096x2048
      bakeshop resize probe.hdr small.hdr --size 360
      bakeshop resize pano_64k.zarr pano_8k.exr --size 8192 --memory 2GB
    """
    from bakeshop.image import resize_area
    from bakeshop.io import read_image
    from bakeshop.resources import MemoryLimitError

    refuse_overwriting_inputs(target, source)
    wanted = parse_size(size)
    if chunked(source, memory, scheduler):
        _resize_chunked(source, target, wanted, alpha, memory, scheduler)
        return
    image, meta = read_image(source, with_metadata=True)
    image = fit_alpha(image, alpha, source, target)
    h, w = image.shape[:2]
    if isinstance(wanted, int):
        wanted = (wanted, max(1, round(h * wanted / w)))
    try:
        out = resize_area(image, wanted)
    except MemoryLimitError as e:  # an output larger than memory: by strips, or refused
        if target.suffix.lower() not in _STRIPS:
            e.reason += f" (a {', '.join(_STRIPS)} output is written by strips, past memory)"
            raise
        del image
        _resize_chunked(source, target, wanted, alpha, memory, scheduler)
        return
    bits = stored_bits(meta)
    line = write_any(target, out, picture, inputs=[bits], linear=bits is None)
    click.echo(
        f"wrote {target}: {w}x{h} -> {wanted[0]}x{wanted[1]} (mean preserved)"
        + (f"; {line}" if line else "")
    )


#: outputs that the chunked resize writes strip by strip (larger than memory).
_STRIPS = (".zarr", ".tif", ".tiff", ".pfm", ".hdr", ".exr")


def _resize_chunked(
    source: Path,
    target: Path,
    wanted: int | tuple[int, int],
    alpha: str | None,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    from bakeshop.huge import resize_to_file

    reader = open_fitted(source, alpha, target)
    h, w, _ = reader.shape
    if isinstance(wanted, int):
        wanted = (wanted, max(1, round(h * wanted / w)))
    with engine(memory, scheduler) as eng:
        if target.suffix.lower() in _STRIPS:
            resize_to_file(reader, target, wanted, engine=eng)
        else:
            from bakeshop.huge import resize as resize_chunked
            from bakeshop.io import write_image

            write_image(target, resize_chunked(reader, wanted, engine=eng))
    click.echo(f"wrote {target}: {w}x{h} -> {wanted[0]}x{wanted[1]} (mean preserved, chunked)")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(resize)
