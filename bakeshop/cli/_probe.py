"""Options and helpers shared by the commands that read a probe (``irradiance``, ``sun``,
``dims``, ``prefilter``, ``bake-probe``, ``fresnel``)."""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from bakeshop.cli._numbers import Integer, Size
from bakeshop.cli._paths import parse_size
from bakeshop.errors import ArgumentError, with_article
from bakeshop.io.environment import LAYOUT_ENVMAPS, is_cube, read_environment
from bakeshop.sphere import FILE_LAYOUTS

if TYPE_CHECKING:
    import numpy as np

    from bakeshop.io.stream import Reader
    from bakeshop.light import Sun

#: GGX levels when no --mips is given (fewer where the level-0 cube has fewer).
DEFAULT_MIPS = 9


def chain_mips(mips: int | None, size: int, size_option: str, path: str | os.PathLike) -> int:
    """--mips, by default ``min(DEFAULT_MIPS, size.bit_length())``: the levels a cube of
    ``size`` texels has; more is refused, naming ``path``, before anything is read."""
    top = size.bit_length()
    if mips is None:
        return min(DEFAULT_MIPS, top)
    if mips > top:
        raise ArgumentError(
            f"--mips {mips}: {with_article(size)}-texel cube has 1..{top} mip levels; "
            f"lower --mips or raise {size_option}",
            path,
        )
    return mips


#: output texels of a DIM when no --size is given (360x180, the pipeline's latlong).
DEFAULT_TEXELS = 360 * 180


from_option = click.option(
    "--from",
    "src_layout",
    type=click.Choice(FILE_LAYOUTS),
    help="Layout of IN; read from an EXR's envmap attribute (openexr-latlong, openexr-cube), "
    "else guessed from its shape when only one fits (2:1 is latlong). IN may also be a "
    ".dds/.ktx/.ktx2 cube or six files with {face}.",
)


to_option = click.option(
    "--to",
    "dst_layout",
    type=click.Choice(FILE_LAYOUTS),
    default="latlong",
    show_default=True,
    help="Layout of the DIM.",
)


size_option = click.option(
    "--size",
    type=Size(8192),
    metavar="N|WxH",
    help="Size of the DIM as its layout reads it (latlong WxH or height N; face edge for "
    "crosses and strips; edge for square layouts). Default: 360x180, or as many texels.",
)


method_option = click.option(
    "--method",
    type=click.Choice(("auto", "exact", "sh")),
    default="auto",
    show_default=True,
    help="auto: exact to 0.1% RMS / 0.5% max in seconds; exact: every texel for every "
    "output texel (slow: the reference); sh: spherical harmonics to --order.",
)


order_option = click.option(
    "--order",
    type=Integer(0, 64),
    default=2,
    show_default=True,
    help="SH order for --method sh, --sh-json and --shader (2: 9 coefficients per channel).",
)


def timed(
    compute: Callable[..., Any],
    image: np.ndarray | Reader,
    layout: str,
    dst_layout: str,
    size: int | tuple[int, int] | None,
    method: str,
    order: int,
    window: str = "minimal",
) -> tuple[Any, float]:
    """``(compute(image, layout, to=..., ...), seconds)``: the DIM or the DIM pair, timed (of an
    image in memory, or of a chunked reader)."""
    started = time.perf_counter()
    result = compute(
        image,
        layout,
        to=dst_layout,
        size=output_size(dst_layout, size),
        method=method,
        order=order,
        window=window,
    )
    return result, time.perf_counter() - started


def output_size(layout: str, size: str | int | tuple[int, int] | None) -> tuple[int, int] | int:
    from bakeshop.sphere import layout as get_layout

    if size is not None:
        return parse_size(size)
    if layout == "latlong":
        return (360, 180)
    return get_layout(layout).default_size(DEFAULT_TEXELS)


def sun_lines(sun: Sun) -> list[str]:
    x, y, z = sun.direction
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, y))))
    azimuth = math.degrees(math.atan2(x, -z))  # 0 forward (-Z), 90 right (+X)
    rgb = ", ".join(f"{v:.4g}" for v in sun.color)
    irr = ", ".join(f"{v:.4g}" for v in sun.irradiance)
    return [
        f"direction          [{x:.5f}, {y:.5f}, {z:.5f}]  "
        f"(elevation {elevation:.2f} deg, azimuth {azimuth:.2f} deg from -Z towards +X)",
        f"angular radius     {sun.angular_radius_deg:.3f} deg",
        f"solid angle        {sun.solid_angle_sr:.4g} sr",
        f"colour             [{rgb}] (mean radiance above the sky)",
        f"irradiance         [{irr}] at normal incidence",
        f"removed region     {sun.mask_radius_deg:.2f} deg radius",
    ]


def read_probe(
    source: Path | None,
    layout: str | None,
    *,
    convention: str = "opengl",
    with_metadata: bool = False,
) -> tuple[Any, ...]:
    """``(image, layout, path)`` of the input probe (and its file's metadata with
    ``with_metadata``); the embedded default when ``source`` is None (see
    :func:`bakeshop.io.read_environment`)."""
    from bakeshop import progress
    from bakeshop.data import default_probe_path

    source = default_probe_path() if source is None else source
    with progress.step(f"reading {source.name}"):
        (image, layout, _), meta = read_environment(
            source, layout, convention=convention, with_metadata=True
        )
    return (image, layout, source, meta) if with_metadata else (image, layout, source)


def picture_layout(layout: str) -> str:
    """The layout a probe's picture (a painted probe) is written in: a cube as a vertical
    cross (:func:`bakeshop.io.environment.as_picture`), any other layout as it is."""
    return "cross-vertical" if is_cube(layout) else layout


def check_picture_format(layout: str, fmt: str, source: str | os.PathLike) -> None:
    """Refuse, before any work, to write a probe picture in OpenEXR's layouts to a format that
    cannot say so (only an .exr's envmap attribute can)."""
    if layout in LAYOUT_ENVMAPS and fmt != "exr":
        raise ArgumentError(
            f"the probe is {layout} (OpenEXR's mapping, from its envmap attribute), which only "
            f"an .exr file can say: use --format exr, or convert it first (bakeshop remap "
            f"{source} probe.hdr --to latlong)",
            source,
        )


window_option = click.option(
    "--window",
    type=click.Choice(("minimal", "hanning", "lanczos", "none")),
    default="minimal",
    show_default=True,
    help="Window of SH irradiance against ringing (method sh, --sh-json, --shader): minimal is "
    "Sloan's least window that makes it nowhere negative (none when it already is); hanning "
    "and lanczos are fixed windows of width order+1.",
)
