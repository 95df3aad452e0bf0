"""``bakeshop irradiance``: the diffuse irradiance map (DIM) of a probe."""

from __future__ import annotations

from pathlib import Path

import click

from bakeshop.cli._budget import check
from bakeshop.cli._common import (
    PictureRule,
    alpha_option,
    environment_weights,
    fit_alpha,
    is_picture,
    linearise,
    make_picture,
    picture_options,
    refuse_unused_picture_rule,
    srgb_decode_option,
    warn,
)
from bakeshop.cli._paths import ENVIRONMENT, OUTPUT, refuse_overwriting_inputs
from bakeshop.cli._probe import (
    from_option,
    method_option,
    order_option,
    output_size,
    read_probe,
    size_option,
    timed,
    to_option,
    window_option,
)
from bakeshop.errors import ArgumentError
from bakeshop.io import stored_bits
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
    "SH coefficients (Ramamoorthi and Hanrahan's quadratic form), windowed (--window).",
)
@window_option
@srgb_decode_option
@alpha_option
@picture_options()
def irradiance(
    source: Path,
    target: Path,
    src_layout: str | None,
    method: str,
    order: int,
    dst_layout: str,
    size: int | tuple[int, int] | None,
    sh_json: Path | None,
    shader: Path | None,
    window: str,
    srgb_decode: bool,
    alpha: str | None,
    picture: PictureRule,
) -> None:
    """Compute the diffuse irradiance map (DIM) of the probe IN and write it to OUT.

    A DIM texel holds E(n) / pi for the surface normal n it looks along: the radiance that a
    white Lambertian surface facing n reflects (a uniform sky of 1 gives 1). The default method
    is exact to 0.1% RMS from the full-resolution probe, in seconds.

    SH irradiance (--method sh, --sh-json, --shader) rings: a sunny probe's order-2 DIM goes
    negative opposite the sun. --window (default minimal: Sloan's least window that makes it
    non-negative) tames it; the negative fraction is reported with and without the window, and
    sh.json keeps the raw radiance coefficients beside the windowed irradiance.

    A picture OUT (.png .tga .jpg) follows the display rule (docs/tonemap.md: --exposure,
    --tonemap, sRGB or --linear, --bits). A picture IN holds display-encoded values: used as
    stored, with a warning, unless --srgb-decode linearises them.

    \b
    Example:
      bakeshop irradiance probe.hdr dim.hdr
      bakeshop irradiance probe.exr dim.exr --to cross-vertical --size 32
      bakeshop irradiance probe.hdr dim_sh.hdr --method sh --order 2 --sh-json sh.json
      bakeshop irradiance probe.hdr dim.hdr --shader irradiance.glsl
      bakeshop irradiance probe.hdr dim.png --exposure auto
    """
    from bakeshop.io import write_environment, write_image, write_json, write_text
    from bakeshop.light import irradiance as compute_dim
    from bakeshop.light import irradiance_cost, sh, sh_coefficients

    extras = [p for p in (sh_json, shader) if p is not None]
    for out in (target, *extras):
        refuse_overwriting_inputs(out, source)
    if shader is not None and shader.suffix.lower() not in (".glsl", ".hlsl"):
        raise ArgumentError("the shader file must end in .glsl or .hlsl", shader)
    check_openexr_target(target, dst_layout)
    picture_out = is_picture(target)
    if not picture_out:
        refuse_unused_picture_rule(picture, target)
    image, layout, _, meta = read_probe(source, src_layout, with_metadata=True)
    image, linear = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, target)
    cost = irradiance_cost(
        image.shape, layout, to=dst_layout, size=output_size(dst_layout, size), method=method,
        order=order,
    )  # fmt: skip
    if window == "minimal" and (method == "sh" or sh_json is not None):
        search = sh.search_cost(order, 3)  # after the DIM: the larger one's memory
        larger = search if search.memory > cost.memory else cost
        cost = larger._replace(seconds=cost.seconds + search.seconds)
    check(cost, source, "--order or --size", "--order, --size or --method")
    dim, elapsed = timed(compute_dim, image, layout, dst_layout, size, method, order, window)
    made = None
    if picture_out:
        weights = environment_weights(dst_layout, dim.shape[:-1])
        made = make_picture(
            dim, picture, target, weights=weights, inputs=[stored_bits(meta)], linear_input=linear
        )
        write_image(target, made.pixels, description=made.description)
    else:
        write_environment(target, dim, dst_layout)
    click.echo(
        f"wrote {target}: {describe(dim, dst_layout)} DIM (E/pi) of {source.name} "
        f"({describe(image, layout)}), method {method}"
        + (f" order {order}" if method == "sh" else "")
        + f", {elapsed:.2f} s"
    )
    if method == "sh":
        report = sh.windowed_irradiance(sh_coefficients(image, layout, order=order), window=window)
        click.echo(f"  SH irradiance: {report.describe()}")
    if made is not None:
        click.echo(f"  picture: {made.line}")
        if made.note:
            warn(made.note, target)
    if extras:
        coeffs = sh_coefficients(image, layout, order=max(order, 2) if shader else order)
        if sh_json is not None:
            kept = coeffs[: (order + 1) ** 2]
            windowed = sh.windowed_irradiance(kept, window=window)
            write_json(sh_json, sh.to_document(kept, irradiance=windowed))
            click.echo(
                f"wrote {sh_json}: {(order + 1) ** 2} SH radiance coefficients per channel and "
                f"the windowed irradiance ({windowed.describe()})"
            )
        if shader is not None:
            code = sh.shader_snippet(coeffs, language=shader.suffix.lower()[1:], window=window)
            write_text(shader, code)
            click.echo(
                f"wrote {shader}: bakeshop_irradiance(n) from 9 SH coefficients, {window} window"
            )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(irradiance)
