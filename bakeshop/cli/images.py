"""``bakeshop info``, ``convert`` and ``resize``: look at images and move them between formats."""

from __future__ import annotations

import json
from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import (
    INPUT,
    OUTPUT,
    is_ldr,
    parse_options,
    parse_size,
    refuse_overwriting_inputs,
    writer_option,
)
from bakeshop.errors import ArgumentError

DEFAULT_PROBE = Path(__file__).resolve().parents[1] / "data" / "default_probe.hdr"


@click.command(context_settings={"max_content_width": 100})
@click.argument("files", nargs=-1, type=INPUT)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object per file instead.")
def info(files: tuple[Path, ...], as_json: bool):
    """Describe image files: format, size, channels, stored type, per-channel min/max/mean,
    NaN/Inf counts, dynamic range in stops, and a guess of the panorama layout from the shape
    (labelled as a guess). Without FILES, describes the embedded default probe.

    \b
    Example:
      bakeshop info probe.hdr normals.png
      bakeshop info --json probe.exr | jq .dynamic_range_stops
    """
    from bakeshop.io import read_image
    from bakeshop.sphere import guess_layout
    from bakeshop.statistics import describe

    for path in files or (DEFAULT_PROBE,):
        image, meta = read_image(path, with_metadata=True)
        stats = describe(image)
        h, w, c = image.shape
        report = {
            "file": str(path),
            "format": meta["format"],
            "width": w,
            "height": h,
            "channels": c,
            "stored": meta.get("stored"),
            **{k: stats[k] for k in ("channels", "nan", "inf", "dynamic_range_stops")},
            "layout_guess": guess_layout(h, w),
            "metadata": {k: v for k, v in meta.items() if k not in ("format", "stored")},
        }
        report["channel_stats"] = report.pop("channels")
        report["channels"] = c
        if as_json:
            click.echo(json.dumps(report, default=str))
        else:
            _print_info(report)


def _print_info(r: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console(soft_wrap=True)
    names = {1: "Y", 3: "RGB", 4: "RGBA"}.get(r["channels"], "?" * r["channels"])
    stops = r["dynamic_range_stops"]
    guess = ", ".join(r["layout_guess"]) or "none (not a panorama shape)"
    console.print(
        f"[bold]{r['file']}[/bold]: {r['format']}, {r['width']}x{r['height']}, {names}, "
        f"stored as {r['stored']}"
    )
    table = Table(box=None, padding=(0, 2), show_edge=False)
    for col in ("channel", "min", "max", "mean"):
        table.add_column(col, justify="right")
    for name, s in zip(names, r["channel_stats"], strict=True):
        table.add_row(
            name, *(f"{s[k]:.6g}" if s[k] is not None else "-" for k in ("min", "max", "mean"))
        )
    console.print(table)
    console.print(
        f"  NaN: {r['nan']}  Inf: {r['inf']}  dynamic range: "
        + (f"{stops:.1f} stops" if stops is not None else "n/a")
    )
    console.print(f"  layout (a guess from the shape): {guess}")
    for key, value in r["metadata"].items():
        console.print(f"  {key}: {value}")


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
    from bakeshop.io import ALPHA_EXTENSIONS, read_image, write_image
    from bakeshop.light.tonemap import exposure as apply_exposure
    from bakeshop.light.tonemap import srgb_decode as decode
    from bakeshop.light.tonemap import srgb_encode

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
    from bakeshop.io import read_image, write_image
    from bakeshop.resample import resize_area

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
    """Add ``info``, ``convert`` and ``resize`` to the root command group."""
    for command in (info, convert, resize):
        group.add_command(command)
