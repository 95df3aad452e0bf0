"""``bakeshop normals``: combine, transfer, from-height, check and convert normal maps."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import click
import numpy as np

from bakeshop.cli._common import (
    is_picture,
    output_bits,
    parse_options,
    picture_bits,
    warn,
    writer_option,
)
from bakeshop.cli._normal_layers import build_layers, parse_layer, placement_options, read_map
from bakeshop.cli._numbers import Integer, Number, Size
from bakeshop.cli._paths import INPUT, OUTPUT, parse_size, refuse_overwriting_inputs
from bakeshop.engines import ENGINES
from bakeshop.errors import ArgumentError
from bakeshop.io import stored_bits
from bakeshop.normals.blend import DEFAULT_METHOD, METHODS
from bakeshop.normals.encoding import CONVENTIONS, ENCODINGS

CONTEXT = {"max_content_width": 100}

_convention = click.option(
    "--convention",
    type=click.Choice(CONVENTIONS),
    default="gl",
    show_default=True,
    help="Green channel of the macro map and of OUT: gl = Y+ (OpenGL, Blender, Unity, glTF), "
    "dx = Y- (DirectX, Unreal).",
)
_detail_convention = click.option(
    "--detail-convention",
    type=click.Choice(CONVENTIONS),
    default=None,
    help="Green channel of the detail maps, when it differs from --convention.",
)
_encoding = click.option(
    "--encoding",
    type=click.Choice(ENCODINGS),
    default="packed",
    show_default=True,
    help="packed: stored (n + 1) / 2, as every 8/16-bit map and most EXR bakes; signed: float "
    "files that store the components in [-1, 1].",
)
_writer = writer_option(
    "A writer option for OUT, repeatable: PNG bits=8|16 (default: the inputs' depth, 16 for "
    "float inputs); EXR pixel_type=half|float."
)


def write_normal_map(
    path: Path, normals: np.ndarray, *, convention: str = "gl", encoding: str = "packed",
    channels: str = "xyz", inputs: Sequence[int | None] = (), **options: Any,
) -> int | None:  # fmt: skip
    """Write unit normals (OpenGL frame) in an encoding; ``options`` go to the codec.

    A picture file's depth follows ``inputs`` (the inputs' sample depths: 8, 16, None for
    floats; see :func:`~bakeshop.cli._common.output_bits`) unless ``bits=`` is given, and a
    reduction below the inputs' is said in one warning line. Returns the bits written (None
    for a float file)."""
    from bakeshop.cli._common import is_picture
    from bakeshop.io import write_image
    from bakeshop.normals.encoding import encode_normals

    values = encode_normals(normals, convention=convention, encoding=encoding, channels=channels)
    bits = None
    if is_picture(path):
        requested = options.pop("bits", None)
        bits, note = output_bits(
            path,
            requested=None if requested is None else picture_bits(requested, path),
            inputs=inputs,
        )
        if Path(path).suffix.lower() == ".png":
            options["bits"] = bits
        if note:
            warn(note, path)
    write_image(path, values.astype(np.float32, copy=False), **options)
    return bits


def _depth_text(bits: int | None) -> str:
    return "float" if bits is None else f"{bits}-bit"


@click.group(context_settings=CONTEXT)
def normals() -> None:
    """Tangent-space normal maps: combine macro and micro detail correctly, transfer a tileable
    detail into a mesh's UV layout, make normals from heights, check and convert maps.

    \b
    Example:
      bakeshop normals combine rifle_n.png wood_n.png out.png --tile 8 --mask stock.png
      bakeshop normals transfer rifle.glb grit_n.png grit_in_uvs.png --size 2048 \\
          --projection triplanar --tile 20
    """


@normals.command(context_settings=CONTEXT)
@click.argument("macro", type=INPUT)
@click.argument("detail", type=INPUT)
@click.argument("out", type=OUTPUT)
@click.option(
    "--method",
    type=click.Choice(METHODS),
    default=DEFAULT_METHOD,
    show_default=True,
    help="Blend method (docs/normals.md compares them): exact is exact for a detail unwrapped "
    "onto the macro UVs; rnm for detail laid out by arc length; pd for heights added along "
    "the low-poly normal; sg, whiteout, udn, overlay and linear for comparison.",
)
@placement_options(
    tile="Repetitions of DETAIL across the macro map (negative mirrors).",
    rotate="Counter-clockwise rotation of the pattern; the normals turn with it.",
    strength="Height scale of the detail (0 = none, negative inverts).",
)
@click.option(
    "--mask",
    type=INPUT,
    default=None,
    help="Where DETAIL applies: a greyscale weight map, or with --mask-id an ID map.",
)
@click.option(
    "--mask-id",
    "mask_ids",
    multiple=True,
    metavar="ID",
    help="Material ID in --mask where DETAIL applies, repeatable: grey level 0-255, "
    "#rrggbb or r/g/b.",
)
@click.option(
    "--layer",
    "layers",
    multiple=True,
    metavar="FILE[,KEY=VALUE...]",
    help="A further detail layer, repeatable, applied in order after DETAIL. Keys: "
    "tile, offset, rotate, strength, mask, id (repeatable), convention.",
)
@_convention
@_detail_convention
@_encoding
@_writer
@click.option("--compress", is_flag=True, help="Write OUT (.dds, .ktx2, .ktx) block-compressed "
              "with its mip chain: BC5 (x, y; z rebuilt) unless --engine says otherwise, with "
              "its angular error in OUT.json.")  # fmt: skip
@click.option("--engine", type=click.Choice(sorted(ENGINES)), help="Compress for this engine: "
              "its normal-map format and green convention (implies --compress).")  # fmt: skip
def combine(
    macro: Path,
    detail: Path,
    out: Path,
    method: str,
    tile: tuple[float, float],
    offset: tuple[float, float],
    rotate: float,
    strength: float,
    mask: Path | None,
    mask_ids: tuple[str, ...],
    layers: tuple[str, ...],
    convention: str,
    detail_convention: str | None,
    encoding: str,
    options: tuple[str, ...],
    compress: bool,
    engine: str | None,
) -> None:
    """Blend tileable DETAIL normal maps onto the MACRO normal map; write OUT.

    The detail is tiled over the macro map's UV square (--tile, --offset, --rotate) with
    wrap-around trilinear filtering, so tiles meet without seams and minified detail is
    prefiltered. Each further --layer is blended onto the result of the ones before it; masks
    of another size are resampled to the macro map's.

    \b
    Example:
      bakeshop normals combine rifle_n.png wood_n.png rifle_wood.png --tile 8 \\
          --mask ids.png --mask-id '#8a4b20' \\
          --layer 'grit_n.png,tile=24,rotate=30,strength=0.6,mask=ids.png,id=#9090a0'
      bakeshop normals combine macro.tga detail.tga out.tga --method rnm --convention dx
    """
    from bakeshop.normals.tiling import apply_layers

    settings = [
        {
            "path": Path(detail),
            "tile": tile,
            "offset": offset,
            "rotate": rotate,
            "strength": strength,
            "mask": mask,
            "ids": list(mask_ids),
        }
    ] + [parse_layer(spec) for spec in layers]
    refuse_overwriting_inputs(
        out, macro, *(s["path"] for s in settings), *(s["mask"] for s in settings if s.get("mask"))
    )
    base, macro_bits = read_map(macro, convention, encoding, "--convention")
    depths = [macro_bits]
    built = build_layers(
        base.shape[:2], settings, detail_convention or convention, encoding, depths
    )
    result = apply_layers(base, built, method=method)
    h, w = result.shape[:2]
    if compress or engine:
        from bakeshop.cli.compress import describe_quality, write_levels
        from bakeshop.io.compress.pipeline import box_mips

        preset = ENGINES[engine] if engine else None
        conv = preset.normal_convention if preset else convention
        fmt = preset.normal_format if preset else "bc5"
        levels = box_mips(result, cube=False, normals=True)
        _, report = write_levels(out, levels, fmt, cube=False, normals=True,
                                 normal_convention=conv, extra={"engine": engine})  # fmt: skip
        click.echo(
            f"wrote {out}: {w}x{h} {fmt} ({conv}), {len(levels)} levels, {len(built)} detail "
            f"layer(s) blended with {method}; {describe_quality(report['quality'])}"
        )
        return
    bits = write_normal_map(
        out,
        result,
        convention=convention,
        encoding=encoding,
        inputs=depths,
        **parse_options(options),
    )
    click.echo(
        f"wrote {out}: {w}x{h} {_depth_text(bits)}, {len(built)} detail layer(s) blended with "
        f"{method}"
    )


@normals.command(context_settings=CONTEXT)
@click.argument("mesh", type=INPUT)
@click.argument("detail", type=INPUT)
@click.argument("out", type=OUTPUT)
@click.option(
    "--size",
    type=Size(16384),
    default=None,
    metavar="N|WxH",
    help="Size of OUT (the macro map's); taken from --macro when given.",
)
@click.option(
    "--projection",
    type=click.Choice(["uv2", "planar", "box", "triplanar"]),
    default="uv2",
    show_default=True,
    help="How DETAIL is applied: the mesh's second UV set (glTF TEXCOORD_1), or a "
    "projection in object space.",
)
@click.option(
    "--axis",
    type=click.Choice(["x", "y", "z"]),
    default="z",
    show_default=True,
    help="Axis of the planar projection.",
)
@placement_options(
    tile="Repetitions per unit of uv2, or per object-space unit for projections.",
    rotate="Counter-clockwise rotation of the pattern.",
    strength="Height scale of the detail.",
)
@click.option(
    "--sharpness",
    type=Number(0, 64),
    default=4.0,
    show_default=True,
    help="Exponent of the triplanar blend weights |N_i|^k.",
)
@click.option(
    "--padding",
    type=Integer(-1, 4096),
    default=16,
    show_default=True,
    metavar="PX",
    help="Texels of dilation around UV islands (0 = none, -1 = fill the whole map).",
)
@click.option(
    "--macro",
    type=INPUT,
    default=None,
    help="Also blend the transferred detail onto this macro normal map (same layout).",
)
@click.option(
    "--method",
    type=click.Choice(METHODS),
    default=DEFAULT_METHOD,
    show_default=True,
    help="Blend method with --macro.",
)
@_convention
@_detail_convention
@_encoding
@_writer
def transfer(
    mesh: Path,
    detail: Path,
    out: Path,
    size: int | tuple[int, int] | None,
    projection: str,
    axis: str,
    tile: tuple[float, float],
    offset: tuple[float, float],
    rotate: float,
    strength: float,
    sharpness: float,
    padding: int,
    macro: Path | None,
    method: str,
    convention: str,
    detail_convention: str | None,
    encoding: str,
    options: tuple[str, ...],
) -> None:
    """Bake the tileable DETAIL normal map into the UV layout of MESH (OBJ, glTF, GLB); write OUT.

    Every texel of the macro UV layout gets the detail as the mesh shows it through its second
    UV set or an object-space projection, rotated into the macro map's MikkTSpace tangent
    frame, so OUT can be blended onto the macro map texel by texel (or pass --macro to do it
    here). UV islands are dilated by --padding texels so mip levels don't bleed at seams.

    \b
    Example:
      bakeshop normals transfer rifle.glb wood_n.png wood_uv.png --size 2048 --tile 4
      bakeshop normals transfer rifle.obj grit_n.png rifle_final.png --projection triplanar \\
          --tile 30 --macro rifle_n.png
    """
    from bakeshop.io import load_mesh
    from bakeshop.normals.blend import blend
    from bakeshop.normals.transfer import transfer_detail

    refuse_overwriting_inputs(out, mesh, detail, *([macro] if macro else []))
    base = None
    shape = None
    depths = []
    if size is not None:
        wanted = parse_size(size)
        shape = (wanted, wanted) if isinstance(wanted, int) else (wanted[1], wanted[0])
    if macro is not None:
        base, macro_bits = read_map(macro, convention, encoding, "--convention")
        depths.append(macro_bits)
        if shape is not None and shape != base.shape[:2]:
            raise ArgumentError(
                f"--size {size} differs from the macro map's {base.shape[1]}x{base.shape[0]}",
                macro,
            )
        shape = base.shape[:2]
    elif shape is None:
        raise ArgumentError("give --size (or --macro, whose size is used)")
    d, detail_bits = read_map(
        detail, detail_convention or convention, encoding, "--detail-convention"
    )
    depths.append(detail_bits)
    m = load_mesh(mesh)
    result, covered = transfer_detail(
        m,
        d,
        shape,
        projection=projection,
        tile=tile,
        offset=offset,
        rotation=rotate,
        axis=axis,
        sharpness=sharpness,
        strength=strength,
        padding=None if padding < 0 else padding,
    )
    if base is not None:
        result = blend(base, result, method=method)
    bits = write_normal_map(
        out,
        result,
        convention=convention,
        encoding=encoding,
        inputs=depths,
        **parse_options(options),
    )
    h, w = shape
    click.echo(
        f"wrote {out}: {w}x{h} {_depth_text(bits)}, {len(m.faces)} triangles, "
        f"{covered.mean():.1%} of texels covered, {projection} projection"
        + (f", blended with {method}" if base is not None else "")
    )


@normals.command("from-height", context_settings=CONTEXT)
@click.argument("height", type=INPUT)
@click.argument("out", type=OUTPUT)
@click.option(
    "--strength",
    type=Number(-1e4, 1e4),
    default=1.0,
    show_default=True,
    metavar="S",
    help="Height in texels of one unit of stored height (an 8-bit map's full range).",
)
@click.option(
    "--derivative",
    type=click.Choice(["central", "sobel"]),
    default="central",
    show_default=True,
    help="Central differences, or Sobel (smoother).",
)
@click.option("--no-wrap", is_flag=True, help="Clamp at the edges (the map is not tileable).")
@click.option(
    "--channel", type=Integer(0, 3), default=0, show_default=True, help="Channel of HEIGHT to use."
)
@_convention
@_encoding
@_writer
def from_height(
    height: Path,
    out: Path,
    strength: float,
    derivative: str,
    no_wrap: bool,
    channel: int,
    convention: str,
    encoding: str,
    options: tuple[str, ...],
) -> None:
    """Make a normal map OUT from the height map HEIGHT.

    n = normalize(-S dh/dx, -S dh/dy, 1) with y up the picture; wraps around the edges unless
    --no-wrap (tileable detail maps should wrap).

    \b
    Example:
      bakeshop normals from-height grit_height.png grit_n.png --strength 8
      bakeshop normals from-height rock_h.exr rock_n.png --derivative sobel --convention dx
    """
    from bakeshop.io import read_image
    from bakeshop.normals.height import height_to_normal

    refuse_overwriting_inputs(out, height)
    image, meta = read_image(height, with_metadata=True)
    if not 0 <= channel < image.shape[2]:
        raise ArgumentError(
            f"--channel {channel}: the file has {image.shape[2]} channel(s)", height
        )
    n = height_to_normal(
        image[:, :, channel], strength=strength, derivative=derivative, wrap=not no_wrap
    )
    bits = write_normal_map(
        out,
        n,
        convention=convention,
        encoding=encoding,
        inputs=[stored_bits(meta)],
        **parse_options(options),
    )
    click.echo(
        f"wrote {out}: {n.shape[1]}x{n.shape[0]} {_depth_text(bits)} normals ({derivative}, "
        f"strength {strength:g}, {'clamped' if no_wrap else 'wrapped'} edges)"
    )


@normals.command(context_settings=CONTEXT)
@click.argument("maps", nargs=-1, required=True, type=INPUT)
@click.option("--xy", is_flag=True, help="Two-channel (BC5) maps: z is reconstructed.")
@click.option(
    "--tolerance",
    type=Number(0, 2),
    default=0.1,
    show_default=True,
    help="Allowed | |n| - 1 | of the stored vectors.",
)
@_encoding
def check(maps: tuple[Path, ...], xy: bool, tolerance: float, encoding: str) -> int:
    """Report texels of normal MAPS that are far from unit length or point into the surface.

    Exits with status 1 when any texel is flagged (0 when all maps are clean), so it can gate
    an asset pipeline.

    \b
    Example:
      bakeshop normals check textures/*_n.png
      bakeshop normals check rifle_n_bc5.png --xy
    """
    from bakeshop.io import read_image
    from bakeshop.normals.encoding import check_normals

    status = 0
    for path in maps:
        r = check_normals(
            read_image(path),
            encoding=encoding,
            channels="xy" if xy else "xyz",
            length_tolerance=tolerance,
        )
        verdict = "ok" if r.ok else "FLAGGED"
        click.echo(
            f"{path}: {verdict}: {r.texels} texels, {r.off_unit} off unit length "
            f"(> {tolerance:g}), {r.into_surface} into the surface, {r.invalid} NaN/Inf; "
            f"length {r.min_length:.3f}..{r.max_length:.3f}"
        )
        for row, col, length, z in r.worst[:5]:
            click.echo(f"  row {row}, column {col}: length {length:.3f}, z {z:.3f}")
        if not r.ok and r.into_surface > r.texels // 2 and not xy:
            click.echo("  (most texels point inwards: is it a two-channel map? try --xy)")
        status |= not r.ok
    return status


@normals.command(context_settings=CONTEXT)
@click.argument("source", type=INPUT)
@click.argument("target", type=OUTPUT)
@click.option(
    "--from",
    "source_convention",
    type=click.Choice(CONVENTIONS),
    required=True,
    help="Convention of SOURCE.",
)
@click.option(
    "--to",
    "target_convention",
    type=click.Choice(CONVENTIONS),
    required=True,
    help="Convention of TARGET.",
)
@click.option("--xy", is_flag=True, help="SOURCE is a two-channel (BC5) map: rebuild z.")
@click.option("--renormalize", is_flag=True, help="Rescale every vector to unit length.")
@_encoding
@_writer
def convert(
    source: Path,
    target: Path,
    source_convention: str,
    target_convention: str,
    xy: bool,
    renormalize: bool,
    encoding: str,
    options: tuple[str, ...],
) -> None:
    """Convert a normal map between the OpenGL (Y+) and DirectX (Y-) conventions.

    Without --xy or --renormalize only the green channel changes (G -> 1 - G, exactly: an
    8-bit value c becomes 255 - c), so converting twice gives back the same file.

    \b
    Example:
      bakeshop normals convert brick_dx.png brick_gl.png --from dx --to gl
      bakeshop normals convert rifle_bc5.png rifle_n.png --from gl --to gl --xy
    """
    from bakeshop.io import read_image, write_image
    from bakeshop.normals.encoding import convert_normal_map

    refuse_overwriting_inputs(target, source)
    image, meta = read_image(source, with_metadata=True)
    if image.shape[2] < 3 and not xy:
        raise ArgumentError("a normal map needs at least three channels (or --xy)", source)
    values = convert_normal_map(
        image,
        source=source_convention,
        target=target_convention,
        encoding=encoding,
        channels="xy" if xy else "xyz",
        renormalize=renormalize,
    )
    writer_options: dict[str, Any] = dict(parse_options(options))
    bits = None
    if is_picture(target):
        requested = writer_options.pop("bits", None)
        bits, note = output_bits(
            target,
            requested=None if requested is None else picture_bits(requested, target),
            inputs=[stored_bits(meta)],
        )
        if target.suffix.lower() == ".png":
            writer_options["bits"] = bits
        if note:
            warn(note, target)
    write_image(target, values, **writer_options)
    click.echo(f"wrote {target}: {_depth_text(bits)}, {source_convention} -> {target_convention}")


def register(group: click.Group) -> None:
    """Add the ``normals`` command group to the root command."""
    group.add_command(normals)
