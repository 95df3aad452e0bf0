"""``bakeshop remap``: convert a panorama between layouts (latlong, light probes, cube maps)."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import input_layout, parse_size, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError

#: single-file float cube map containers (level 0 only here).
CUBE_CONTAINERS = (".dds", ".ktx")
#: the layout name for six files, one per face (``{face}`` in the file name).
FACES = "faces"


def _layouts() -> list[str]:
    from bakeshop.sphere import LAYOUT_NAMES

    return [*LAYOUT_NAMES, FACES]


def _face_paths(pattern: Path, short: bool) -> list[Path]:
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    names = FACE_NAMES_SHORT if short else FACE_NAMES
    return [Path(str(pattern).replace("{face}", name)) for name in names]


def _is_cube(layout: str) -> bool:
    return layout in ("cube", FACES)


def read_environment(path: Path, layout: str | None, convention: str, short: bool):
    """(image, layout, how the layout was known) of an input: one image file, six ``{face}``
    files or a .dds/.ktx cube map (cube layouts in the engine ``convention``)."""
    from bakeshop import sphere
    from bakeshop.io import read_image

    if "{face}" in str(path):
        if layout is not None and not _is_cube(layout):
            raise ArgumentError(f"a {{face}} input is six cube faces, not {layout}", path)
        faces = []
        for face_path in _face_paths(path, short):
            if not face_path.is_file():
                raise ArgumentError("missing cube face file", face_path)
            faces.append(read_image(face_path))
        shapes = {f.shape for f in faces}
        if len(shapes) != 1 or faces[0].shape[0] != faces[0].shape[1]:
            raise ArgumentError(
                f"the six faces must be square and equal; got {sorted(shapes)}", path
            )
        cube = sphere.faces_to_cube(np.stack(faces), convention=convention)
        return cube, "cube", "six face files"
    if not path.is_file():
        raise ArgumentError("no such file", path)
    if path.suffix.lower() in CUBE_CONTAINERS:
        from bakeshop.io.dds import read_dds
        from bakeshop.io.ktx import read_ktx

        mips, meta = (read_dds if path.suffix.lower() == ".dds" else read_ktx)(path)
        if not meta.get("cube"):
            raise ArgumentError("this texture is not a cube map", path)
        return sphere.faces_to_cube(mips[0], convention=convention), "cube", "a cube map file"
    image = read_image(path)
    if layout is not None and _is_cube(layout):
        raise ArgumentError(
            "a cube input is six files (put {face} in the name), a .dds or .ktx file, or a "
            "cross or strip picture (--from cross-vertical, ...)",
            path,
        )
    if layout is not None:
        return image, layout, "given"
    guessed = input_layout(image, None, path)
    h, w = image.shape[:2]
    return image, guessed, f"guessed from its {w}x{h} shape"


def write_environment(target: Path, image, layout: str, convention: str, short: bool) -> list:
    """Write a flat layout to ``target``; a cube to six ``{face}`` files or a .dds/.ktx file,
    as the engine ``convention`` loads it. Returns the paths written."""
    from bakeshop import sphere
    from bakeshop.io import write_image

    if not _is_cube(layout):
        write_image(target, image)
        return [target]
    faces = sphere.cube_to_faces(image, convention=convention)
    if target.suffix.lower() in CUBE_CONTAINERS:
        from bakeshop.io.dds import write_dds
        from bakeshop.io.ktx import write_ktx

        write = write_dds if target.suffix.lower() == ".dds" else write_ktx
        # half floats unless a value (the sun) would overflow them
        dtype = "float16" if np.nanmax(np.abs(faces)) <= 65504 else "float32"
        write(target, [faces], dtype=dtype)
        return [target]
    paths = _face_paths(target, short)
    for path, face in zip(paths, faces, strict=True):
        write_image(path, face)
    return paths


def _check_target(target: Path, layout: str) -> None:
    if _is_cube(layout):
        if "{face}" not in str(target) and target.suffix.lower() not in CUBE_CONTAINERS:
            raise ArgumentError(
                "a cube is written as six files: put {face} in the output name (sky_{face}.exr "
                "gives sky_posx.exr ... sky_negz.exr), write one .dds or .ktx file, or choose a "
                "cross or strip (--to cross-vertical)",
                target,
            )
    elif "{face}" in str(target):
        raise ArgumentError(f"{{face}} in the output name needs --to faces, not {layout}", target)


def _describe(layout: str, shape) -> str:
    if len(shape) == 3:
        return f"{layout} (6 faces of {shape[2]}x{shape[1]})"
    return f"{layout} {shape[1]}x{shape[0]}"


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("target", type=click.Path(dir_okay=False, writable=True, path_type=Path))
@click.option(
    "--from",
    "src",
    type=click.Choice(_layouts()),
    help="Layout of SOURCE. Default: guessed from its shape (2:1 latlong, 3:4 and 4:3 crosses, "
    "6:1 and 1:6 strips; a square image is ambiguous: name it).",
)
@click.option("--to", "dst", type=click.Choice(_layouts()), required=True, help="Layout of TARGET.")
@click.option(
    "--size",
    "size_text",
    metavar="N|WxH",
    help="Output size: WxH for a latlong (360x180) or N (its height), one edge for square "
    "layouts, the face edge for cubes, crosses and strips. Default: about as many texels as "
    "SOURCE.",
)
@click.option(
    "--filter",
    "filter_name",
    type=click.Choice(["auto", "nearest", "bilinear", "area"]),
    default="auto",
    show_default=True,
    help="Sampling filter; auto is area (energy-preserving average) when the output has fewer "
    "texels than SOURCE, else bilinear.",
)
@click.option(
    "--rotate",
    metavar="YAW,PITCH,ROLL",
    help="Rotate the environment, degrees: yaw about +Y (positive turns the view ahead to the "
    "left), pitch about +X (positive lifts it), roll about +Z; applied roll, pitch, yaw.",
)
@click.option(
    "--convention",
    type=click.Choice(["opengl", "vulkan", "directx"]),
    default="opengl",
    show_default=True,
    help="Face set of cube files (faces, .dds, .ktx), read and written: opengl and vulkan "
    "sample the same faces; directx is the left-handed (z forward) set.",
)
@click.option(
    "--short-face-names",
    is_flag=True,
    help="{face} is px, nx, py, ny, pz, nz instead of posx, negx, posy, negy, posz, negz.",
)
def remap(source, target, src, dst, size_text, filter_name, rotate, convention, short_face_names):
    """Convert the panorama SOURCE from one layout to another and write TARGET.

    Layouts: latlong (equirectangular), angular (Debevec light probe), mirrorball, octahedral,
    dual-paraboloid, cube maps as six files (faces: {face} in the name, or one .dds/.ktx
    file) and as pictures: cross-vertical, cross-horizontal, strip-horizontal,
    strip-vertical. Crosses and strips are drawn as HDRShop and cmft draw them (seen from
    inside the cube, unmirrored, the centre looking forward); six face files follow
    --convention. Seams are filtered across (cube edges, latlong poles). See
    docs/panoramas.md.

    \b
    Example:
      bakeshop remap probe.hdr cross.exr --to cross-vertical --size 512
      bakeshop remap ball.hdr sky.hdr --from mirrorball --to latlong --size 2048x1024
      bakeshop remap sky.exr sky_{face}.exr --to faces --size 1024 --convention directx
      bakeshop remap sky_{face}.hdr sky.exr --from faces --to latlong --rotate 90,0,0
    """
    from bakeshop import progress, sphere

    refuse_overwriting_inputs(target, source)
    _check_target(target, dst)
    rotation = None
    if rotate is not None:
        try:
            rotation = [float(v) for v in rotate.split(",")]
        except ValueError:
            rotation = []
        if len(rotation) != 3:
            raise ArgumentError(f"--rotate takes YAW,PITCH,ROLL in degrees; got {rotate!r}")
    with progress.step(f"reading {source}"):
        image, src, how = read_environment(source, src, convention, short_face_names)
    src_layout = sphere.layout(src)
    dst_name = "cube" if dst == FACES else dst
    dst_layout = sphere.layout(dst_name)
    size = None if size_text is None else parse_size(size_text)
    in_texels = int(
        np.count_nonzero(src_layout.solid_angles(image.shape[: 3 if src == "cube" else 2]))
    )
    if filter_name == "auto":
        shape = dst_layout.shape(size if size is not None else dst_layout.default_size(in_texels))
        out_texels = int(np.count_nonzero(dst_layout.solid_angles(shape)))
        filter_name = "area" if out_texels < in_texels else "bilinear"
    with progress.step(f"remapping {src} -> {dst_name} ({filter_name})"):
        out = sphere.remap(image, src, dst_name, size, filter=filter_name, rotation=rotation)
    with progress.step(f"writing {target}"):
        written = write_environment(target, out, dst, convention, short_face_names)
    shape = out.shape[:-1]
    where = written[0] if len(written) == 1 else f"{written[0]} ... {written[-1].name}"
    click.echo(
        f"wrote {where}: {_describe(dst_name, shape)} from {_describe(src, image.shape[:-1])} "
        f"({how}), {filter_name}" + (f", rotated {rotate}" if rotate else "")
    )


def register(group: click.Group) -> None:
    group.add_command(remap)
