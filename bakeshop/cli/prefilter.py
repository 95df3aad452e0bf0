"""``bakeshop prefilter``: glossy-reflection cube mip chains (GGX, Phong)."""

from __future__ import annotations

import time
from pathlib import Path

import click

from bakeshop.cli._budget import check
from bakeshop.cli._common import (
    PictureRule,
    alpha_option,
    convention_option,
    environment_weights,
    fit_alpha,
    is_picture,
    linearise,
    make_picture,
    picture_options,
    refuse_unused_picture_rule,
    srgb_decode_option,
    stored_bits,
    warn,
)
from bakeshop.cli._numbers import Integer, Number
from bakeshop.cli._paths import ENVIRONMENT, OUTPUT_CHAIN, refuse_overwriting_inputs
from bakeshop.cli._probe import chain_mips, read_probe
from bakeshop.errors import ArgumentError
from bakeshop.io.environment import (
    check_chain_path,
    describe,
    write_chain,
)

_from = click.option(
    "--from",
    "src_layout",
    metavar="LAYOUT",
    help="Layout of IN (latlong, angular, mirrorball, cross-vertical, ...); guessed from its "
    "shape when only one fits. IN may also be a .dds/.ktx/.ktx2 cube or six files with {face}.",
)


_convention = convention_option(
    "Engine whose cube faces to write (directx: the left-handed, z-forward face set)."
)


_float32 = click.option(
    "--float32", is_flag=True, help="Store 32-bit floats in .dds/.ktx/.ktx2 (default: half floats "
    "unless a value exceeds 65504)."
)  # fmt: skip


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@click.argument("target", metavar="OUT", type=OUTPUT_CHAIN)
@click.option("--brdf", type=click.Choice(("ggx", "phong")), default="ggx", show_default=True,
              help="ggx: a mip chain, roughness rising with the level (split-sum, with the dfg "
              "table); phong: one Phong lobe (--exponent).")  # fmt: skip
@click.option(
    "--exponent",
    type=Number(0, 1e8, low_open=True),
    help="Phong only: one lobe of this exponent, one level (HDRShop's specular convolution). "
    "Default: a chain with cmft's exponents, 2^(10 (1 - m/(mips-1)) + 1).",
)
@click.option("--size", type=Integer(1, 4096), default=256, show_default=True,
              help="Face size of level 0.")  # fmt: skip
@click.option(
    "--mips",
    type=Integer(1, 14),
    help="Levels (default: 9, or down to 1x1; at most log2(--size) + 1).",
)
@_from
@click.option("--samples", type=Integer(1, 65536), default=256, show_default=True,
              help="Importance samples per texel (narrow lobes; wide ones are exact).")  # fmt: skip
@_convention
@_float32
@srgb_decode_option
@alpha_option
@picture_options()
def prefilter(
    source: Path,
    target: Path,
    brdf: str,
    exponent: float | None,
    size: int,
    mips: int | None,
    src_layout: str | None,
    samples: int,
    convention: str,
    float32: bool,
    srgb_decode: bool,
    alpha: str | None,
    picture: PictureRule,
) -> None:
    """Prefilter the environment IN into a glossy-reflection cube mip chain OUT.

    GGX (the split-sum approximation of UE4): level m has roughness m / (mips - 1), so level 0
    is the environment itself and the last level roughness 1; a shader reads it with
    textureLod(env, R, roughness * (mips - 1)) and multiplies by the DFG table (bakeshop dfg).
    Phong: cmft's exponent per level, or one lobe with --exponent. OUT is one .dds, .ktx or
    .ktx2 file holding the whole chain, or a name with {mip} (and {face} for six face files).
    Picture files per level (.png .tga .jpg) follow the display rule (docs/tonemap.md), with
    one exposure for every level (metered on level 0 with --exposure auto or fit).

    \b
    Example:
      bakeshop prefilter probe.hdr specular.dds
      bakeshop prefilter probe.exr specular.ktx2 --size 128 --mips 8
      bakeshop prefilter probe.hdr "spec_{mip}_{face}.hdr" --convention directx
      bakeshop prefilter probe.hdr glossy.dds --brdf phong --exponent 64 --size 64
    """
    from bakeshop.light import specular

    check_chain_path(target)
    refuse_overwriting_inputs(target, source)
    if exponent is not None and brdf != "phong":
        raise ArgumentError("--exponent is the exponent of a Phong lobe: add --brdf phong")
    if exponent is not None and mips not in (None, 1):
        raise ArgumentError("--exponent makes one level (one lobe); leave out --mips")
    mips = 1 if exponent is not None else chain_mips(mips, size, "--size", target)
    picture_out = is_picture(target)
    if not picture_out:
        refuse_unused_picture_rule(picture, target)
    image, layout, _, meta = read_probe(source, src_layout, with_metadata=True)
    image, linear = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, target)
    cost = specular.prefilter_cost(
        image.shape, layout, size=size, mips=mips, samples=samples, itemsize=image.itemsize
    )
    check(cost, source, "--size", "--samples or --size")
    started = time.perf_counter()
    if brdf == "ggx":
        chain = specular.prefilter_ggx(image, layout, size=size, mips=mips, samples=samples)
        what = f"GGX, roughness m/{mips - 1} per level" if mips > 1 else "GGX, roughness 0"
    else:
        exponents = None if exponent is None else [exponent]
        chain = specular.prefilter_phong(
            image, layout, size=size, mips=mips, exponents=exponents, samples=samples
        )
        what = f"Phong exponent {exponent:g}" if exponent else "Phong, cmft's exponents"
    elapsed = time.perf_counter() - started
    made = None
    if picture_out:
        pictures = []
        for level in chain:  # level 0 sets the exposure; every level gets the same
            rule = picture if made is None else picture._replace(ev=made.ev)
            made_level = make_picture(
                level,
                rule,
                target,
                weights=environment_weights("cube", level.shape[:-1]),
                inputs=[stored_bits(meta)],
                linear_input=linear,
            )
            made = made or made_level
            pictures.append(made_level.pixels)
        chain_out = pictures
    else:
        chain_out = chain
    paths = write_chain(
        target,
        chain_out,
        convention=convention,
        float32=float32,
        description=None if made is None else made.description,
    )
    where = target if len(paths) == 1 else f"{len(paths)} files ({paths[0].name} ...)"
    click.echo(
        f"wrote {where}: {len(chain)} levels of 6x{size} down to 6x{chain[-1].shape[1]} "
        f"({what}; {convention} faces) from {source.name} ({describe(image, layout)}), "
        f"{elapsed:.2f} s"
    )
    if made is not None:
        click.echo(f"  pictures: {made.line} (level 0)")
        if made.note:
            warn(made.note, target)


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(prefilter)
