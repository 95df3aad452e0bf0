"""``bakeshop irradiance``, ``sun`` and ``dims``: diffuse irradiance maps and the sun of a probe."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import (
    ENVIRONMENT,
    OUTPUT,
    float_format_option,
    out_dir_option,
    parse_size,
    refuse_overwriting_inputs,
)
from bakeshop.cli._environment import as_picture, describe, read_environment
from bakeshop.errors import ArgumentError

#: layouts a single image file can hold (the cube is written as a cross or a strip).
FILE_LAYOUTS = (
    "latlong",
    "angular",
    "mirrorball",
    "octahedral",
    "dual-paraboloid",
    "cross-vertical",
    "cross-horizontal",
    "strip-horizontal",
    "strip-vertical",
)
#: output texels of a DIM when no --size is given (360x180, the pipeline's latlong).
DEFAULT_TEXELS = 360 * 180

_from = click.option(
    "--from",
    "src_layout",
    type=click.Choice(FILE_LAYOUTS),
    help="Layout of IN; guessed from its shape when only one fits (2:1 is latlong). IN may "
    "also be a .dds/.ktx/.ktx2 cube or six files with {face}.",
)
_to = click.option(
    "--to",
    "dst_layout",
    type=click.Choice(FILE_LAYOUTS),
    default="latlong",
    show_default=True,
    help="Layout of the DIM.",
)
_size = click.option(
    "--size",
    metavar="N|WxH",
    help="Size of the DIM as its layout reads it (latlong WxH or height N; face edge for "
    "crosses and strips; edge for square layouts). Default: 360x180, or as many texels.",
)
_method = click.option(
    "--method",
    type=click.Choice(("auto", "exact", "sh")),
    default="auto",
    show_default=True,
    help="auto: exact to 0.1% RMS / 0.5% max in seconds; exact: every texel for every "
    "output texel (slow: the reference); sh: spherical harmonics to --order.",
)
_order = click.option(
    "--order",
    type=click.IntRange(0, 64),
    default=2,
    show_default=True,
    help="SH order for --method sh, --sh-json and --shader (2: 9 coefficients per channel).",
)


def _read(path: Path, given: str | None):
    from bakeshop import progress

    with progress.step(f"reading {path.name}"):
        image, layout, _ = read_environment(path, given)
    return image, layout


def _timed(compute, image, layout, dst_layout, size, method, order):
    """``(compute(image, layout, to=..., ...), seconds)``: the DIM or the DIM pair, timed."""
    started = time.perf_counter()
    result = compute(
        image,
        layout,
        to=dst_layout,
        size=_output_size(dst_layout, size),
        method=method,
        order=order,
    )
    return result, time.perf_counter() - started


def _output_size(layout: str, size: str | None):
    from bakeshop.sphere import layout as get_layout

    if size is not None:
        return parse_size(size)
    if layout == "latlong":
        return (360, 180)
    return get_layout(layout).default_size(DEFAULT_TEXELS)


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@click.argument("target", metavar="OUT", type=OUTPUT)
@_from
@_method
@_order
@_to
@_size
@click.option(
    "--sh-json",
    type=OUTPUT,
    help="Also write the probe's SH radiance coefficients (to --order) as JSON.",
)
@click.option(
    "--shader",
    type=OUTPUT,
    help="Also write a GLSL (.glsl) or HLSL (.hlsl) function returning the DIM value from 9 "
    "SH coefficients (Ramamoorthi and Hanrahan's quadratic form).",
)
def irradiance(source, target, src_layout, method, order, dst_layout, size, sh_json, shader):
    """Compute the diffuse irradiance map (DIM) of the probe IN and write it to OUT.

    A DIM texel holds E(n) / pi for the surface normal n it looks along: the radiance that a
    white Lambertian surface facing n reflects (a uniform sky of 1 gives 1). The default method
    is exact to 0.1% RMS from the full-resolution probe, in seconds.

    \b
    Example:
      bakeshop irradiance probe.hdr dim.hdr
      bakeshop irradiance probe.exr dim.exr --to cross-vertical --size 32
      bakeshop irradiance probe.hdr dim_sh.hdr --method sh --order 2 --sh-json sh.json
      bakeshop irradiance probe.hdr dim.hdr --shader irradiance.glsl
    """
    from bakeshop.io import write_image
    from bakeshop.light import irradiance as ir
    from bakeshop.light import sh

    extras = [p for p in (sh_json, shader) if p is not None]
    for out in (target, *extras):
        refuse_overwriting_inputs(out, source)
    if shader is not None and shader.suffix.lower() not in (".glsl", ".hlsl"):
        raise ArgumentError("the shader file must end in .glsl or .hlsl", shader)
    image, layout = _read(source, src_layout)
    dim, elapsed = _timed(ir.irradiance, image, layout, dst_layout, size, method, order)
    write_image(target, dim)
    click.echo(
        f"wrote {target}: {describe(dim, dst_layout)} DIM (E/pi) of {source.name} "
        f"({describe(image, layout)}), method {method}"
        + (f" order {order}" if method == "sh" else "")
        + f", {elapsed:.2f} s"
    )
    if extras:
        coeffs = ir.sh_coefficients(image, layout, order=max(order, 2) if shader else order)
        if sh_json is not None:
            sh.write_json(sh_json, coeffs[: (order + 1) ** 2])
            click.echo(f"wrote {sh_json}: {(order + 1) ** 2} SH radiance coefficients per channel")
        if shader is not None:
            from bakeshop.io._files import atomic_path

            text = sh.shader_snippet(coeffs, language=shader.suffix.lower()[1:])
            with atomic_path(shader) as tmp:
                tmp.write_text(text, encoding="utf-8")
            click.echo(f"wrote {shader}: bakeshop_irradiance(n) from 9 SH coefficients")


def _sun_lines(sun) -> list[str]:
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


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@_from
@click.option("--json", "as_json", is_flag=True, help="Print sun.json instead.")
def sun(source, src_layout, as_json):
    """Find the sun of the probe IN and print its direction, size, colour and irradiance.

    The sun is the brightest compact light that stands well above the sky around it and
    dominates every other compact light; overcast, indoor and dawn probes have none, and the
    command says so (with --json it prints {"sun": null}). Directions are unit [x, y, z] with
    +Y up, -Z forward, +X right.

    \b
    Example:
      bakeshop sun probe.hdr
      bakeshop sun probe.hdr --json > sun.json
    """
    from bakeshop.light.sun import find_sun

    image, layout = _read(source, src_layout)
    found = find_sun(image, layout)
    if as_json:
        click.echo(json.dumps({"sun": None} if found is None else found.to_dict(), indent=1))
    elif found is None:
        click.echo(f"{source}: no sun (no compact light stands out from the sky)")
    else:
        click.echo(f"{source}: sun found")
        for line in _sun_lines(found):
            click.echo(f"  {line}")


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@out_dir_option("Directory for the outputs (created if missing).")
@_from
@float_format_option("File format of the three images.")
@_method
@_order
@_to
@_size
def dims(source, out_dir, src_layout, fmt, method, order, dst_layout, size):
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
    from bakeshop.io import write_image
    from bakeshop.light import irradiance as ir
    from bakeshop.light import sun as sunlib

    out_dir.mkdir(parents=True, exist_ok=True)
    names = {key: out_dir / f"{key}.{fmt}" for key in ("sun_dim", "shadow_dim", "shadow_probe")}
    for path in (*names.values(), out_dir / "sun.json"):
        refuse_overwriting_inputs(path, source)
    image, layout = _read(source, src_layout)
    pair, elapsed = _timed(ir.dim_pair, image, layout, dst_layout, size, method, order)
    with progress.step(f"writing {out_dir}"):
        write_image(names["sun_dim"], pair.sun_dim)
        write_image(names["shadow_dim"], pair.shadow_dim)
        write_image(names["shadow_probe"], as_picture(pair.shadow_probe, layout))
        sunlib.write_json(out_dir / "sun.json", pair.sun)
    click.echo(
        f"wrote {out_dir}: sun_dim.{fmt} and shadow_dim.{fmt} "
        f"({describe(pair.sun_dim, dst_layout)}, method {method}), shadow_probe.{fmt} "
        f"({describe(image, layout)}), sun.json; {elapsed:.2f} s"
    )
    if pair.sun is None:
        click.echo("  no sun: the two DIMs are equal and the probe is unchanged")
    else:
        for line in _sun_lines(pair.sun):
            click.echo(f"  {line}")
        lit = float(np.mean(pair.sun_dim[..., :3]))
        shade = float(np.mean(pair.shadow_dim[..., :3]))
        click.echo(f"  mean DIM            lit {lit:.4g}, shadow {shade:.4g}")


def register(group: click.Group) -> None:
    """Add ``irradiance``, ``sun`` and ``dims`` to the root command group."""
    for command in (irradiance, sun, dims):
        group.add_command(command)
