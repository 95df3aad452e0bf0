"""``bakeshop remap``: convert a panorama between layouts (latlong, light probes, cube maps)."""

from __future__ import annotations

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
    warn,
)
from bakeshop.cli._huge import chunked, engine, memory_option, open_fitted, scheduler_option
from bakeshop.cli._numbers import Numbers, Size
from bakeshop.cli._paths import (
    ENVIRONMENT_SOURCE,
    OUTPUT_FACES,
    parse_size,
    refuse_overwriting_inputs,
)
from bakeshop.errors import ArgumentError, with_article
from bakeshop.io import stored_bits
from bakeshop.io.environment import (
    FACES,
    check_openexr_target,
    describe,
    is_container,
    is_cube,
    read_environment,
    write_environment,
)


def _layouts() -> list[str]:
    from bakeshop.sphere import LAYOUT_NAMES

    return [*LAYOUT_NAMES, FACES]


def _check_target(target: Path, layout: str) -> None:
    if is_cube(layout):
        if "{face}" not in str(target) and not is_container(target):
            raise ArgumentError(
                "a cube is written as six files: put {face} in the output name (sky_{face}.exr "
                "gives sky_posx.exr ... sky_negz.exr), write one .dds, .ktx or .ktx2 file, or "
                "choose a cross or strip (--to cross-vertical) or OpenEXR's cube environment "
                "(--to openexr-cube)",
                target,
            )
    elif "{face}" in str(target):
        raise ArgumentError(f"{{face}} in the output name needs --to faces, not {layout}", target)
    check_openexr_target(target, layout)


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=ENVIRONMENT_SOURCE)
@click.argument("target", type=OUTPUT_FACES)
@click.option(
    "--from",
    "src",
    type=click.Choice(_layouts()),
    help="Layout of SOURCE. Default: an EXR's envmap attribute (openexr-latlong, openexr-cube), "
    "else guessed from its shape (2:1 latlong, 3:4 and 4:3 crosses, 6:1 and 1:6 strips; a "
    "square image is ambiguous: name it).",
)
@click.option("--to", "dst", type=click.Choice(_layouts()), required=True, help="Layout of TARGET.")
@click.option(
    "--size",
    "size_text",
    type=Size(),
    metavar="N|WxH",
    help="Output size: WxH for a latlong (360x180) or N (its height), one edge for square "
    "layouts, the face edge for cubes, crosses and strips. Default: about as many texels as "
    "SOURCE (a power-of-two face edge for cubes, crosses and strips).",
)
@click.option(
    "--filter",
    "filter_name",
    type=click.Choice(["auto", "nearest", "bilinear", "area"]),
    default="auto",
    show_default=True,
    help="Sampling filter; auto is area (energy-preserving average) when the output has at most "
    "half the texels of SOURCE, else bilinear.",
)
@click.option(
    "--rotate",
    type=Numbers(-360, 360, count=3),
    metavar="YAW,PITCH,ROLL",
    help="Rotate the environment, degrees: yaw about +Y (positive turns the view ahead to the "
    "left), pitch about +X (positive lifts it), roll about +Z; applied roll, pitch, yaw.",
)
@convention_option(
    "Face set of cube files (faces, .dds, .ktx, .ktx2), read and written: opengl and vulkan "
    "sample the same faces; directx is the left-handed (z forward) set."
)
@click.option(
    "--short-face-names",
    is_flag=True,
    help="{face} is px, nx, py, ny, pz, nz instead of posx, negx, posy, negy, posz, negz.",
)
@srgb_decode_option
@alpha_option
@picture_options()
@memory_option
@scheduler_option
def remap(
    source: Path,
    target: Path,
    src: str | None,
    dst: str,
    size_text: int | tuple[int, int] | None,
    filter_name: str,
    rotate: tuple[float, ...] | None,
    convention: str,
    short_face_names: bool,
    srgb_decode: bool,
    alpha: str | None,
    picture: PictureRule,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    """Convert the panorama SOURCE from one layout to another and write TARGET.

    Layouts: latlong (equirectangular), angular (Debevec light probe) and mirrorball as HDRShop
    reads them (centre forward, -Z), angular-physical and mirrorball-physical (the exact
    reflection in a ball you photographed: centre +Z, behind the camera), octahedral,
    dual-paraboloid, cube maps as six files (faces: {face} in the name, or one .dds/.ktx/.ktx2
    file) and as pictures: cross-vertical, cross-horizontal, strip-horizontal,
    strip-vertical; OpenEXR's environments openexr-latlong and openexr-cube (.exr only, with
    their envmap attribute). Crosses and strips are drawn as HDRShop and cmft draw them (seen
    from inside the cube, unmirrored, the centre looking forward); six face files follow
    --convention. Seams are filtered across (cube edges, latlong poles). See
    docs/panoramas.md and docs/conventions.md.

    A picture TARGET (.png .tga .jpg) of HDR data follows the display rule of every command
    (docs/tonemap.md): --exposure (default 0 EV), --tonemap (default none: clamp at 1), sRGB
    encoding (or --linear), 8 bits (16 with --bits 16, or when the input has 16), said in one
    line and recorded in the file. A picture SOURCE holds display-encoded values: they are
    remapped as stored (with a warning) unless --srgb-decode linearises them.

    \b
    Example:
      bakeshop remap probe.hdr cross.exr --to cross-vertical --size 512
      bakeshop remap ball.hdr sky.hdr --from mirrorball --to latlong --size 2048x1024
      bakeshop remap sky.exr sky_{face}.exr --to faces --size 1024 --convention directx
      bakeshop remap sky_{face}.hdr sky.exr --from faces --to latlong --rotate 90,0,0
      bakeshop remap sky.ktx2 sky.hdr --to latlong
      bakeshop remap KernerEnvCube.exr kerner.hdr --to latlong
      bakeshop remap sky.hdr sky_env.exr --to openexr-cube --size 512
      bakeshop remap probe.hdr preview.png --to cross-vertical --exposure auto --tonemap aces
      bakeshop remap pano_32k.pfm sky_{face}.exr --to faces --size 2048 --memory 2GB

    A panorama larger than memory (a flat layout in .pfm, .hdr, .exr, .tif or .zarr) is
    remapped tile by tile within --memory, each tile reading only its window of the source
    (docs/huge-images.md); nearest and bilinear give the in-memory result bit for bit.
    """
    from bakeshop import progress, sphere

    refuse_overwriting_inputs(target, source)
    _check_target(target, dst)
    rotation = None if rotate is None else list(rotate)
    picture_out = is_picture(target)
    if not picture_out:
        refuse_unused_picture_rule(picture, target)
    if "{face}" not in str(source) and chunked(source, memory, scheduler):
        if picture_out or srgb_decode:
            raise ArgumentError(
                "a panorama larger than memory is remapped to a float file (.pfm, .hdr, .exr, "
                ".zarr): make the picture from the result",
                target,
            )
        _remap_chunked(source, target, src, dst, size_text, filter_name, rotation, convention,
                       short_face_names, alpha, memory, scheduler)  # fmt: skip
        return
    with progress.step(f"reading {source}"):
        (image, src, how), meta = read_environment(
            source, src, convention=convention, short=short_face_names, with_metadata=True
        )
    image, linear = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, target)
    dst_name = "cube" if dst == FACES else dst
    size = None if size_text is None else parse_size(size_text)
    if filter_name == "auto":
        src_shape = image.shape[: 3 if src == "cube" else 2]
        dst_shape = sphere.remap_shape(src, src_shape, dst_name, size)
        filter_name = sphere.auto_filter(src, src_shape, dst_name, dst_shape)
    cost = sphere.remap_cost(src, image.shape[: 3 if src == "cube" else 2], dst_name, size,
                             filter=filter_name, channels=image.shape[-1],
                             itemsize=image.itemsize)  # fmt: skip
    check(cost, source, "--size", "--size", memory=memory)
    with progress.step(f"remapping {src} -> {dst_name} ({filter_name})"):
        out = sphere.remap(image, src, dst_name, size, filter=filter_name, rotation=rotation)
    made = None
    if picture_out:
        weights = environment_weights(dst_name, out.shape[:-1])
        made = make_picture(
            out, picture, target, weights=weights, inputs=[stored_bits(meta)], linear_input=linear
        )
    with progress.step(f"writing {target}"):
        written = write_environment(
            target,
            out if made is None else made.pixels,
            dst,
            convention=convention,
            short=short_face_names,
            description=None if made is None else made.description,
        )
    where = written[0] if len(written) == 1 else f"{written[0]} ... {written[-1].name}"
    click.echo(
        f"wrote {where}: {describe(out, dst_name)} from {describe(image, src)} "
        f"({how}), {filter_name}"
        + (f", rotated {','.join(f'{a:g}' for a in rotate)}" if rotate else "")
    )
    if made is not None:
        click.echo(f"  picture: {made.line}")
        if made.note:
            warn(made.note, target)


def _remap_chunked(
    source: Path,
    target: Path,
    src: str | None,
    dst: str,
    size_text: int | tuple[int, int] | None,
    filter_name: str,
    rotation: list[float] | None,
    convention: str,
    short: bool,
    alpha: str | None,
    memory: int | str | None,
    scheduler: str | None,
) -> None:
    from bakeshop import sphere
    from bakeshop.huge import remap as remap_chunked

    reader = open_fitted(source, alpha, target)
    h, w, _ = reader.shape
    how = "given"
    if src is None:
        guesses = sphere.guess_layout(h, w)
        if len(guesses) != 1:
            raise ArgumentError(
                f"cannot tell the layout of {with_article(w)}x{h} image; name it with --from",
                source,
            )
        src, how = guesses[0], f"guessed from its {w}x{h} shape"
    dst_name = "cube" if dst == FACES else dst
    size = None if size_text is None else parse_size(size_text)
    with engine(memory, scheduler) as eng:
        out = remap_chunked(reader, src, dst_name, size, filter=filter_name, rotation=rotation,
                            engine=eng)  # fmt: skip
    written = write_environment(target, out, dst, convention=convention, short=short)
    where = written[0] if len(written) == 1 else f"{written[0]} ... {written[-1].name}"
    click.echo(
        f"wrote {where}: {describe(out, dst_name)} from {src} {w}x{h} ({how}), "
        f"{filter_name}, chunked"
    )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(remap)
