"""``bakeshop convert``: any image format to any other."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import click
import numpy as np

from bakeshop.cli._common import (
    RGB_ONLY,
    PictureRule,
    alpha_option,
    fit_alpha,
    parse_options,
    picture_options,
    write_any,
    writer_option,
)
from bakeshop.cli._paths import OUTPUT, SOURCE, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError
from bakeshop.io import stored_bits

#: the codecs' options, ``-O KEY=VALUE``, of every command that writes any image format.
codec_options = writer_option(
    "A writer option, repeatable: EXR pixel_type=half|float, compression=zip|piz|...; "
    "PNG bits=8|16; JPEG quality=1..100; TGA rle=true; PFM byteorder=<|>."
)


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=SOURCE)
@click.argument("target", type=OUTPUT)
@click.option(
    "--srgb-decode",
    is_flag=True,
    help="Reading an 8/16-bit format into a float one: decode sRGB to linear values.",
)
@codec_options
@alpha_option
@picture_options()
def convert(
    source: Path,
    target: Path,
    srgb_decode: bool,
    options: tuple[str, ...],
    alpha: str | None,
    picture: PictureRule,
) -> None:
    """Convert SOURCE to TARGET, any supported format to any other (by extension: .hdr .pfm
    .exr .tga .png .jpg; a 2-D .dds/.ktx/.ktx2 texture's level 0 as SOURCE).

    Float to 8/16-bit (for example .hdr to .png) follows the display rule of every command
    (docs/tonemap.md): --exposure (default 0; a float TARGET is scaled by it too), --tonemap
    (default none: clamp to [0, 1]), sRGB encoding (IEC 61966-2-1; --linear skips it), 8 bits
    (--bits 16 for more; 16 by default for --linear), said in one line and recorded in the
    file. 8/16-bit files are read as their stored values scaled to [0, 1], never linearised
    unless --srgb-decode; between 8/16-bit formats the values are kept as stored and the depth
    follows SOURCE (a 16-bit PNG stays 16-bit; TGA and JPEG hold 8, which is said). Where the
    target stores no alpha (.hdr, .pfm, .jpg), an alpha of 1 everywhere is dropped with a
    note, and any other needs --alpha drop or --alpha premultiply.

    \b
    Example:
      bakeshop convert probe.hdr probe.exr -O compression=piz
      bakeshop convert probe.exr preview.png --exposure -2
      bakeshop convert probe.exr preview.jpg --exposure auto --tonemap aces
      bakeshop convert albedo.png albedo.exr --srgb-decode
      bakeshop convert big.pfm big.zarr

    Between the formats that stream (.pfm, .hdr, .exr, .tif, .zarr), an image larger than
    memory is converted strip by strip: a .zarr store (zarr v3, 256x256 chunks) is the native
    form of huge images for bakeshop and its dask workers (docs/huge-images.md).
    """
    from bakeshop.image import srgb_decode as decode

    refuse_overwriting_inputs(target, source)
    writer_options = parse_options(options)
    if _streams(source, target):
        _convert_strips(source, target, picture, srgb_decode, writer_options, alpha)
        return
    image, meta = _read(source)
    bits = stored_bits(meta)
    steps = []
    if image.shape[2] == 4 and alpha is not None:
        steps.append(f"alpha: {alpha}")
    image = fit_alpha(image, alpha, source, target)
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


def _read(source: Path) -> tuple[np.ndarray, dict]:
    """The image of ``source`` with its metadata: a 2-D texture container (.dds, .ktx, .ktx2)
    gives its level 0; a cube map or a texture array is refused (remap reads cubes)."""
    from bakeshop.io import read_container, read_image
    from bakeshop.io.containers import is_container

    if not is_container(source):
        return read_image(source, with_metadata=True)
    mips, meta = read_container(source)
    if meta.get("cube") or mips[0].ndim != 3:
        what = "a cube map" if meta.get("cube") else "a texture array"
        raise ArgumentError(
            f"{what} is not one picture; bakeshop remap turns a cube map into one, and bakeshop "
            "compress writes it as another container",
            source,
        )
    return mips[0], meta


#: formats converted strip by strip (images larger than memory).
_STREAMED = (".pfm", ".hdr", ".pic", ".rgbe", ".exr", ".tif", ".tiff", ".zarr")


def _streams(source: Path, target: Path) -> bool:
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


def _convert_strips(
    source: Path,
    target: Path,
    picture: PictureRule,
    srgb_decode: bool,
    options: dict[str, Any],
    alpha: str | None,
) -> None:
    from bakeshop import progress
    from bakeshop.huge.memory import resolve_memory
    from bakeshop.io.stream import open_image, write_strips

    if picture.linear or srgb_decode:
        raise ArgumentError("--linear and --srgb-decode apply to 8/16-bit formats", target)
    if not isinstance(picture.ev, float) or picture.operator != "none":
        raise ArgumentError(
            "by strips, a float file takes a number of stops of --exposure and no --tonemap",
            target,
        )
    exposure = picture.ev
    reader = open_image(source)
    h, w, c = reader.shape
    if c == 4 and target.suffix.lower() in RGB_ONLY:
        c = 3
    rows = max(1, min(h, resolve_memory(None) // 8 // (w * reader.shape[2] * 4)))
    rows = max(rows - rows % 256, min(rows, 256))  # whole rows of zarr and TIFF chunks
    scale = np.float32(2.0**exposure)

    def strips() -> Iterator[np.ndarray]:
        for top in progress.track(range(0, h, rows), f"converting {source.name}"):
            block = fit_alpha(
                reader.read((top, min(top + rows, h))), alpha, source, target, note=top == 0
            )
            yield block * scale if exposure else block

    write_strips(target, (h, w, c), strips(), **options)
    how = f" (exposure {exposure:+g} EV)" if exposure else ""
    click.echo(f"wrote {target}: {w}x{h}x{c} by strips of {rows} rows{how}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(convert)
