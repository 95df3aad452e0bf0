"""``bakeshop dims``: the DIM pair of a probe (sun DIM, shadow DIM, shadow probe, sun)."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import float_format_option, linearise, out_dir_option, srgb_decode_option
from bakeshop.cli._paths import ENVIRONMENT, refuse_overwriting_inputs
from bakeshop.cli._probe import (
    check_picture_format,
    from_option,
    method_option,
    order_option,
    picture_layout,
    read_probe,
    size_option,
    sun_lines,
    timed,
    to_option,
    window_option,
)
from bakeshop.io.environment import as_picture, check_openexr_target, describe


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@out_dir_option("Directory for the outputs (created if missing).")
@from_option
@float_format_option("File format of the three images.")
@method_option
@order_option
@to_option
@size_option
@window_option
@srgb_decode_option
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
) -> None:
    """Make the DIM pair of the probe IN: sun_dim, shadow_dim, shadow_probe and sun.json.

    The sun is found and painted out of the probe (shadow_probe, same layout and size as IN,
    a vertical cross for a cube);
    shadow_dim is the DIM of the painted probe, for surfaces the shadow pass says are in
    shadow; sun_dim adds the sun's own light, for lit surfaces. sun.json gives the sun's
    direction for the shadow pass. A probe without a sun gives two equal DIMs and
    {"sun": null}.

    \b
    Example:
      bakeshop dims probe.hdr --out-dir dims/
      bakeshop dims probe.exr -o dims/ --format exr --size 512x256
    """
    from bakeshop import progress
    from bakeshop.io import write_environment, write_json
    from bakeshop.light import dim_pair, sun_document

    names = {key: out_dir / f"{key}.{fmt}" for key in ("sun_dim", "shadow_dim", "shadow_probe")}
    for path in (*names.values(), out_dir / "sun.json"):  # before any work
        refuse_overwriting_inputs(path, source)
    check_openexr_target(names["sun_dim"], dst_layout)
    out_dir.mkdir(parents=True, exist_ok=True)
    image, layout, _, meta = read_probe(source, src_layout, with_metadata=True)
    check_picture_format(layout, fmt, source)
    image, _ = linearise(image, source, meta, srgb_decode)
    pair, elapsed = timed(dim_pair, image, layout, dst_layout, size, method, order, window)
    with progress.step(f"writing {out_dir}"):
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
    if pair.sun is None:
        click.echo("  no sun: the two DIMs are equal and the probe is unchanged")
    else:
        for line in sun_lines(pair.sun):
            click.echo(f"  {line}")
        lit = float(np.mean(pair.sun_dim[..., :3]))
        shade = float(np.mean(pair.shadow_dim[..., :3]))
        click.echo(f"  mean DIM            lit {lit:.4g}, shadow {shade:.4g}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(dims)
