"""Reading and writing environments for the commands, in any layout: one image file, six
``{face}`` files, or a float cube map container (.dds, .ktx, .ktx2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bakeshop.cli._common import input_layout
from bakeshop.errors import ArgumentError

#: single-file float texture containers (cube maps, mip chains, 2-D tables).
CONTAINERS = (".dds", ".ktx", ".ktx2")
#: the layout name for six files, one per face (``{face}`` in the file name).
FACES = "faces"
#: largest finite float16; containers holding a larger value are written as float32.
HALF_MAX = 65504.0


def is_cube(layout: str) -> bool:
    """True for the cube layouts: ``cube`` and six ``faces`` files."""
    return layout in ("cube", FACES)


def is_container(path: Path) -> bool:
    """True when ``path`` names a .dds, .ktx or .ktx2 file."""
    return Path(path).suffix.lower() in CONTAINERS


def face_paths(pattern: Path, short: bool = False) -> list[Path]:
    """The six file names of ``pattern`` with ``{face}`` replaced, in OpenGL face order."""
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    names = FACE_NAMES_SHORT if short else FACE_NAMES
    return [Path(str(pattern).replace("{face}", name)) for name in names]


def auto_filter(image, src: str, dst: str, size=None) -> str:
    """The filter ``--filter auto`` means for remapping ``image`` from ``src`` to ``dst``:
    ``"area"`` (the energy-preserving average) when the output holds at most half as many
    directions as the input (a real downsampling, where a point filter aliases), else
    ``"bilinear"``: near the input's size the area filter must cut source texels into parts,
    which costs 7-13 s and ~1.3 GB on a first 4096x2048 <-> 6x1024^2 call (a single command
    does not reuse the plan), while bilinear moves the total energy by ~0.2-1% only for a
    one-texel sun. ``size`` None is the default
    :func:`sphere.remap` picks (about as many directions as the input)."""
    from bakeshop import sphere

    src_layout, dst_layout = sphere.layout(src), sphere.layout(dst)
    in_texels = int(
        np.count_nonzero(src_layout.solid_angles(image.shape[: 3 if src == "cube" else 2]))
    )
    shape = dst_layout.shape(size if size is not None else dst_layout.default_size(in_texels))
    out_texels = int(np.count_nonzero(dst_layout.solid_angles(shape)))
    return "area" if 2 * out_texels <= in_texels else "bilinear"


def describe(image, layout: str) -> str:
    """``'latlong 1024x512'`` or ``'cube (6 faces of 256x256)'``: for the commands' summaries."""
    if is_cube(layout):
        return f"cube (6 faces of {image.shape[2]}x{image.shape[1]})"
    return f"{layout} {image.shape[1]}x{image.shape[0]}"


def as_picture(image, layout: str):
    """``image`` as one picture: a cube becomes a vertical cross, other layouts are pictures."""
    from bakeshop import sphere

    return sphere.cube_to_view(image, "cross-vertical") if is_cube(layout) else image


def read_container(path: Path):
    """``(mips, metadata)`` of a .dds, .ktx or .ktx2 file."""
    from bakeshop.io.dds import read_dds
    from bakeshop.io.ktx import read_ktx
    from bakeshop.io.ktx2 import read_ktx2

    read = {".dds": read_dds, ".ktx": read_ktx, ".ktx2": read_ktx2}[Path(path).suffix.lower()]
    return read(path)


def write_container(path: Path, mips, *, float32: bool = False) -> None:
    """Write ``mips`` to a .dds, .ktx or .ktx2 file: half floats unless ``float32`` or a value
    (the sun) would overflow them."""
    from bakeshop.io.dds import write_dds
    from bakeshop.io.ktx import write_ktx
    from bakeshop.io.ktx2 import write_ktx2

    write = {".dds": write_dds, ".ktx": write_ktx, ".ktx2": write_ktx2}[Path(path).suffix.lower()]
    peak = max(float(np.nanmax(np.abs(level))) for level in mips)
    dtype = "float16" if not float32 and peak <= HALF_MAX else "float32"
    write(path, mips, dtype=dtype)


def read_environment(path: Path, layout: str | None, convention: str = "opengl", short=False):
    """``(image, layout, how the layout was known)`` of an input: one image file, six
    ``{face}`` files or a .dds/.ktx/.ktx2 cube map (cube layouts in the engine
    ``convention``)."""
    from bakeshop import sphere
    from bakeshop.io import check_input, read_image

    if "{face}" in str(path):
        if layout is not None and not is_cube(layout):
            raise ArgumentError(f"a {{face}} input is six cube faces, not {layout}", path)
        faces = []
        for face_path in face_paths(path, short):
            check_input(face_path)
            faces.append(read_image(face_path))
        shapes = {f.shape for f in faces}
        if len(shapes) != 1 or faces[0].shape[0] != faces[0].shape[1]:
            raise ArgumentError(
                f"the six faces must be square and equal; got {sorted(shapes)}", path
            )
        cube = sphere.faces_to_cube(np.stack(faces), convention=convention)
        return cube, "cube", "six face files"
    check_input(path)
    if is_container(path):
        mips, meta = read_container(path)
        if not meta.get("cube"):
            raise ArgumentError("this texture is not a cube map", path)
        faces = mips[0]
        if faces.shape[-1] == 4 and np.all(faces[..., 3] == 1):
            # DDS and KTX have no RGB half-float format: the writers pad RGB with an opaque
            # alpha, which an environment does not carry (and .hdr output cannot store)
            faces = faces[..., :3]
        return sphere.faces_to_cube(faces, convention=convention), "cube", "a cube map file"
    image = read_image(path)
    if layout is not None and is_cube(layout):
        raise ArgumentError(
            "a cube input is six files (put {face} in the name), a .dds, .ktx or .ktx2 file, "
            "or a cross or strip picture (--from cross-vertical, ...)",
            path,
        )
    if layout is not None:
        return image, layout, "given"
    guessed = input_layout(image, None, path)
    h, w = image.shape[:2]
    return image, guessed, f"guessed from its {w}x{h} shape"


def write_environment(
    target: Path, image, layout: str, convention: str = "opengl", short: bool = False
) -> list[Path]:
    """Write a flat layout to ``target``; a cube to six ``{face}`` files or one
    .dds/.ktx/.ktx2 file, as the engine ``convention`` loads it. Returns the paths written."""
    from bakeshop import sphere
    from bakeshop.io import write_image

    if not is_cube(layout):
        write_image(target, image)
        return [target]
    faces = sphere.cube_to_faces(image, convention=convention)
    if is_container(target):
        write_container(target, [faces])
        return [target]
    paths = face_paths(target, short)
    for path, face in zip(paths, faces, strict=True):
        write_image(path, face)
    return paths
