"""Khronos texture (KTX 1.1): float cube maps and 2-D textures with their mip chains.

The container OpenGL and Vulkan engines load prefiltered environment maps from; its fields are
the arguments of ``glTexImage2D``. Layout of a file written here (Khronos, "KTX File Format
Specification" version 1.1; little-endian uint32 fields)::

    AB 4B 54 58 20 31 31 BB 0D 0A 1A 0A      identifier "«KTX 11»\\r\\n\\x1A\\n"
    endianness 0x04030201, glType (GL_HALF_FLOAT or GL_FLOAT), glTypeSize (2 or 4),
    glFormat (GL_RED, GL_RG, GL_RGB, GL_RGBA), glInternalFormat (GL_R16F ... GL_RGBA32F),
    glBaseInternalFormat (= glFormat), pixelWidth, pixelHeight, pixelDepth 0,
    numberOfArrayElements 0, numberOfFaces (6 for a cube map, else 1), numberOfMipmapLevels,
    bytesOfKeyValueData
    key/value data          "KTXorientation" = "S=r,T=d" (row 0 of each image is t = 0, shown
                            at the top)
    for each mip level:     imageSize (bytes of one face), then for each face (+X, -X, +Y, -Y,
                            +Z, -Z): its rows in order, each padded to 4 bytes

Rows are stored in the order OpenGL uploads them (row 0 at t = 0), which is bakeshop's row 0, so
cube faces are exactly bakeshop's internal (OpenGL) cube. Sample types ``float16`` (default)
and ``float32``, 1 to 4 channels; half refuses finite values beyond +-65504, naming float32.

Block-compressed textures (:class:`bakeshop.io.compress.BlockTexture`) are written by
:func:`write_ktx_blocks` for engines and loaders that still take KTX 1 (three.js' KTXLoader,
older Android and WebGL pipelines): glType 0, glTypeSize 1, glFormat 0, glInternalFormat the
compressed format (GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT 0x8E8F, GL_COMPRESSED_RGBA_BPTC_UNORM
0x8E8C, GL_COMPRESSED_RG_RGTC2 0x8DBD, ...), glBaseInternalFormat its base format, and per level
``imageSize`` (the bytes of one face) then each face's blocks.

The reader takes what these writers write, in either byte order (a big-endian file's fields
and samples are swapped per glTypeSize: 2 for half, 4 for float, 1 for blocks, which have no
order): float formats as they are, block formats decoded with bakeshop's own decoders
(:func:`read_ktx`) or kept (:func:`read_ktx_blocks`).
"""

from __future__ import annotations

import os
import struct
from collections.abc import Sequence
from typing import TYPE_CHECKING, BinaryIO, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import FormatError, UnsupportedError, validate_choice, with_article
from bakeshop.io import _intent
from bakeshop.io._files import (
    MAX_PIXELS,
    atomic_path,
    check_payload,
    open_input,
    read_payload,
)
from bakeshop.io._levels import (
    DTYPES,
    MAX_LEVELS,
    check_chain_decode,
    check_levels,
    encode,
    mip_size,
    names_its_file,
)

if TYPE_CHECKING:
    from bakeshop.io.compress.texture import BlockTexture

NAME = "KTX"

IDENTIFIER = b"\xabKTX 11\xbb\r\n\x1a\n"
ENDIANNESS = 0x04030201

GL_HALF_FLOAT, GL_FLOAT = 0x140B, 0x1406
#: channels -> glFormat.
GL_FORMATS = {1: 0x1903, 2: 0x8227, 3: 0x1907, 4: 0x1908}  # RED, RG, RGB, RGBA
#: (dtype name, channels) -> glInternalFormat.
GL_INTERNAL_FORMATS = {
    ("float16", 1): 0x822D,  # GL_R16F
    ("float16", 2): 0x822F,  # GL_RG16F
    ("float16", 3): 0x881B,  # GL_RGB16F
    ("float16", 4): 0x881A,  # GL_RGBA16F
    ("float32", 1): 0x822E,  # GL_R32F
    ("float32", 2): 0x8230,  # GL_RG32F
    ("float32", 3): 0x8815,  # GL_RGB32F
    ("float32", 4): 0x8814,  # GL_RGBA32F
}
_GL_TYPES = {"float16": GL_HALF_FLOAT, "float32": GL_FLOAT}
_FIELDS = struct.Struct("<13I")
_HEADER_SIZE = len(IDENTIFIER) + _FIELDS.size
ORIENTATION = b"KTXorientation\x00S=r,T=d\x00"

__all__ = ["write_ktx", "write_ktx_blocks", "read_ktx", "read_ktx_blocks", "sniff"]


def sniff(head: bytes) -> bool:
    """True if ``head`` starts with the KTX 1.1 identifier."""
    return head[: len(IDENTIFIER)] == IDENTIFIER


def _pad4(n: int) -> int:
    return (n + 3) & ~3


def write_ktx(
    path: str | os.PathLike, mips: Sequence[ArrayLike], *, dtype: str = "float16"
) -> None:
    """Write a mip chain (a cube map or a 2-D texture) as a KTX 1.1 file.

    Parameters
    ----------
    path : path-like
        Written atomically (a failed write leaves no partial file).
    mips : sequence of arrays, level 0 first
        Cube map levels ``(6, S, S, C)`` in OpenGL face order, or 2-D levels ``(H, W, C)`` (or
        ``(H, W)``), C in 1..4, each level half the previous (floor, at least 1). NaN is refused.
    dtype : {"float16", "float32"}
        Stored sample type (glType GL_HALF_FLOAT or GL_FLOAT).
    """
    validate_choice(dtype, tuple(DTYPES), "KTX sample type")
    levels, cube = check_levels(mips)
    channels = levels[0].shape[-1]
    height, width = levels[0].shape[-3:-1]
    kv = struct.pack("<I", len(ORIENTATION)) + ORIENTATION
    kv += bytes(_pad4(len(kv)) - len(kv))
    fmt = GL_FORMATS[channels]
    fields = _FIELDS.pack(
        ENDIANNESS, _GL_TYPES[dtype], DTYPES[dtype].itemsize, fmt,
        GL_INTERNAL_FORMATS[dtype, channels], fmt, width, height, 0, 0, 6 if cube else 1,
        len(levels), len(kv),
    )  # fmt: skip
    with (
        _intent.intent(path, "mips", levels, dtype=dtype),
        atomic_path(path) as tmp,
        open(tmp, "wb") as f,
    ):
        f.write(IDENTIFIER + fields + kv)
        for level in levels:
            h, w = level.shape[-3:-1]
            row = w * channels * DTYPES[dtype].itemsize
            padding = _pad4(row) - row
            f.write(struct.pack("<I", _pad4(row) * h))
            for face in level if cube else [level]:
                data = encode(face, DTYPES[dtype]).reshape(h, row // DTYPES[dtype].itemsize)
                if padding:
                    data = np.concatenate(
                        [data.view(np.uint8), np.zeros((h, padding), np.uint8)], axis=1
                    )
                f.write(np.ascontiguousarray(data).tobytes())


def write_ktx_blocks(path: str | os.PathLike, texture: BlockTexture) -> None:
    """Write a block-compressed texture (:class:`bakeshop.io.compress.BlockTexture`) as KTX 1.1.

    Parameters
    ----------
    path : path-like
        Written atomically.
    texture : BlockTexture
        A cube map (faces in OpenGL order) or a 2-D texture.
    """
    fmt = texture.format
    kv = struct.pack("<I", len(ORIENTATION)) + ORIENTATION
    kv += bytes(_pad4(len(kv)) - len(kv))
    fields = _FIELDS.pack(
        ENDIANNESS, 0, 1, 0, fmt.gl, fmt.gl_base, texture.width, texture.height, 0, 0,
        texture.faces, len(texture.levels), len(kv),
    )  # fmt: skip
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(IDENTIFIER + fields + kv)
        for m in range(len(texture.levels)):
            f.write(struct.pack("<I", texture.face_bytes(m)))
            f.write(texture.levels[m])  # block sizes are multiples of 8: no padding


@names_its_file
def read_ktx_blocks(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[BlockTexture, dict]:
    """Read a block-compressed KTX 1 file without decoding it.

    Returns
    -------
    texture : bakeshop.io.compress.BlockTexture
    metadata : dict
        As :func:`read_ktx` returns it.
    """
    texture, metadata = _read(path, max_pixels, decode=False)
    if texture is None:
        raise UnsupportedError("this KTX file is not block-compressed; read it with read_ktx")
    return texture, metadata


@names_its_file
def read_ktx(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[list[np.ndarray], dict]:
    """Read a KTX 1.1 file (a cube map or a 2-D texture with its mips) as float mips.

    Float files are returned as stored; block-compressed files are decoded with bakeshop's own
    decoders (:func:`bakeshop.io.compress.decode_image`).

    Returns
    -------
    mips : list of float32 arrays
        Level 0 first; ``(6, S, S, C)`` per level for a cube map, ``(H, W, C)`` for a 2-D
        texture; row 0 is the first row in the file (t = 0).
    metadata : dict
        ``format`` ("KTX"), ``stored`` ("float16", "float32" or a block format's name),
        ``cube`` (bool), ``gl_internal_format`` (int) and ``key_values`` (dict of str to bytes).

    Raises
    ------
    bakeshop.errors.FormatError
        Not a KTX 1 file, an inconsistent header, or fewer bytes than the header promises.
    bakeshop.errors.UnsupportedError
        Integer and other formats, 3-D textures and texture arrays.
    """
    return _read(path, max_pixels, decode=True)


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
    with open_input(path) as f:
        return _read_levels(f, max_pixels, decode)


def _read_levels(
    f: BinaryIO, max_pixels: int, decode: bool
) -> tuple[list[np.ndarray] | BlockTexture | None, dict]:
    """The header and key/value data of the KTX file ``f``, checked against its size and the
    decode budget; then its levels, each read (and checked) in turn: never the whole file."""
    from bakeshop.io.compress.formats import FORMATS, level_bytes

    file_size = os.fstat(f.fileno()).st_size
    data = f.read(_HEADER_SIZE)
    if len(data) < _HEADER_SIZE or not sniff(data):
        raise FormatError("not a KTX 1 file (bad identifier)")
    order = "<" if struct.unpack_from("<I", data, 12)[0] == ENDIANNESS else ">"
    if struct.unpack_from(order + "I", data, 12)[0] != ENDIANNESS:
        raise FormatError("bad KTX endianness field")
    (_, gl_type, type_size, gl_format, internal, _, width, height, depth, array_elements, faces,
     mip_count, kv_bytes) = struct.unpack_from(order + "13I", data, 12)  # fmt: skip
    match = [k for k, v in GL_INTERNAL_FORMATS.items() if v == internal]
    block = next((f for f in FORMATS.values() if f.gl == internal), None)
    if not match and block is None:
        raise UnsupportedError(
            f"glInternalFormat 0x{internal:04X} is not supported (only float and "
            "BC1/3/4/5/6H/7 formats)"
        )
    if block is not None:
        if gl_type != 0 or gl_format != 0 or type_size != 1:
            raise FormatError("a compressed KTX file must have glType 0, glFormat 0, glTypeSize 1")
    else:
        dtype, channels = match[0]
        if gl_type != _GL_TYPES[dtype] or type_size != DTYPES[dtype].itemsize:
            raise FormatError(f"glType 0x{gl_type:04X} does not match glInternalFormat")
        if gl_format != GL_FORMATS[channels]:
            raise FormatError(f"glFormat 0x{gl_format:04X} does not match glInternalFormat")
    if depth or array_elements:
        raise UnsupportedError("3-D textures and texture arrays are not supported")
    if faces not in (1, 6):
        raise FormatError(f"numberOfFaces is {faces} (expected 1 or 6)")
    cube = faces == 6
    if not (1 <= width and 1 <= height and width * height <= max_pixels):
        raise FormatError(f"KTX size {width}x{height} out of range (limit {max_pixels} pixels)")
    if cube and width != height:
        raise FormatError(f"a cube map's faces must be square; the header says {width}x{height}")
    levels = max(mip_count, 1)  # 0 asks the loader to generate mips: level 0 is stored
    if levels > MAX_LEVELS or max(width, height) >> (levels - 1) == 0:
        raise FormatError(
            f"{levels} mip levels is more than {with_article(width)}x{height} texture has"
        )
    check_payload(kv_bytes, file_size - _HEADER_SIZE, "key/value data")
    key_values = _key_values(read_payload(f, kv_bytes, "key/value data"), order)
    metadata = {
        "format": NAME,
        "stored": block.name if block is not None else dtype,
        "cube": cube,
        "gl_internal_format": internal,
        "key_values": key_values,
    }
    sides = [(mip_size(width, m), mip_size(height, m)) for m in range(levels)]
    if block is not None:
        decoded, sizes = block.channels, [level_bytes(block, w, h) for w, h in sides]
    else:
        texel = channels * DTYPES[dtype].itemsize
        decoded, sizes = channels, [_pad4(w * texel) * h for w, h in sides]
    check_chain_decode(
        width, height, levels, faces, decoded, faces * sum(sizes), file_size, decode=decode
    )
    if block is not None:
        from bakeshop.io.compress.texture import BlockTexture

        raw = []
        for m, size in enumerate(sizes):
            image_size = struct.unpack(order + "I", read_payload(f, 4, "mip level size"))[0]
            if image_size != size:
                raise FormatError(f"mip {m}: imageSize {image_size}, expected {size}")
            raw.append(read_payload(f, faces * size, f"mip {m}"))
        texture = BlockTexture(block, width, height, cube, tuple(raw))
        return (texture.decode() if decode else texture), metadata
    if not decode:
        return None, metadata
    stored = np.dtype(order + DTYPES[dtype].char)
    mips = []
    for m in range(levels):
        h, w = mip_size(height, m), mip_size(width, m)
        row = w * channels * stored.itemsize
        image_size = struct.unpack(order + "I", read_payload(f, 4, "mip level size"))[0]
        if image_size != _pad4(row) * h:
            raise FormatError(f"mip {m}: imageSize {image_size}, expected {_pad4(row) * h}")
        level = np.empty((faces, h, w, channels), np.float32)
        for face in range(faces):
            face_bytes = read_payload(f, image_size, f"mip {m}")
            rows = np.frombuffer(face_bytes, np.uint8).reshape(h, _pad4(row))
            level[face] = rows[:, :row].copy().view(stored).reshape(h, w, channels)
        mips.append(level if cube else level[0])
    return mips, metadata


def _key_values(block: bytes, order: str) -> dict:
    out, i = {}, 0
    while i + 4 <= len(block):
        n = struct.unpack_from(order + "I", block, i)[0]
        entry = block[i + 4 : i + 4 + n]
        if len(entry) != n or b"\x00" not in entry:
            raise FormatError("malformed KTX key/value data")
        key, _, value = entry.partition(b"\x00")
        out[key.decode("utf-8", "replace")] = value
        i += 4 + _pad4(n)
    return out
