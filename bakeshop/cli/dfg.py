"""``bakeshop dfg``: the split-sum DFG lookup table."""

from __future__ import annotations

import time
from pathlib import Path

import click

from bakeshop.cli._budget import check
from bakeshop.cli._numbers import Integer
from bakeshop.cli._paths import OUTPUT
from bakeshop.io.environment import write_table

_float32 = click.option(
    "--float32", is_flag=True, help="Store 32-bit floats in .dds/.ktx/.ktx2 (default: half floats "
    "unless a value exceeds 65504)."
)  # fmt: skip


@click.command(context_settings={"max_content_width": 100})
@click.argument("target", metavar="OUT", type=OUTPUT)
@click.option("--size", type=Integer(1, 4096), default=128, show_default=True,
              help="Side of the square table.")  # fmt: skip
@click.option("--samples", type=Integer(1, 1 << 20), default=4096, show_default=True,
              help="Importance samples per texel.")  # fmt: skip
@click.option(
    "--visibility",
    type=click.Choice(("height-correlated", "schlick")),
    default="height-correlated",
    show_default=True,
    help="Smith GGX visibility: height-correlated (Heitz 2014, exact) or UE4's separable "
    "Schlick-Smith (k = alpha/2).",
)
@_float32
def dfg(target: Path, size: int, samples: int, visibility: str, float32: bool) -> None:
    """Write the split-sum DFG lookup table to OUT: scale and bias on F0 per (n.v, roughness).

    Columns are n.v and rows roughness (row 0 smoothest), both at texel centres:
    specular = prefiltered * (F0 * lut.r + lut.g) with lut = texture(dfg, vec2(NdotV,
    roughness)). A .dds/.ktx/.ktx2 file holds an RG float texture; an image file (.exr, .hdr,
    .pfm, 16-bit .png) holds RGB with blue 0.

    \b
    Example:
      bakeshop dfg dfg.dds
      bakeshop dfg dfg_lut.exr --size 256 --visibility schlick
    """
    from bakeshop.light.dfg import dfg_table, dfg_table_cost

    check(dfg_table_cost(size, samples=samples), target, "--size", "--samples or --size")
    started = time.perf_counter()
    table = dfg_table(size, samples=samples, visibility=visibility)
    elapsed = time.perf_counter() - started
    write_table(target, table, float32=float32)
    click.echo(
        f"wrote {target}: {size}x{size} DFG table ({visibility} Smith GGX, {samples} samples), "
        f"{elapsed:.2f} s"
    )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(dfg)
