"""``bakeshop info``: what is in an image file or a texture container."""

from __future__ import annotations

import json
from pathlib import Path

import click

from bakeshop.cli._paths import INPUT


@click.command(context_settings={"max_content_width": 100})
@click.argument("files", nargs=-1, type=INPUT)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object per file instead.")
def info(files: tuple[Path, ...], as_json: bool) -> None:
    """Describe image files: format, size, channels, stored type, per-channel min/max/mean,
    NaN/Inf counts, dynamic range in stops, and a guess of the panorama layout from the shape
    (labelled as a guess). A .dds, .ktx or .ktx2 texture (block-compressed ones decoded) is
    described by its level 0, all six faces of a cube, with its levels. Without FILES,
    describes the embedded default probe.

    \b
    Example:
      bakeshop info probe.hdr normals.png
      bakeshop info --json probe.exr | jq .dynamic_range_stops
    """
    from bakeshop.data import default_probe_path
    from bakeshop.image import describe
    from bakeshop.io import read_container, read_image
    from bakeshop.io.containers import is_container
    from bakeshop.sphere import guess_layout

    for path in files or (default_probe_path(),):
        if is_container(path):
            mips, meta = read_container(path)
            image = mips[0].reshape(-1, *mips[0].shape[-2:])  # a cube's faces stacked
            meta = {k: v for k, v in meta.items() if not isinstance(v, (bytes, dict))}
            meta["levels"] = len(mips)
            if meta.get("cube"):
                meta["faces"] = "6 (stacked in OpenGL order +X -X +Y -Y +Z -Z above)"
        else:
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
            "layout_guess": ["cube"] if meta.get("cube") else guess_layout(h, w),
            "metadata": {k: v for k, v in meta.items() if k not in ("format", "stored")},
        }
        report["channel_stats"] = report.pop("channels")
        report["channels"] = c
        if as_json:
            click.echo(json.dumps(report, default=str))
        else:
            _print_info(report)


def _print_info(r: dict) -> None:
    """The report as text: a line for the file, a table of the channels' statistics, the rest
    one fact a line (plain click output: importing rich would add 0.05-0.07 s to a 0.3 s
    command)."""
    names = {1: "Y", 2: "RG", 3: "RGB", 4: "RGBA"}.get(r["channels"], "?" * r["channels"])
    stops = r["dynamic_range_stops"]
    guess = ", ".join(r["layout_guess"]) or "none (not a panorama shape)"
    click.echo(
        click.style(r["file"], bold=True) + f": {r['format']}, {r['width']}x{r['height']}, "
        f"{names}, stored as {r['stored']}"
    )
    rows = [("channel", "min", "max", "mean")] + [
        (name, *(f"{s[k]:.6g}" if s[k] is not None else "-" for k in ("min", "max", "mean")))
        for name, s in zip(names, r["channel_stats"], strict=True)
    ]
    widths = [max(len(row[i]) for row in rows) for i in range(4)]
    for row in rows:
        click.echo("  " + "    ".join(cell.rjust(w) for cell, w in zip(row, widths, strict=True)))
    click.echo(
        f"  NaN: {r['nan']}  Inf: {r['inf']}  dynamic range: "
        + (f"{stops:.1f} stops" if stops is not None else "n/a")
    )
    click.echo(f"  layout (a guess from the shape): {guess}")
    for key, value in r["metadata"].items():
        click.echo(f"  {key}: {value}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(info)
