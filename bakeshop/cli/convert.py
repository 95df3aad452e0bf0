"""``bakeshop convert``: any image format to any other."""

from __future__ import annotations

import click
import numpy as np

from bakeshop.cli._common import (
    OUTPUT,
    SOURCE,
    Exposure,
    is_ldr,
    parse_options,
    refuse_overwriting_inputs,
    writer_option,
)
from bakeshop.errors import ArgumentError


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=SOURCE)
@click.argument("target", type=OUTPUT)
@click.option(
    "--exposure",
    "-e",
    type=Exposure(words=()),
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
      bakeshop convert big.pfm big.zarr

    Between the formats that stream (.pfm, .hdr, .exr, .tif, .zarr), an image larger than
    memory is converted strip by strip: a .zarr store (zarr v3, 256x256 chunks) is the native
    form of huge images for bakeshop and its dask workers (docs/huge-images.md).
    """
    from bakeshop.image import exposure as apply_exposure
    from bakeshop.image import srgb_decode as decode
    from bakeshop.image import srgb_encode
    from bakeshop.io import ALPHA_EXTENSIONS, read_image, write_image

    refuse_overwriting_inputs(target, source)
    writer_options = parse_options(options)
    if _streams(source, target):
        _convert_strips(source, target, exposure, linear, srgb_decode, writer_options)
        return
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


#: formats converted strip by strip (images larger than memory).
_STREAMED = (".pfm", ".hdr", ".pic", ".rgbe", ".exr", ".tif", ".tiff", ".zarr")


def _streams(source, target) -> bool:
    """Strip by strip when a .zarr or .tif is involved, or both ends stream and the image is
    larger than a quarter of the memory available."""
    s, t = source.suffix.lower(), target.suffix.lower()
    if s not in _STREAMED or t not in _STREAMED:
        if s in (".zarr", ".tif", ".tiff") or t in (".zarr", ".tif", ".tiff"):
            raise ArgumentError(
                f"{source.suffix} to {target.suffix}: a .zarr or .tif converts from and to "
                ".pfm, .hdr, .exr, .tif and .zarr",
                target,
            )
        return False
    if s in (".zarr", ".tif", ".tiff") or t in (".zarr", ".tif", ".tiff"):
        return True
    from bakeshop.huge.memory import resolve_memory
    from bakeshop.io.stream import open_image

    try:
        return open_image(source).nbytes > resolve_memory(None) // 4
    except Exception:  # the in-memory reader says what is wrong with the file
        return False


def _convert_strips(source, target, exposure, linear, srgb_decode, options) -> None:
    from bakeshop import progress
    from bakeshop.huge.memory import resolve_memory
    from bakeshop.io.stream import open_image, write_strips

    if linear or srgb_decode:
        raise ArgumentError("--linear and --srgb-decode apply to 8/16-bit formats", target)
    reader = open_image(source)
    h, w, c = reader.shape
    if c == 4 and target.suffix.lower() in (".pfm", ".hdr"):
        c = 3
    rows = max(1, min(h, resolve_memory(None) // 8 // (w * reader.shape[2] * 4)))
    rows = max(rows - rows % 256, min(rows, 256))  # whole rows of zarr and TIFF chunks
    scale = np.float32(2.0**exposure)

    def strips():
        for top in progress.track(range(0, h, rows), f"converting {source.name}"):
            block = reader.read((top, min(top + rows, h)))[:, :, :c]
            yield block * scale if exposure else block

    write_strips(target, (h, w, c), strips(), **options)
    how = f" (exposure {exposure:+g} EV)" if exposure else ""
    click.echo(f"wrote {target}: {w}x{h}x{c} by strips of {rows} rows{how}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(convert)
