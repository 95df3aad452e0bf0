"""DirectDraw Surface (DDS): float cube maps and 2-D textures with their mip chains.

The container Direct3D engines load prefiltered environment maps from. Layout of a file written
here (Microsoft, "DDS file layout", "DDS_HEADER", "DDS_HEADER_DXT10"; all fields little-endian
uint32)::

    "DDS "                  magic
    DDS_HEADER (124 bytes)  size 124, flags CAPS|HEIGHT|WIDTH|PITCH|PIXELFORMAT[|MIPMAPCOUNT],
                            height, width, pitch (bytes per row of level 0), depth 0, mip count,
                            11 reserved, DDS_PIXELFORMAT (size 32, flags FOURCC, "DX10"),
                            caps TEXTURE[|COMPLEX|MIPMAP], caps2 CUBEMAP|all six faces (cubes)
    DDS_HEADER_DXT10        DXGI format, dimension TEXTURE2D (3), misc flags TEXTURECUBE (4)
                            for cubes, array size 1, misc flags 2 (alpha mode) 0
    pixels                  for each array layer (one unless ``array=True``), for each face
                            (+X, -X, +Y, -Y, +Z, -Z; one for a 2-D texture): for each mip
                            level: its rows top to bottom, texels RGBA interleaved

Sample types: ``float16`` (the default: half the memory, what engines sample environment maps
in) and ``float32``; 1, 2 and 4 channels are stored as R, RG and RGBA (DXGI_FORMAT_R16_FLOAT,
R16G16_FLOAT, R16G16B16A16_FLOAT or the 32-bit ones). Three channels are padded to RGBA with
alpha 1: DXGI has no 16-bit RGB format, and filtering 32-bit RGB is optional in Direct3D. Half
refuses finite values beyond +-65504, naming float32 (a sun is brighter than that in some
probes; :func:`bakeshop.io.write_container` picks float32 for it). ``unorm8`` stores 8-bit
unsigned normalised samples (DXGI_FORMAT_R8_UNORM, R8G8_UNORM, R8G8B8A8_UNORM; a stored c
reads as c / 255), for data such as two-channel normal maps. ``array=True`` writes a 2-D
texture array: the DX10 header's arraySize is the number of layers.

Cube faces are stored in OpenGL's order and orientation (bakeshop's internal cube), which is
also Direct3D's face order and addressing rule; a Direct3D engine whose world is left-handed
(z forward) wants the ``directx`` face set of :func:`bakeshop.sphere.cube.cube_to_faces` instead,
which the caller passes in.

Block-compressed textures (:class:`bakeshop.io.compress.BlockTexture`: BC1, BC3, BC4, BC5,
BC6H, BC7) are written by :func:`write_dds_blocks` with the same headers, except that the header
gives the linear size (bytes of one face of level 0, flag LINEARSIZE) instead of a pitch, the
DX10 header names the exact DXGI format (BC6H_UF16 95, BC6H_SF16 96, BC7_UNORM 98,
BC7_UNORM_SRGB 99, ...), and each level of each face is its 4x4 blocks row by row (a 2x2 or 1x1
level is one block).

The reader takes what these writers write plus the legacy floating-point FourCC codes (D3DFMT
111 to 116) and block FourCCs (DXT1, DXT5, ATI1/BC4U, ATI2/BC5U) that older tools write without
the DX10 header. :func:`read_dds` decodes block-compressed files to float mips with bakeshop's
own decoders; :func:`read_dds_blocks` returns their blocks as they are.
"""

from __future__ import annotations

import os
import struct
from collections.abc import Sequence
from typing import TYPE_CHECKING, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import FormatError, UnsupportedError, validate_choice, with_article
from bakeshop.io import _intent
from bakeshop.io._files import MAX_PIXELS, atomic_path, check_payload, open_input
from bakeshop.io._levels import (
    DTYPES,
    MAX_LEVELS,
    UNORM_DTYPES,
    check_chain_decode,
    check_levels,
    encode,
    mip_size,
    names_its_file,
)
from bakeshop.io._quantize import unsigned_to_float

if TYPE_CHECKING:
    from bakeshop.io.compress.texture import BlockTexture

NAME = "DDS"

MAGIC = b"DDS "

# DDS_HEADER flags, caps and pixel-format flags (Microsoft's names).
DDSD_CAPS, DDSD_HEIGHT, DDSD_WIDTH, DDSD_PITCH = 0x1, 0x2, 0x4, 0x8
DDSD_PIXELFORMAT, DDSD_MIPMAPCOUNT, DDSD_LINEARSIZE, DDSD_DEPTH = 0x1000, 0x20000, 0x80000, 0x800000
DDPF_FOURCC = 0x4
DDSCAPS_COMPLEX, DDSCAPS_TEXTURE, DDSCAPS_MIPMAP = 0x8, 0x1000, 0x400000
DDSCAPS2_CUBEMAP, DDSCAPS2_ALLFACES, DDSCAPS2_VOLUME = 0x200, 0xFC00, 0x200000
D3D10_RESOURCE_DIMENSION_TEXTURE2D = 3
DDS_RESOURCE_MISC_TEXTURECUBE = 0x4

#: DXGI_FORMAT -> (sample dtype name, channels), the uncompressed float formats.
DXGI_FORMATS = {
    2: ("float32", 4),  # R32G32B32A32_FLOAT
    6: ("float32", 3),  # R32G32B32_FLOAT (read only)
    10: ("float16", 4),  # R16G16B16A16_FLOAT
    16: ("float32", 2),  # R32G32_FLOAT
    34: ("float16", 2),  # R16G16_FLOAT
    41: ("float32", 1),  # R32_FLOAT
    54: ("float16", 1),  # R16_FLOAT
    28: ("unorm8", 4),  # R8G8B8A8_UNORM
    49: ("unorm8", 2),  # R8G8_UNORM
    61: ("unorm8", 1),  # R8_UNORM
}
#: legacy D3DFORMAT FourCC codes of float formats -> (dtype name, channels).
D3D_FORMATS = {
    111: ("float16", 1),
    112: ("float16", 2),
    113: ("float16", 4),
    114: ("float32", 1),
    115: ("float32", 2),
    116: ("float32", 4),
}

#: legacy FourCC codes of block formats -> bakeshop block format name (read only).
FOURCC_BLOCKS = {
    b"DXT1": "bc1",
    b"DXT5": "bc3",
    b"ATI1": "bc4",
    b"BC4U": "bc4",
    b"ATI2": "bc5",
    b"BC5U": "bc5",
}

#: Every sample type this module stores.
SAMPLE_TYPES = {**DTYPES, **UNORM_DTYPES}

_HEADER = struct.Struct("<4s7I44s2I4s5I5I")  # magic, DDS_HEADER with its DDS_PIXELFORMAT
_DX10 = struct.Struct("<5I")

__all__ = ["write_dds", "write_dds_blocks", "read_dds", "read_dds_blocks", "sniff"]


def sniff(head: bytes) -> bool:
    """True if ``head`` starts with the DDS magic and a 124-byte header size."""
    return head[:4] == MAGIC and head[4:8] == struct.pack("<I", 124)


def write_dds(
    path: str | os.PathLike,
    mips: Sequence[ArrayLike],
    *,
    dtype: str = "float16",
    array: bool = False,
) -> None:
    """Write a mip chain (a cube map, a 2-D texture or a 2-D texture array) as a DDS file with
    the DX10 header.

    Parameters
    ----------
    path : path-like
        Written atomically (a failed write leaves no partial file).
    mips : sequence of arrays, level 0 first
        Cube map levels ``(6, S, S, C)`` in OpenGL face order, or 2-D levels ``(H, W, C)`` (or
        ``(H, W)``), C in 1..4, each level half the previous (floor, at least 1); with
        ``array=True``, ``(L, H, W, C)`` levels of L layers. NaN is refused.
    dtype : {"float16", "float32", "unorm8"}
        Stored sample type (DXGI_FORMAT_R16G16B16A16_FLOAT and friends, the 32-bit ones, or
        R8G8_UNORM and friends: floats in [0, 1] rounded to c / 255, or uint8 as is).
    array : bool
        Write a texture array (arraySize = L).
    """
    validate_choice(dtype, tuple(SAMPLE_TYPES), "DDS sample type")
    levels, cube = check_levels(mips, array=array)
    channels = levels[0].shape[-1]
    stored = 4 if channels == 3 else channels
    fmt = next(k for k, v in DXGI_FORMATS.items() if v == (dtype, stored))
    height, width = levels[0].shape[-3:-1]
    layers = levels[0].shape[0] if array else 1
    itemsize = SAMPLE_TYPES[dtype].itemsize
    flags = DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PITCH | DDSD_PIXELFORMAT
    caps = DDSCAPS_TEXTURE
    if len(levels) > 1:
        flags |= DDSD_MIPMAPCOUNT
        caps |= DDSCAPS_COMPLEX | DDSCAPS_MIPMAP
    caps2 = 0
    if cube:
        caps |= DDSCAPS_COMPLEX
        caps2 = DDSCAPS2_CUBEMAP | DDSCAPS2_ALLFACES
    header = _HEADER.pack(
        MAGIC, 124, flags, height, width, width * stored * itemsize, 0, len(levels), bytes(44),
        32, DDPF_FOURCC, b"DX10", 0, 0, 0, 0, 0, caps, caps2, 0, 0, 0,
    )  # fmt: skip
    dx10 = _DX10.pack(
        fmt,
        D3D10_RESOURCE_DIMENSION_TEXTURE2D,
        DDS_RESOURCE_MISC_TEXTURECUBE if cube else 0,
        layers,
        0,
    )
    with (
        _intent.intent(path, "mips", levels, dtype=dtype, array=array),
        atomic_path(path) as tmp,
        open(tmp, "wb") as f,
    ):
        f.write(header + dx10)
        for layer in range(layers):
            for face in range(6 if cube else 1):
                for level in levels:
                    texels = level[face] if cube else level[layer] if array else level
                    if channels == 3:
                        one = 255 if texels.dtype == np.uint8 else 1
                        texels = np.concatenate(
                            [texels, np.full_like(texels[..., :1], one)], axis=-1
                        )
                    f.write(np.ascontiguousarray(encode(texels, SAMPLE_TYPES[dtype])).tobytes())


def write_dds_blocks(path: str | os.PathLike, texture: BlockTexture) -> None:
    """Write a block-compressed texture (:class:`bakeshop.io.compress.BlockTexture`) as a DDS file
    with the DX10 header: faces in file order (each face's whole mip chain, then the next
    face), the exact DXGI format, the cube flag and the mip count.

    Parameters
    ----------
    path : path-like
        Written atomically.
    texture : BlockTexture
        A cube map (faces in OpenGL order, which is also Direct3D's) or a 2-D texture.
    """
    levels = len(texture.levels)
    flags = DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_LINEARSIZE | DDSD_PIXELFORMAT
    caps = DDSCAPS_TEXTURE
    if levels > 1:
        flags |= DDSD_MIPMAPCOUNT
        caps |= DDSCAPS_COMPLEX | DDSCAPS_MIPMAP
    caps2 = 0
    if texture.cube:
        caps |= DDSCAPS_COMPLEX
        caps2 = DDSCAPS2_CUBEMAP | DDSCAPS2_ALLFACES
    header = _HEADER.pack(
        MAGIC, 124, flags, texture.height, texture.width, texture.face_bytes(0), 0, levels,
        bytes(44), 32, DDPF_FOURCC, b"DX10", 0, 0, 0, 0, 0, caps, caps2, 0, 0, 0,
    )  # fmt: skip
    misc = DDS_RESOURCE_MISC_TEXTURECUBE if texture.cube else 0
    dx10 = _DX10.pack(texture.format.dxgi, D3D10_RESOURCE_DIMENSION_TEXTURE2D, misc, 1, 0)
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(header + dx10)
        for face in range(texture.faces):
            for m in range(levels):
                f.write(texture.face(m, face))


@names_its_file
def read_dds_blocks(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[BlockTexture, dict]:
    """Read a block-compressed DDS file without decoding it.

    Returns
    -------
    texture : bakeshop.io.compress.BlockTexture
    metadata : dict
        As :func:`read_dds` returns it.

    Raises
    ------
    bakeshop.errors.UnsupportedError
        The file is not block-compressed (read it with :func:`read_dds`).
    """
    texture, metadata = _read(path, max_pixels, decode=False)
    if texture is None:
        raise UnsupportedError("this DDS file is not block-compressed; read it with read_dds")
    return texture, metadata


@names_its_file
def read_dds(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[list[np.ndarray], dict]:
    """Read a DDS file (a cube map, a 2-D texture or a 2-D texture array with its mips) as
    float mips.

    Float files are returned as stored; block-compressed files are decoded with bakeshop's own
    decoders (:func:`bakeshop.io.compress.decode_image`): BC6H to its half-float values, the
    8-bit formats to [0, 1] (sRGB formats to linear values).

    Parameters
    ----------
    path : path-like
    max_pixels : int
        Largest accepted width * height * layers of level 0 (per face).

    Returns
    -------
    mips : list of float32 arrays
        Level 0 first; ``(6, S, S, C)`` per level for a cube map (faces in file order, which is
        OpenGL's), ``(H, W, C)`` for a 2-D texture, ``(L, H, W, C)`` for a texture array (a DX10
        arraySize above 1); C as stored (block formats: BC4 1, BC5 2, BC6H 3, others 4).
        ``unorm8`` samples read as c / 255.
    metadata : dict
        ``format`` ("DDS"), ``stored`` ("float16", "float32", "unorm8" or the block format's
        name such as "bc6h"), ``cube`` (bool), ``layers`` (the arraySize; 1 for a single
        texture), ``dxgi_format`` (int; the legacy FourCC code's DXGI equivalent) and
        ``header`` ("DX10" or "legacy").

    Raises
    ------
    bakeshop.errors.FormatError
        Not a DDS file, an inconsistent header, or fewer bytes than the header promises.
    bakeshop.errors.UnsupportedError
        Other integer formats, volume textures, cube map arrays and block-compressed arrays.
    """
    mips, metadata = _read(path, max_pixels, decode=True)
    return mips, metadata


@overload
def _read(
    path: str | os.PathLike, max_pixels: int, decode: Literal[True]
) -> tuple[list[np.ndarray], dict]: ...


@overload
def _read(
    path: str | os.PathLike, max_pixels: int, decode: Literal[False]
) -> tuple[BlockTexture | None, dict]: ...


def _read(
    path: str | os.PathLike, max_pixels: int, decode: bool
) -> tuple[list[np.ndarray] | BlockTexture | None, dict]:
    """Parse a DDS file: (float mips or BlockTexture or None, metadata)."""
    from bakeshop.io.compress.formats import FORMATS

    with open_input(path) as f:
        head = f.read(_HEADER.size + _DX10.size)
        size = os.fstat(f.fileno()).st_size
    if len(head) < _HEADER.size or not sniff(head):
        raise FormatError("not a DDS file (bad magic or header size)")
    fields = _HEADER.unpack_from(head)
    flags, height, width, _pitch, depth, mip_count = fields[2:8]
    pf_size, pf_flags, fourcc = fields[9:12]
    caps, caps2 = fields[17:19]
    if pf_size != 32:
        raise FormatError(f"bad DDS pixel format size {pf_size} (expected 32)")
    offset = _HEADER.size
    layers = 1
    if not pf_flags & DDPF_FOURCC:
        raise UnsupportedError(
            "only floating-point and block-compressed DDS formats are supported (no FourCC code)"
        )
    block = None
    by_dxgi = {f.dxgi: f for f in FORMATS.values()}
    if fourcc == b"DX10":
        if len(head) < offset + _DX10.size:
            raise FormatError("truncated DDS file: the DX10 header is missing")
        fmt, dimension, misc, array_size, _ = _DX10.unpack_from(head, offset)
        offset += _DX10.size
        if fmt in by_dxgi:
            block = by_dxgi[fmt]
        elif fmt not in DXGI_FORMATS:
            raise UnsupportedError(
                f"DXGI format {fmt} is not supported (only float, 8-bit unorm and BC1/3/4/5/6H/7)"
            )
        if dimension != D3D10_RESOURCE_DIMENSION_TEXTURE2D:
            raise UnsupportedError(f"DDS resource dimension {dimension}: only 2-D textures")
        cube = bool(misc & DDS_RESOURCE_MISC_TEXTURECUBE)
        if array_size < 1:
            raise FormatError("DDS arraySize is 0")
        if array_size != 1 and (cube or block is not None):
            what = "cube map" if cube else "block-compressed"
            raise UnsupportedError(f"{what} arrays are not supported (array size {array_size})")
        layers = array_size
        kind = "DX10"
    else:
        code = struct.unpack("<I", fourcc)[0]
        if fourcc in FOURCC_BLOCKS:
            block = FORMATS[FOURCC_BLOCKS[fourcc]]
            fmt = block.dxgi
        elif code in D3D_FORMATS:
            fmt = next(k for k, v in DXGI_FORMATS.items() if v == D3D_FORMATS[code])
        else:
            raise UnsupportedError(
                f"DDS format {fourcc!r} is not supported (only float and block-compressed formats)"
            )
        cube = bool(caps2 & DDSCAPS2_CUBEMAP)
        if cube and caps2 & DDSCAPS2_ALLFACES != DDSCAPS2_ALLFACES:
            raise UnsupportedError("cube maps with missing faces are not supported")
        kind = "legacy"
    if caps2 & DDSCAPS2_VOLUME or (flags & DDSD_DEPTH and depth > 1):
        raise UnsupportedError("volume textures are not supported")
    if not (1 <= width and 1 <= height and width * height * layers <= max_pixels):
        raise FormatError(
            f"DDS size {width}x{height}x{layers} out of range (limit {max_pixels} pixels)"
        )
    if cube and width != height:
        raise FormatError(f"a cube map's faces must be square; the header says {width}x{height}")
    levels = mip_count if flags & DDSD_MIPMAPCOUNT or mip_count > 1 else 1
    levels = max(levels, 1)
    if levels > MAX_LEVELS or max(width, height) >> (levels - 1) == 0:
        raise FormatError(
            f"{levels} mip levels is more than {with_article(width)}x{height} texture has"
        )
    faces = 6 if cube else 1
    metadata = {"format": NAME, "cube": cube, "layers": layers, "dxgi_format": fmt, "header": kind}
    if block is not None:
        from bakeshop.io.compress.formats import level_bytes
        from bakeshop.io.compress.texture import BlockTexture

        sizes = [level_bytes(block, mip_size(width, m), mip_size(height, m)) for m in range(levels)]
        check_payload(faces * sum(sizes), size - offset)
        check_chain_decode(
            width, height, levels, faces, block.channels, faces * sum(sizes), size, decode=decode
        )
        with open(path, "rb") as f:
            f.seek(offset)
            blob = f.read(faces * sum(sizes))
        chains = [blob[i * sum(sizes) : (i + 1) * sum(sizes)] for i in range(faces)]
        starts = np.concatenate([[0], np.cumsum(sizes)])
        data = tuple(
            b"".join(chain[starts[m] : starts[m + 1]] for chain in chains) for m in range(levels)
        )
        texture = BlockTexture(block, width, height, cube, data)
        metadata["stored"] = block.name
        return (texture.decode() if decode else texture), metadata
    if not decode:
        return None, metadata
    dtype, channels = DXGI_FORMATS[fmt]
    itemsize = SAMPLE_TYPES[dtype].itemsize
    shapes = [(mip_size(height, m), mip_size(width, m), channels) for m in range(levels)]
    face_bytes = sum(h * w * c for h, w, c in shapes) * itemsize
    check_payload(layers * faces * face_bytes, size - offset)
    check_chain_decode(
        width, height, levels, layers * faces, channels, layers * faces * face_bytes, size,
        decode=True,
    )  # fmt: skip
    raw = np.fromfile(
        path,
        dtype=SAMPLE_TYPES[dtype],
        offset=offset,
        count=layers * faces * face_bytes // itemsize,
    )
    if dtype in UNORM_DTYPES:
        raw = unsigned_to_float(raw, 8)
    lead = (faces,) if cube else (layers,) if layers > 1 else ()
    mips = [np.empty(lead + s, np.float32) for s in shapes]
    start = 0
    for index in range(layers * faces):
        for m, (h, w, c) in enumerate(shapes):
            texels = raw[start : start + h * w * c].reshape(h, w, c)
            if lead:
                mips[m][index] = texels
            else:
                mips[m][...] = texels
            start += h * w * c
    metadata["stored"] = dtype
    return mips, metadata
