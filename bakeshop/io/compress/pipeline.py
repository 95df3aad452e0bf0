"""From float levels to a compressed file with its measured quality: what ``bakeshop compress``,
``bake-probe --compress`` and ``normals combine --compress`` share.

:func:`box_mips` makes a mip chain (the mean of each 2x2 texel block, as ``glGenerateMipmap``
does; normal maps are renormalised per level), :func:`compress_levels` encodes the levels in a
block format or an RGBM/RGBD packing, decodes them again with bakeshop's own decoders and
measures what was lost, and :func:`write_compressed` writes the file (DDS, KTX2, KTX, or PNG
for the packings) and its JSON sidecar.

Quality kinds: ``"hdr"`` (BC6H and the packings: multi-exposure PSNR and log2 RMSE against the
unclamped input, so clamping counts as loss), ``"ldr"`` (PSNR of the stored values; sRGB
formats are compared in their sRGB encoding, as the 8 bits are spent there) and ``"normal"``
(angular error of the rebuilt unit normals).
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, BakeshopError, validate_choice, with_article
from bakeshop.io.compress import packing, quality
from bakeshop.io.compress.encode import linear_to_srgb
from bakeshop.io.compress.formats import FORMATS, block_format
from bakeshop.io.compress.texture import BlockTexture, Overflow, encode_texture
from bakeshop.resources import Cost, require

__all__ = [
    "PACKINGS",
    "OUTPUT_FORMATS",
    "Compressed",
    "box_mips",
    "compress_levels",
    "compress_levels_cost",
    "write_compressed",
    "sidecar_path",
]

#: RGBM/RGBD packings: name -> (packing, block format or None for 8-bit PNG).
PACKINGS = {
    "rgbm": ("rgbm", None),
    "rgbd": ("rgbd", None),
    "rgbm-bc7": ("rgbm", "bc7"),
    "rgbd-bc7": ("rgbd", "bc7"),
}
#: everything ``--format`` takes.
OUTPUT_FORMATS = tuple(FORMATS) + tuple(PACKINGS)
#: quality kinds.
KINDS = ("hdr", "ldr", "normal")


@dataclass
class Compressed:
    """What :func:`compress_levels` returns."""

    #: the output format name (a block format or a packing).
    format: str
    #: the encoded texture (block formats and packings in BC7), else None.
    texture: BlockTexture | None
    #: 8-bit packed levels for PNG packings (float values on the 8-bit grid), else None.
    packed: list | None
    #: the levels as a renderer reads them back (decoded, unpacked), level 0 first.
    decoded: list
    #: cube map (6 faces per level) or 2-D texture.
    cube: bool
    #: quality, clamping and format facts for messages and the sidecar.
    report: dict = field(default_factory=dict)


def _box(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    from bakeshop.image import resize_area

    return resize_area(image, size)


def box_mips(
    level0: ArrayLike, *, cube: bool, levels: int | None = None, normals: bool = False
) -> list[np.ndarray]:
    """A mip chain from level 0 by 2x2 box averaging (exact area averaging at odd sizes).

    Parameters
    ----------
    level0 : (H, W, C) or (6, S, S, C) array
    cube : bool
        Level 0 is a cube map (each face is reduced on its own).
    levels : int, optional
        Number of levels (default: down to 1x1).
    normals : bool
        Level 0 holds unit normals (signed components): each level is renormalised.

    Returns
    -------
    list of float32 arrays, level 0 first.
    """
    a = np.asarray(level0, np.float32)
    h, w = a.shape[-3:-1]
    full = max(h, w).bit_length()
    levels = full if levels is None else levels
    if not 1 <= levels <= full:
        raise ArgumentError(
            f"{with_article(w)}x{h} texture has 1 to {full} mip levels, not {levels}"
        )
    chain = [a]
    for m in range(1, levels):
        size = (max(1, w >> m), max(1, h >> m))
        previous = chain[-1]
        if cube:
            nxt = np.stack([_box(face, size) for face in previous])
        else:
            nxt = _box(previous, size)
        if normals:
            norm = np.linalg.norm(nxt[..., :3], axis=-1, keepdims=True)
            nxt[..., :3] = np.where(norm > 0, nxt[..., :3] / np.maximum(norm, 1e-12), 0)
            nxt[..., 2] = np.where(norm[..., 0] > 0, nxt[..., 2], 1)
        chain.append(nxt.astype(np.float32, copy=False))
    return chain


def _kind(name: str, normals: bool) -> str:
    if normals:
        return "normal"
    if name in PACKINGS or FORMATS[name].hdr:
        return "hdr"
    return "ldr"


def _measure(kind: str, reference: list, decoded: list, srgb: bool, convention: str) -> dict:
    per_level = []
    for m, (ref, dec) in enumerate(zip(reference, decoded, strict=True)):
        ref = np.asarray(ref, np.float32).reshape(-1, ref.shape[-1])
        dec = np.asarray(dec, np.float32).reshape(-1, dec.shape[-1])
        entry: dict[str, float] = {"level": m}
        if kind == "hdr":
            entry["mpsnr_db"] = quality.mpsnr(ref[:, :3], dec[:, :3])
            entry["log2_rmse"] = quality.log2_rmse(ref[:, :3], dec[:, :3])
        elif kind == "ldr":
            c = min(ref.shape[1], dec.shape[1])
            a, b = ref[:, :c], dec[:, :c]
            if srgb:
                a, b = a.copy(), b.copy()
                a[:, :3], b[:, :3] = linear_to_srgb(a[:, :3]), linear_to_srgb(b[:, :3])
            entry["psnr_db"] = quality.psnr(np.clip(a, 0, 1), b)
        else:
            xy = dec[:, :2] * 2 - 1
            if convention == "dx":
                xy[:, 1] *= -1
            entry.update(
                {
                    f"angle_{k}_deg": v
                    for k, v in quality.angular_error(ref[:, :3], quality.rebuild_z(xy)).items()
                }  # fmt: skip
            )
        per_level.append(entry)
    out = {"kind": kind, **{k: v for k, v in per_level[0].items() if k != "level"}}
    out["levels"] = per_level
    return out


#: Peak bytes per texel (of all levels) that :func:`compress_levels` holds beyond its input:
#: the encoder's surfaces and blocks, the decoded copy and the quality measure's temporaries
#: (measured on 6-face chains from 256 to 1024: 168 for bc6h, whose multi-exposure PSNR is the
#: heaviest, 124 for bc5, 84 for bc7).
TEXEL_BYTES = 192


def compress_levels_cost(shapes: Sequence[tuple[int, ...]], name: str) -> Cost:
    """What :func:`compress_levels` of levels of ``shapes`` (each with its channel axis) holds
    at its peak (:data:`TEXEL_BYTES` per texel); ``work`` is in texels."""
    texels = sum(math.prod(shape[:-1]) for shape in shapes)
    what = f"compressing {len(shapes)} levels ({texels:,} texels) to {name}"
    return Cost(TEXEL_BYTES * texels, texels, what)


def compress_levels(
    mips: Sequence[ArrayLike],
    name: str,
    *,
    cube: bool,
    quality_profile: str = "fast",
    overflow: Overflow = "refuse",
    normals: bool = False,
    normal_convention: str = "gl",
    rgbm_range: float = 8.0,
    workers: int | None = None,
) -> Compressed:
    """Compress float levels and measure the result.

    Parameters
    ----------
    mips : list of arrays, level 0 first
        Cube levels ``(6, S, S, C)`` or 2-D levels ``(H, W, C)``. Colour and HDR data as linear
        values; normal maps (``normals=True``) as unit vectors in the OpenGL tangent frame.
    name : str
        A block format (:data:`bakeshop.io.compress.FORMATS`) or a packing (:data:`PACKINGS`).
    cube : bool
    quality_profile : str
        Encoder profile (:data:`bakeshop.io.compress.QUALITIES`).
    overflow : {"refuse", "clamp"}
        Values BC6H cannot store (:func:`bakeshop.io.compress.check_range`); RGBM and RGBD clip
        above their range and report it.
    normals : bool
        The levels are normal maps: stored packed ``(n + 1) / 2`` (x and y only for BC5), in the
        green convention ``normal_convention`` ("gl" or "dx").
    rgbm_range : float
        RGBM's range R.
    workers : int, optional
        Encoder threads.

    Returns
    -------
    Compressed
    """
    validate_choice(name, OUTPUT_FORMATS, "output format")
    validate_choice(normal_convention, ("gl", "dx"), "normal-map convention")
    require(compress_levels_cost([np.shape(m) for m in mips], name))
    levels = [np.asarray(m, np.float32) for m in mips]
    kind = _kind(name, normals)
    report: dict = {"format": name}
    if name in PACKINGS:
        which, block = PACKINGS[name]
        if normals:
            raise ArgumentError("RGBM and RGBD pack HDR colour, not normal maps")
        limit = rgbm_range if which == "rgbm" else packing.RGBD_MAX
        clipped = sum(int(np.count_nonzero(level[..., :3] > limit)) for level in levels)
        if which == "rgbm":
            packed = [packing.encode_rgbm(level, range=rgbm_range) for level in levels]
        else:
            packed = [packing.encode_rgbd(level) for level in levels]
        report["packing"] = {
            "name": which,
            "range": rgbm_range if which == "rgbm" else packing.RGBD_MAX,
            "clipped_values": clipped,
            "decode": packing.DECODE_FORMULAS[which].format(range=f"{rgbm_range:g}"),
        }
        texture = None
        if block is None:
            stored = [np.rint(np.clip(p, 0, 1) * 255) / 255 for p in packed]
            packed_out = [s.astype(np.float32) for s in stored]
        else:
            texture = encode_texture(packed, block, quality=quality_profile, workers=workers)
            stored = texture.decode()
            packed_out = None
        unpack = packing.decode_rgbm if which == "rgbm" else packing.decode_rgbd
        kwargs = {"range": rgbm_range} if which == "rgbm" else {}
        decoded = [unpack(s, **kwargs) for s in stored]
        report["quality"] = _measure(kind, levels, decoded, False, normal_convention)
        report["quality_profile"] = quality_profile if texture is not None else None
        return Compressed(name, texture, packed_out, decoded, cube, report)
    fmt = block_format(name)
    source = levels
    if normals:
        if fmt.hdr:
            raise ArgumentError(f"{name} stores HDR colour; normal maps go to bc5, bc7 or bc1")
        source = []
        for level in levels:
            n = level[..., :3].astype(np.float32).copy()
            if normal_convention == "dx":
                n[..., 1] *= -1
            source.append(np.clip((n + 1) / 2, 0, 1))
    texture = encode_texture(
        source, fmt, quality=quality_profile, overflow=overflow, workers=workers
    )
    decoded = texture.decode()
    notes = texture.notes
    if notes.get("clamped_values") is not None:
        report["overflow"] = {k: notes[k] for k in ("overflow", "clamped_values", "peak",
                                                    "clamped_energy")}  # fmt: skip
    report["quality_profile"] = quality_profile
    report["quality"] = _measure(kind, levels, decoded, fmt.srgb, normal_convention)
    if normals:
        report["normal_convention"] = normal_convention
    return Compressed(name, texture, None, decoded, cube, report)


def sidecar_path(target: str | os.PathLike) -> Path:
    """The JSON sidecar of an output: ``OUT.json`` beside it (``specular.dds.json``); for a PNG
    pattern with ``{mip}``/``{face}``, the pattern without them (``env_{mip}.png`` ->
    ``env.png.json``)."""
    target = Path(target)
    name = re.sub(r"[_\-.]?\{(mip|face)\}", "", target.name)
    return target.with_name(name + ".json")


def _finite(value: object) -> object:
    if isinstance(value, float) and not math.isfinite(value):
        return None  # JSON has no infinity: a lossless level has no finite PSNR
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


def write_json(path: str | os.PathLike, data: dict) -> None:
    """Write ``data`` as indented JSON, atomically (infinite numbers become null)."""
    from bakeshop.io._files import atomic_path

    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(_finite(data), indent=2) + "\n")


def write_compressed(
    target: str | os.PathLike,
    result: Compressed,
    *,
    supercompression: str = "none",
    extra: dict | None = None,
) -> list[Path]:
    """Write a :class:`Compressed` result and its JSON sidecar; return the paths written.

    Block-compressed textures go to ``target`` by its extension (.dds, .ktx2, .ktx); PNG
    packings to ``target`` with ``{face}`` (cube maps) and ``{mip}`` (more than one level)
    replaced by the face name and level number. The sidecar (:func:`sidecar_path`) holds
    ``result.report``, the file facts and ``extra``.
    """
    from bakeshop.io import write_image

    target = Path(target)
    suffix = target.suffix.lower()
    paths = []
    report = dict(result.report)
    if result.texture is not None:
        from bakeshop.io import _intent
        from bakeshop.io.dds import write_dds_blocks
        from bakeshop.io.ktx import write_ktx_blocks
        from bakeshop.io.ktx2 import write_ktx2_blocks

        with _intent.intent(target, "blocks", result.texture):
            if suffix == ".dds":
                write_dds_blocks(target, result.texture)
            elif suffix == ".ktx2":
                write_ktx2_blocks(target, result.texture, supercompression=supercompression)
                report["supercompression"] = supercompression
            elif suffix == ".ktx":
                write_ktx_blocks(target, result.texture)
            else:
                raise ArgumentError(
                    "a block-compressed texture is written to .dds, .ktx2 or .ktx", target
                )
        fmt = result.texture.format
        report.update(
            {
                "container": suffix[1:],
                "block_format": fmt.name,
                "dxgi_format": fmt.dxgi,
                "vk_format": fmt.vk,
                "gl_internal_format": fmt.gl,
                "width": result.texture.width,
                "height": result.texture.height,
                "cube": result.cube,
                "levels": len(result.texture.levels),
                "bytes": sum(len(level) for level in result.texture.levels),
            }
        )
        paths.append(target)
    else:
        from bakeshop.sphere import FACE_NAMES

        assert result.packed is not None  # no texture: a PNG packing's levels
        if suffix != ".png":
            raise ArgumentError("RGBM and RGBD without BC7 are written as 8-bit PNG", target)
        if result.cube and "{face}" not in target.name:
            raise ArgumentError("a cube map in PNG files needs {face} in the name", target)
        if len(result.packed) > 1 and "{mip}" not in target.name:
            raise ArgumentError("a mip chain in PNG files needs {mip} in the name", target)
        for m, level in enumerate(result.packed):
            faces = level if result.cube else [level]
            for f, face in enumerate(faces):
                name = str(target).replace("{mip}", str(m))
                if result.cube:
                    name = name.replace("{face}", FACE_NAMES[f])
                write_image(name, face)
                paths.append(Path(name))
        report.update({"container": "png", "cube": result.cube, "levels": len(result.packed)})
    try:
        import ispc_texcomp

        # the package's stub (__init__.pyi) omits the __version__ its module defines
        encoder = f"ispc-texcomp {ispc_texcomp.__version__}"  # type: ignore[attr-defined]
    except ImportError:  # PNG packings need no encoder
        encoder = None
    if result.format == "bc6h-signed":
        encoder = "bakeshop bc6h-signed"
    from bakeshop import __version__

    report = {"file": paths[0].name, "bakeshop": __version__, "encoder": encoder, **report}
    report.update(extra or {})
    sidecar = sidecar_path(target)
    try:
        write_json(sidecar, report)
    except OSError as e:
        raise BakeshopError(e.strerror or str(e), sidecar) from None
    return paths + [sidecar]
