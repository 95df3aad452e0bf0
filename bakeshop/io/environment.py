"""Environments in files: any layout as one image, six ``{face}`` files, or a DDS/KTX/KTX2 cube
map; cube mip chains; and 2-D lookup tables.

>>> from bakeshop.io import read_environment, write_environment
>>> env = read_environment("probe.hdr")                 # layout guessed from the 2:1 shape
>>> env.image.shape, env.layout                         # ((512, 1024, 3), 'latlong')
>>> write_environment("env_{face}.exr", cube, "cube")   # six OpenGL faces

A cube in memory is bakeshop's ``(6, S, S, C)`` in OpenGL order and orientation; in files it
is the face set of an engine ``convention`` (:func:`bakeshop.sphere.cube_to_faces`).

OpenEXR environments say their mapping in the standard ``envmap`` attribute (``ImfEnvmap.h``):
``latlong`` and ``cube`` are read as bakeshop's layouts ``openexr-latlong`` and
``openexr-cube`` (the exact mappings the header defines, see docs/conventions.md), and an
environment written in one of them to an .exr file carries the attribute.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Literal, NamedTuple, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.io._files import check_input
from bakeshop.io.containers import is_container, read_container, write_container

#: the placeholder a file name uses for the six faces of a cube (``env_{face}.hdr``).
FACE_FIELD = "{face}"
#: the layout name of a cube stored as six files (``{face}`` in the name) or one container.
FACES = "faces"
#: the placeholder for the level of a mip chain written as one file per level.
MIP_FIELD = "{mip}"
#: OpenEXR ``envmap`` attribute value -> the bakeshop layout that is its mapping, and back.
ENVMAP_LAYOUTS = {"latlong": "openexr-latlong", "cube": "openexr-cube"}
LAYOUT_ENVMAPS = {layout: envmap for envmap, layout in ENVMAP_LAYOUTS.items()}


class EnvironmentFile(NamedTuple):
    """What :func:`read_environment` returns."""

    #: ``(H, W, C)`` float32, or ``(6, S, S, C)`` for a cube.
    image: np.ndarray
    #: its layout name (``"cube"`` for face files and containers).
    layout: str
    #: how the layout was known: ``"given"``, ``"guessed from its 1024x512 shape"``, ...
    how: str


def is_cube(layout: str) -> bool:
    """True for the cube layouts: ``cube`` (in memory) and ``faces`` (in files)."""
    return layout in ("cube", FACES)


def face_paths(pattern: str | os.PathLike, *, short: bool = False) -> list[Path]:
    """The six file names of ``pattern`` with ``{face}`` replaced (posx ... negz, or px ... nz
    with ``short``), in OpenGL face order."""
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    names = FACE_NAMES_SHORT if short else FACE_NAMES
    return [Path(str(pattern).replace(FACE_FIELD, name)) for name in names]


def describe(image: np.ndarray, layout: str) -> str:
    """``'latlong 1024x512'`` or ``'cube (6 faces of 256x256)'``: for summaries."""
    if is_cube(layout):
        return f"cube (6 faces of {image.shape[2]}x{image.shape[1]})"
    return f"{layout} {image.shape[1]}x{image.shape[0]}"


def as_picture(image: np.ndarray, layout: str) -> np.ndarray:
    """``image`` as one picture: a cube becomes a vertical cross, other layouts are pictures."""
    from bakeshop.sphere import cube_to_view

    return cube_to_view(image, "cross-vertical") if is_cube(layout) else image


def guess_input_layout(image: np.ndarray, path: str | os.PathLike | None = None) -> str:
    """The one layout whose pictures have ``image``'s shape
    (:func:`bakeshop.sphere.guess_layout`); :class:`ArgumentError` naming the candidates when
    the shape fits several (a square may be angular, mirror ball or octahedral) or none."""
    from bakeshop.sphere import guess_layout

    h, w = image.shape[:2]
    candidates = guess_layout(h, w)
    if len(candidates) != 1:
        which = ", ".join(candidates) if candidates else "none"
        raise ArgumentError(
            f"cannot tell the layout of {with_article(w)}x{h} image (candidates: {which}); name it "
            "(--from LAYOUT, or layout=)",
            path,
        )
    return candidates[0]


@overload
def read_environment(
    path: str | os.PathLike,
    layout: str | None = None,
    *,
    convention: str = "opengl",
    short: bool = False,
    with_metadata: Literal[False] = False,
) -> EnvironmentFile: ...


@overload
def read_environment(
    path: str | os.PathLike,
    layout: str | None = None,
    *,
    convention: str = "opengl",
    short: bool = False,
    with_metadata: Literal[True],
) -> tuple[EnvironmentFile, dict]: ...


@overload
def read_environment(
    path: str | os.PathLike,
    layout: str | None = None,
    *,
    convention: str = "opengl",
    short: bool = False,
    with_metadata: bool,
) -> EnvironmentFile | tuple[EnvironmentFile, dict]: ...


def read_environment(
    path: str | os.PathLike,
    layout: str | None = None,
    *,
    convention: str = "opengl",
    short: bool = False,
    with_metadata: bool = False,
) -> EnvironmentFile | tuple[EnvironmentFile, dict]:
    """Read an environment: one image file, six ``{face}`` files, or a .dds/.ktx/.ktx2 cube.

    Parameters
    ----------
    path : path-like
        One image (any layout), a name with ``{face}`` (six files, see :func:`face_paths`), or
        a cube map container (its level 0 is read).
    layout : str, optional
        The layout of a single image (:data:`bakeshop.sphere.LAYOUT_NAMES`). When None: an
        OpenEXR file's ``envmap`` attribute if it has one (``latlong`` is ``openexr-latlong``,
        ``cube`` is ``openexr-cube``), else guessed from the shape
        (:func:`guess_input_layout`). A layout given overrides the attribute (``how`` says
        so). Face files and containers are cubes (``"cube"`` or ``"faces"``).
    convention : {"opengl", "vulkan", "directx"}
        The engine face set of face files and containers (:func:`bakeshop.sphere.faces_to_cube`).
    short : bool
        ``{face}`` stands for px ... nz instead of posx ... negz.
    with_metadata : bool
        Also return what the file says (:func:`bakeshop.io.read_image`'s metadata; the first
        face's for six files, with ``"stored"`` the deepest of the six; the container's).

    Returns
    -------
    EnvironmentFile
        ``(image, layout, how)``; a cube is bakeshop's internal ``(6, S, S, C)``.
    metadata : dict, only with ``with_metadata=True``
    """
    env, meta = _read_environment(path, layout, convention, short)
    return (env, meta) if with_metadata else env


def _read_environment(
    path: str | os.PathLike, layout: str | None, convention: str, short: bool
) -> tuple[EnvironmentFile, dict]:
    from bakeshop import sphere
    from bakeshop.io import read_image

    path = Path(path)
    if FACE_FIELD in str(path):
        if layout is not None and not is_cube(layout):
            raise ArgumentError(f"a {{face}} input is six cube faces, not {layout}", path)
        faces, metas = [], []
        for face_path in face_paths(path, short=short):
            check_input(face_path)
            face, meta = read_image(face_path, with_metadata=True)
            faces.append(face)
            metas.append(meta)
        shapes = {f.shape for f in faces}
        if len(shapes) != 1 or faces[0].shape[0] != faces[0].shape[1]:
            raise ArgumentError(
                f"the six faces must be square and equal; got {sorted(shapes)}", path
            )
        cube = sphere.faces_to_cube(np.stack(faces), convention=convention)
        meta = dict(metas[0], stored=max((m["stored"] for m in metas), key=_depth), files=6)
        return EnvironmentFile(cube, "cube", "six face files"), meta
    check_input(path)
    if is_container(path):
        mips, meta = read_container(path)
        if not meta.get("cube"):
            raise ArgumentError("this texture is not a cube map", path)
        cube = sphere.faces_to_cube(_without_padding(mips[0]), convention=convention)
        return EnvironmentFile(cube, "cube", "a cube map file"), dict(meta)
    image, meta = read_image(path, with_metadata=True)
    envmap = ENVMAP_LAYOUTS.get(meta.get("envmap", ""))

    if layout is not None and is_cube(layout):
        raise ArgumentError(
            "a cube input is six files (put {face} in the name), a .dds, .ktx or .ktx2 file, "
            "or a cross or strip picture (cross-vertical, ...)",
            path,
        )
    if layout is not None:
        try:
            sphere.layout(layout).check_shape(image.shape[:2])
        except ArgumentError as e:
            raise ArgumentError(e.reason, path) from None
        if envmap is not None and envmap != layout:
            how = f"given, over its envmap attribute ({envmap})"
            return EnvironmentFile(image, layout, how), meta
        return EnvironmentFile(image, layout, "given"), meta
    if envmap is not None:
        try:
            sphere.layout(envmap).check_shape(image.shape[:2])
        except ArgumentError as e:
            raise ArgumentError(f"its envmap attribute says {meta['envmap']}, but {e.reason}",
                                path) from None  # fmt: skip
        return EnvironmentFile(image, envmap, f"its envmap attribute is {meta['envmap']}"), meta
    guessed = guess_input_layout(image, path)
    h, w = image.shape[:2]
    return EnvironmentFile(image, guessed, f"guessed from its {w}x{h} shape"), meta


def _depth(stored: str) -> int:
    """Sort key of a stored sample type: an integer type's bits; floats (half, float32, rgbe)
    above every integer type."""
    text = str(stored)
    if text.startswith("uint"):
        return int("".join(ch for ch in text if ch.isdigit()) or 0)
    return 1000


def _without_padding(faces: np.ndarray) -> np.ndarray:
    """DDS and KTX have no RGB half-float format: the writers pad RGB with an opaque alpha,
    which an environment does not carry (and .hdr output cannot store)."""
    if faces.shape[-1] == 4 and np.all(faces[..., 3] == 1):
        return faces[..., :3]
    return faces


def write_environment(
    path: str | os.PathLike,
    image: ArrayLike,
    layout: str,
    *,
    convention: str = "opengl",
    short: bool = False,
    float32: bool = False,
    description: str | None = None,
) -> list[Path]:
    """Write an environment; a cube to six ``{face}`` files or one .dds/.ktx/.ktx2 file, as the
    engine ``convention`` loads it.

    Parameters
    ----------
    path : path-like
        One image file, or for a cube a name with ``{face}`` or a container.
    image : array
        In ``layout``: ``(H, W, C)``, or ``(6, S, S, C)`` for the cube.
    layout : str
        Any of :data:`bakeshop.sphere.LAYOUT_NAMES`, or ``"faces"`` (a cube). OpenEXR's layouts
        ``openexr-latlong`` and ``openexr-cube`` are written to .exr files only, with their
        ``envmap`` attribute (``latlong``, ``cube``): in any other format they would read back
        as another layout.
    convention : {"opengl", "vulkan", "directx"}
    short : bool
        ``{face}`` becomes px ... nz.
    float32 : bool
        Containers: store 32-bit floats (default: half floats unless a value overflows them).
    description : str, optional
        A line recorded in each picture file (PNG, JPEG, TGA: see :mod:`bakeshop.io.ldr`),
        such as how a picture's exposure was chosen; other formats ignore it.

    Returns
    -------
    list of Path
        The files written.
    """
    from bakeshop import sphere
    from bakeshop.io import write_image

    path = Path(path)
    check_openexr_target(path, layout)
    if layout in LAYOUT_ENVMAPS:
        write_image(path, image, envmap=LAYOUT_ENVMAPS[layout])
        return [path]
    options = _picture_options(path, description)
    if not is_cube(layout):
        write_image(path, image, **options)
        return [path]
    faces = sphere.cube_to_faces(image, convention=convention)
    if is_container(path):
        write_container(path, [faces], float32=float32)
        return [path]
    if FACE_FIELD not in str(path):
        raise ArgumentError(
            "a cube is written as six files (put {face} in the name) or one .dds, .ktx or "
            ".ktx2 file; for one picture, write a cross (cross-vertical, ...)",
            path,
        )
    paths = face_paths(path, short=short)
    for face_path, face in zip(paths, faces, strict=True):
        write_image(face_path, face, **options)
    return paths


def check_openexr_target(path: str | os.PathLike, layout: str) -> None:
    """Refuse to write OpenEXR's layouts (``openexr-latlong``, ``openexr-cube``) anywhere but an
    .exr file: only its ``envmap`` attribute says how to read them (commands call this before
    any work, :func:`write_environment` again when writing)."""
    from bakeshop.io import codec_for

    if layout in LAYOUT_ENVMAPS and codec_for(path) != "exr":
        raise ArgumentError(
            f"{layout} is OpenEXR's environment mapping: write it to an .exr file (its envmap "
            "attribute says how to read it), or convert to another layout",
            path,
        )


def _picture_options(path: Path, description: str | None) -> dict:
    """``{"description": ...}`` for the formats that record one (PNG, JPEG, TGA), else ``{}``."""
    from bakeshop.io import HDR_CODECS, codec_for

    if description is None or is_container(path) or codec_for(path) in HDR_CODECS:
        return {}
    return {"description": description}


def check_chain_path(path: str | os.PathLike) -> None:
    """Refuse a mip chain target that is neither a container nor a ``{mip}`` pattern."""
    if not is_container(path) and MIP_FIELD not in str(path):
        raise ArgumentError(
            "a mip chain is one .dds, .ktx or .ktx2 file, or a name with {mip} (and {face} for "
            "six face files per level, else one vertical cross per level): "
            "spec_{mip}_{face}.hdr",
            path,
        )


def write_chain(
    path: str | os.PathLike,
    chain: Sequence[ArrayLike],
    *,
    convention: str = "opengl",
    float32: bool = False,
    description: str | None = None,
) -> list[Path]:
    """Write a cube mip chain (a list of ``(6, S, S, C)`` levels, level 0 first): one
    .dds/.ktx/.ktx2 file, or files per level (``{mip}`` in the name) with six faces each
    (``{face}``) or one vertical cross each. Returns the paths written; a container holds
    float16 unless ``float32`` or a value would overflow it. ``description`` is recorded in
    picture files (see :func:`write_environment`)."""
    from bakeshop import sphere
    from bakeshop.io import write_image

    path = Path(path)
    check_chain_path(path)
    if is_container(path):
        faces = [sphere.cube_to_faces(level, convention=convention) for level in chain]
        write_container(path, faces, float32=float32)
        return [path]
    paths = []
    for m, level in enumerate(chain):
        name = Path(str(path).replace(MIP_FIELD, str(m)))
        if FACE_FIELD in str(name):
            paths += write_environment(
                name, level, "cube", convention=convention, description=description
            )
        else:
            cross = sphere.cube_to_view(level, "cross-vertical")
            write_image(name, cross, **_picture_options(name, description))
            paths.append(name)
    return paths


def write_table(path: str | os.PathLike, table: ArrayLike, *, float32: bool = False) -> None:
    """Write a 2-D lookup table of linear data (``(H, W, C)``, C <= 4), such as the split-sum
    DFG table: a .dds/.ktx/.ktx2 2-D texture holds its channels; an image file holds them
    padded to RGB with zeros (16-bit for PNG: the table is data, not a picture)."""
    from bakeshop.io import write_image

    table = np.asarray(table)
    if is_container(path):
        write_container(path, [table], float32=float32)
        return
    if table.shape[-1] == 2:
        table = np.concatenate([table, np.zeros_like(table[..., :1])], axis=-1)
    options = {"bits": 16} if Path(path).suffix.lower() == ".png" else {}
    write_image(path, table, **options)
