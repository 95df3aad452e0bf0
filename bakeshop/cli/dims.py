"""``bakeshop dims``: the DIM pair of a probe (sun DIM, shadow DIM, shadow probe, sun)."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from bakeshop.cli._budget import check
from bakeshop.cli._common import (
    alpha_option,
    fit_alpha,
    float_format_option,
    linearise,
    out_dir_option,
    srgb_decode_option,
)
from bakeshop.cli._huge import chunked, engine, memory_option, open_fitted, scheduler_option
from bakeshop.cli._paths import ENVIRONMENT_SOURCE, refuse_overwriting_inputs
from bakeshop.cli._probe import (
    check_picture_format,
    from_option,
    method_option,
    order_option,
    output_size,
    picture_layout,
    read_probe,
    size_option,
    sun_lines,
    timed,
    to_option,
    window_option,
)
from bakeshop.errors import ArgumentError
from bakeshop.io.environment import as_picture, check_openexr_target, describe

if TYPE_CHECKING:
    from bakeshop.huge import HugeDimPair
    from bakeshop.light import DimPair


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT_SOURCE)
@out_dir_option("Directory for the outputs (created if missing).")
@from_option
@float_format_option("File format of the three images.")
@method_option
@order_option
@to_option
@size_option
@window_option
@srgb_decode_option
@alpha_option
@memory_option
@scheduler_option
def dims(
    source: Path,
    out_dir: Path,
    src_layout: str | None,
    fmt: str,
    method: str,
    order: int,
    dst_layout: str,
    size: int | tuple[int, int] | None,
    window: str,
    srgb_decode: bool,
    alpha: str | None,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    """Make the DIM pair of the probe IN: sun_dim, shadow_dim, shadow_probe and sun.json.

    The sun is found and painted out of the probe (shadow_probe, same layout and size as IN,
    a vertical cross for a cube);
    shadow_dim is the DIM of the painted probe, for surfaces the shadow pass says are in
    shadow; sun_dim adds the sun's own light, for lit surfaces. sun.json gives the sun's
    direction for the shadow pass. A probe without a sun gives two equal DIMs and
    {"sun": null}.

    A latlong panorama larger than memory (.pfm, .hdr, .exr, .tif, .zarr; or with --memory or
    --scheduler) is read in two passes of strips within --memory, the sun found and measured at
    full resolution, and the shadow probe written by strips (docs/huge-images.md).

    \b
    Example:
      bakeshop dims probe.hdr --out-dir dims/
      bakeshop dims probe.exr -o dims/ --format exr --size 512x256
      bakeshop dims pano_32k.pfm -o dims/ --format exr --memory 1GB
    """
    from bakeshop import progress
    from bakeshop.io import write_environment, write_json
    from bakeshop.light import dim_pair, dim_pair_cost, sun_document

    names = {key: out_dir / f"{key}.{fmt}" for key in ("sun_dim", "shadow_dim", "shadow_probe")}
    for path in (*names.values(), out_dir / "sun.json"):  # before any work
        refuse_overwriting_inputs(path, source)
    check_openexr_target(names["sun_dim"], dst_layout)
    if chunked(source, memory, scheduler):
        if srgb_decode:
            raise ArgumentError("a panorama larger than memory is read as linear data", source)
        _dims_chunked(source, names, src_layout, (dst_layout, size, method, order, window),
                      alpha, memory, scheduler)  # fmt: skip
        return
    image, layout, _, meta = read_probe(source, src_layout, with_metadata=True)
    check_picture_format(layout, fmt, source)
    image, _ = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, *names.values())
    cost = dim_pair_cost(image.shape, layout, to=dst_layout, size=output_size(dst_layout, size),
                         method=method)  # fmt: skip
    check(cost, source, "--size", "--size or --method")
    # the decoded probe is this command's own: the shadow probe is painted into it, not a copy
    paint_in_place = functools.partial(dim_pair, copy=False)
    pair, elapsed = timed(paint_in_place, image, layout, dst_layout, size, method, order, window)
    with progress.step(f"writing {out_dir}"):
        out_dir.mkdir(parents=True, exist_ok=True)  # after every check: a refusal creates nothing
        write_environment(names["sun_dim"], pair.sun_dim, dst_layout)
        write_environment(names["shadow_dim"], pair.shadow_dim, dst_layout)
        write_environment(
            names["shadow_probe"], as_picture(pair.shadow_probe, layout), picture_layout(layout)
        )
        write_json(out_dir / "sun.json", sun_document(pair.sun))
    click.echo(
        f"wrote {out_dir}: sun_dim.{fmt} and shadow_dim.{fmt} "
        f"({describe(pair.sun_dim, dst_layout)}, method {method}), shadow_probe.{fmt} "
        f"({describe(image, layout)}), sun.json; {elapsed:.2f} s"
    )
    _report(pair)


def _report(pair: DimPair | HugeDimPair) -> None:
    if pair.sun is None:
        click.echo("  no sun: the two DIMs are equal and the probe is unchanged")
    else:
        for line in sun_lines(pair.sun):
            click.echo(f"  {line}")
        lit = float(np.mean(pair.sun_dim[..., :3]))
        shade = float(np.mean(pair.shadow_dim[..., :3]))
        click.echo(f"  mean DIM            lit {lit:.4g}, shadow {shade:.4g}")


def _dims_chunked(
    source: Path,
    names: dict[str, Path],
    src_layout: str | None,
    options: tuple[str, int | tuple[int, int] | None, str, int, str],
    alpha: str | None,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    """The DIM pair of a latlong panorama larger than memory (:func:`bakeshop.huge.dim_pair`)."""
    import functools

    from bakeshop import progress
    from bakeshop.huge import dim_pair as dim_pair_chunked
    from bakeshop.huge import write_shadow_probe
    from bakeshop.io import write_environment, write_json
    from bakeshop.light import sun_document

    dst_layout, size, method, order, window = options
    reader = open_fitted(source, alpha, *names.values())
    h, w, _ = reader.shape
    with engine(memory, scheduler) as eng:
        compute = functools.partial(dim_pair_chunked, engine=eng)
        pair, elapsed = timed(compute, reader, src_layout or "latlong", dst_layout, size, method,
                              order, window)  # fmt: skip
        with progress.step(f"writing {names['sun_dim'].parent}"):
            names["sun_dim"].parent.mkdir(parents=True, exist_ok=True)
            write_environment(names["sun_dim"], pair.sun_dim, dst_layout)
            write_environment(names["shadow_dim"], pair.shadow_dim, dst_layout)
            write_shadow_probe(reader, names["shadow_probe"], pair, engine=eng)
            write_json(names["sun_dim"].parent / "sun.json", sun_document(pair.sun))
    click.echo(
        f"wrote {names['sun_dim'].parent}: {names['sun_dim'].name} and "
        f"{names['shadow_dim'].name} ({describe(pair.sun_dim, dst_layout)}, method {method}), "
        f"{names['shadow_probe'].name} (latlong {w}x{h}, by strips), sun.json; {elapsed:.2f} s, "
        "chunked"
    )
    _report(pair)


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(dims)
