"""``bakeshop irradiance``: the diffuse irradiance map (DIM) of a probe."""

from __future__ import annotations

import click

from bakeshop.cli._common import (
    ENVIRONMENT,
    OUTPUT,
    refuse_overwriting_inputs,
)
from bakeshop.cli._probe import (
    from_option,
    method_option,
    order_option,
    read_probe,
    size_option,
    timed,
    to_option,
)
from bakeshop.errors import ArgumentError
from bakeshop.io.environment import check_openexr_target, describe


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@click.argument("target", metavar="OUT", type=OUTPUT)
@from_option
@method_option
@order_option
@to_option
@size_option
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
    from bakeshop.io import write_environment, write_json, write_text
    from bakeshop.light import irradiance as compute_dim
    from bakeshop.light import sh, sh_coefficients

    extras = [p for p in (sh_json, shader) if p is not None]
    for out in (target, *extras):
        refuse_overwriting_inputs(out, source)
    if shader is not None and shader.suffix.lower() not in (".glsl", ".hlsl"):
        raise ArgumentError("the shader file must end in .glsl or .hlsl", shader)
    check_openexr_target(target, dst_layout)
    image, layout, _ = read_probe(source, src_layout)
    dim, elapsed = timed(compute_dim, image, layout, dst_layout, size, method, order)
    write_environment(target, dim, dst_layout)
    click.echo(
        f"wrote {target}: {describe(dim, dst_layout)} DIM (E/pi) of {source.name} "
        f"({describe(image, layout)}), method {method}"
        + (f" order {order}" if method == "sh" else "")
        + f", {elapsed:.2f} s"
    )
    if extras:
        coeffs = sh_coefficients(image, layout, order=max(order, 2) if shader else order)
        if sh_json is not None:
            write_json(sh_json, sh.to_document(coeffs[: (order + 1) ** 2]))
            click.echo(f"wrote {sh_json}: {(order + 1) ** 2} SH radiance coefficients per channel")
        if shader is not None:
            write_text(shader, sh.shader_snippet(coeffs, language=shader.suffix.lower()[1:]))
            click.echo(f"wrote {shader}: bakeshop_irradiance(n) from 9 SH coefficients")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(irradiance)
