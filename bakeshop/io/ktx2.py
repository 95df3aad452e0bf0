"""Khronos texture 2 (KTX2): float cube maps and 2-D textures with their mip chains.

The container of Vulkan-era engines (and glTF's KHR_texture_basisu); formats are Vulkan's.
Layout of a file written here (Khronos, "KTX File Format Specification" version 2.0;
little-endian)::

    AB 4B 54 58 20 32 30 BB 0D 0A 1A 0A      identifier "«KTX 20»\\r\\n\\x1A\\n"
    uint32 vkFormat (VK_FORMAT_R16G16B16A16_SFLOAT = 97, ...), typeSize (2 or 4),
           pixelWidth, pixelHeight, pixelDepth 0, layerCount 0, faceCount (6 or 1),
           levelCount, supercompressionScheme 0
    uint32 dfdByteOffset, dfdByteLength, kvdByteOffset, kvdByteLength;
    uint64 sgdByteOffset 0, sgdByteLength 0
    level index             per level (base level first): uint64 byteOffset, byteLength,
                            uncompressedByteLength
    data format descriptor  one basic block: RGBSDA colour model, BT.709 primaries, linear
                            transfer, one signed-float sample per channel
    key/value data          "KTXorientation" = "rd", "KTXwriter" = "bakeshop <version>"
    level data              smallest level first, each aligned to lcm(texel size, 4): the
                            faces (+X, -X, +Y, -Y, +Z, -Z) in order, rows unpadded, row 0 first

Row 0 is bakeshop's row 0 (t = 0, shown at the top: "rd"), so cube faces are exactly bakeshop's
internal (OpenGL) cube, which is also what Vulkan samples. Sample types ``float16`` (default)
and ``float32``, 1 to 4 channels; half refuses finite values beyond +-65504, naming float32;
``unorm8`` (VK_FORMAT_R8..._UNORM, a stored c reads as c / 255) for data such as two-channel
normal maps.

Texture arrays (``array=True``): layerCount L, and each level holds its L layers in order
(the specification's order within a level: layers, then faces, then rows).

Block-compressed textures (:class:`bakeshop.io.compress.BlockTexture`) are written by
:func:`write_ktx2_blocks`: the exact VkFormat (VK_FORMAT_BC6H_UFLOAT_BLOCK 143, BC6H_SFLOAT 144,
BC7_UNORM 145, BC7_SRGB 146, ...), typeSize 1, a data format descriptor with the format's colour
model (KHR_DF_MODEL_BC1A ... BC7), 4x4 texel blocks and the samples of the Khronos Data Format
spec's example descriptors, and optionally Zstandard supercompression (scheme 2: each level
deflated on its own, levels byte-aligned, ``uncompressedByteLength`` the inflated size;
"KTXwriterScParams" records the level).

The reader takes what these writers write: float formats, and the block formats, decoded with
bakeshop's own decoders (:func:`read_ktx2`) or kept as blocks (:func:`read_ktx2_blocks`), with
or without Zstandard. The data format descriptor is kept as bytes, not interpreted.
"""

from __future__ import annotations

import math
import os
import struct
from collections.abc import Iterable, Sequence
from types import ModuleType
from typing import TYPE_CHECKING, BinaryIO, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import __version__
from bakeshop.errors import (
    ArgumentError,
    BakeshopError,
    FormatError,
    UnsupportedError,
    validate_choice,
    with_article,
)
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
    UNORM_DTYPES,
    check_chain_decode,
    check_levels,
    encode,
    mip_size,
    names_its_file,
)
from bakeshop.io._quantize import unsigned_to_float
from bakeshop.io.ktx import _key_values

if TYPE_CHECKING:
    from bakeshop.io.compress.formats import BlockFormat
    from bakeshop.io.compress.texture import BlockTexture


NAME = "KTX2"
IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"

#: (dtype name, channels) -> VkFormat.
VK_FORMATS = {
    ("float16", 1): 76,  # VK_FORMAT_R16_SFLOAT
    ("float16", 2): 83,  # VK_FORMAT_R16G16_SFLOAT
    ("float16", 3): 90,  # VK_FORMAT_R16G16B16_SFLOAT
    ("float16", 4): 97,  # VK_FORMAT_R16G16B16A16_SFLOAT
    ("float32", 1): 100,  # VK_FORMAT_R32_SFLOAT
    ("float32", 2): 103,  # VK_FORMAT_R32G32_SFLOAT
    ("float32", 3): 106,  # VK_FORMAT_R32G32B32_SFLOAT
    ("float32", 4): 109,  # VK_FORMAT_R32G32B32A32_SFLOAT
    ("unorm8", 1): 9,  # VK_FORMAT_R8_UNORM
    ("unorm8", 2): 16,  # VK_FORMAT_R8G8_UNORM
    ("unorm8", 3): 23,  # VK_FORMAT_R8G8B8_UNORM
    ("unorm8", 4): 37,  # VK_FORMAT_R8G8B8A8_UNORM
}
#: Every sample type this module stores.
SAMPLE_TYPES = {**DTYPES, **UNORM_DTYPES}
# Khronos Data Format: colour model, primaries, transfer, channel ids and sample qualifiers.
KHR_DF_MODEL_RGBSDA, KHR_DF_PRIMARIES_BT709, KHR_DF_TRANSFER_LINEAR = 1, 1, 1
CHANNEL_IDS = (0, 1, 2, 15)  # R, G, B, alpha
KHR_DF_SAMPLE_DATATYPE_SIGNED, KHR_DF_SAMPLE_DATATYPE_FLOAT = 0x40, 0x80
FLOAT_LOWER, FLOAT_UPPER = 0xBF800000, 0x3F800000  # -1.0f and 1.0f

_HEADER = struct.Struct("<12s9I4I2Q")
_LEVEL = struct.Struct("<3Q")

#: supercompression schemes: name -> supercompressionScheme.
SUPERCOMPRESSION = {"none": 0, "zstd": 2}
KHR_DF_SAMPLE_DATATYPE_FLOAT_BITS = {False: 0, True: KHR_DF_SAMPLE_DATATYPE_FLOAT}
KHR_DF_TRANSFER_SRGB = 2

__all__ = [
    "write_ktx2",
    "write_ktx2_blocks",
    "read_ktx2",
    "read_ktx2_blocks",
    "sniff",
    "zstandard",
]


def sniff(head: bytes) -> bool:
    """True if ``head`` starts with the KTX 2.0 identifier."""
    return head[: len(IDENTIFIER)] == IDENTIFIER


def _pad(n: int, align: int) -> int:
    return -(-n // align) * align


def data_format_descriptor(dtype: str, channels: int) -> bytes:
    """The basic data format descriptor block of a linear RGBA-like format (signed float, or
    unsigned normalised for ``unorm8``), preceded by its total size (as stored in KTX2)."""
    bits = SAMPLE_TYPES[dtype].itemsize * 8
    block = 24 + 16 * channels
    words = [
        0,  # vendorId 0 (Khronos), descriptorType 0 (basic)
        2 | block << 16,  # versionNumber 2, descriptorBlockSize
        KHR_DF_MODEL_RGBSDA | KHR_DF_PRIMARIES_BT709 << 8 | KHR_DF_TRANSFER_LINEAR << 16,
        0,  # texelBlockDimension 1x1x1x1 (stored as 0s)
        channels * bits // 8,  # bytesPlane0
        0,
    ]
    if dtype in UNORM_DTYPES:
        qualifiers, lower, upper = 0, 0, (1 << bits) - 1
    else:
        qualifiers = KHR_DF_SAMPLE_DATATYPE_SIGNED | KHR_DF_SAMPLE_DATATYPE_FLOAT
        lower, upper = FLOAT_LOWER, FLOAT_UPPER
    for c in range(channels):
        words += [
            c * bits | (bits - 1) << 16 | (CHANNEL_IDS[c] | qualifiers) << 24,
            0,  # samplePosition 0
            lower,
            upper,
        ]
    return struct.pack(f"<{len(words) + 1}I", 4 + block, *words)


def block_format_descriptor(fmt: BlockFormat) -> bytes:
    """The basic data format descriptor of a block-compressed format (with its total size), as
    the Khronos Data Format spec's example descriptors give it: 4x4x1x1 texel blocks, one plane
    of the block's bytes, and one sample per stored part of the block (BC3: alpha then colour,
    BC5: red then green; BC1 one sample of channel 1, ALPHAPRESENT, as its VkFormat is the
    RGBA one; the others one sample covering the whole block). BC6H samples are
    float (and signed for SFLOAT) with bounds -1.0 or 0.0 .. 1.0; the others unsigned with
    bounds 0 .. UINT32_MAX."""
    if fmt.name.startswith("bc3"):
        samples = [(15, 0, 64), (0, 64, 64)]
    elif fmt.name == "bc5":
        samples = [(0, 0, 64), (1, 64, 64)]
    elif fmt.name.startswith("bc1"):  # BC1 RGBA: channel 1, the punch-through alpha is live
        samples = [(1, 0, 64)]
    else:
        samples = [(0, 0, fmt.block_bytes * 8)]
    block = 24 + 16 * len(samples)
    transfer = KHR_DF_TRANSFER_SRGB if fmt.srgb else KHR_DF_TRANSFER_LINEAR
    words = [
        0,  # vendorId 0 (Khronos), descriptorType 0 (basic)
        2 | block << 16,  # versionNumber 2, descriptorBlockSize
        fmt.df_model | KHR_DF_PRIMARIES_BT709 << 8 | transfer << 16,  # flags 0: straight alpha
        3 | 3 << 8,  # texelBlockDimension 4x4x1x1 (stored minus one)
        fmt.block_bytes,  # bytesPlane0
        0,
    ]
    for channel, offset, length in samples:
        qualifiers = 0
        lower, upper = 0, 0xFFFFFFFF
        if fmt.hdr:
            qualifiers = KHR_DF_SAMPLE_DATATYPE_FLOAT
            lower, upper = 0, FLOAT_UPPER
            if fmt.signed:
                qualifiers |= KHR_DF_SAMPLE_DATATYPE_SIGNED
                lower = FLOAT_LOWER
        words += [offset | (length - 1) << 16 | (channel | qualifiers) << 24, 0, lower, upper]
    return struct.pack(f"<{len(words) + 1}I", 4 + block, *words)


def _key_value_data(pairs: Iterable[tuple[bytes, bytes]]) -> bytes:
    kv = b""
    for key, value in pairs:
        entry = key + b"\x00" + value + b"\x00"
        kv += struct.pack("<I", len(entry)) + entry
        kv += bytes(_pad(len(kv), 4) - len(kv))
    return kv


def zstandard() -> ModuleType:
    """The ``zstandard`` module, or a one-line install hint (the compress extra)."""
    try:
        import zstandard
    except ImportError:
        raise BakeshopError(
            "Zstandard supercompression needs the zstandard package: install bakeshop[compress]"
        ) from None
    return zstandard


def write_ktx2_blocks(
    path: str | os.PathLike,
    texture: BlockTexture,
    *,
    supercompression: str = "none",
    zstd_level: int = 19,
    key_values: dict | None = None,
) -> None:
    """Write a block-compressed texture (:class:`bakeshop.io.compress.BlockTexture`) as KTX 2.0.

    Parameters
    ----------
    path : path-like
        Written atomically.
    texture : BlockTexture
        A cube map (faces in OpenGL order, which Vulkan samples) or a 2-D texture.
    supercompression : {"none", "zstd"}
        Zstandard (scheme 2) deflates each level on its own; needs the ``zstandard`` package
        (install bakeshop[compress]).
    zstd_level : int
        Zstandard level, 1 (fastest) to 22 (smallest).
    key_values : dict of str to str, optional
        Further key/value entries (sorted by key with the writer's own, as the spec requires).
    """
    validate_choice(supercompression, tuple(SUPERCOMPRESSION), "KTX2 supercompression")
    if not 1 <= zstd_level <= 22:
        raise ArgumentError(f"zstd_level must be in 1..22, got {zstd_level}")
    fmt = texture.format
    levels = list(texture.levels)
    scheme = SUPERCOMPRESSION[supercompression]
    pairs = {
        "KTXorientation": "rd",
        "KTXwriter": f"bakeshop {__version__}",
        **(key_values or {}),
    }
    if scheme:
        pairs["KTXwriterScParams"] = f"--zcmp {zstd_level}"
        compressor = zstandard().ZstdCompressor(level=zstd_level)
        data = [compressor.compress(level) for level in levels]
    else:
        data = levels
    kv = _key_value_data((k.encode(), v.encode()) for k, v in sorted(pairs.items()))
    dfd = block_format_descriptor(fmt)
    align = 1 if scheme else fmt.block_bytes * 4 // math.gcd(fmt.block_bytes, 4)
    index_end = _HEADER.size + _LEVEL.size * len(levels)
    dfd_offset = index_end
    kv_offset = dfd_offset + len(dfd)
    offsets = [0] * len(levels)
    position = kv_offset + len(kv)
    for m in reversed(range(len(levels))):  # the smallest level first
        position = _pad(position, align)
        offsets[m] = position
        position += len(data[m])
    header = _HEADER.pack(
        IDENTIFIER, fmt.vk, 1, texture.width, texture.height, 0, 0, texture.faces, len(levels),
        scheme, dfd_offset, len(dfd), kv_offset, len(kv), 0, 0,
    )  # fmt: skip
    index = b"".join(
        _LEVEL.pack(offsets[m], len(data[m]), len(levels[m])) for m in range(len(levels))
    )
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(header + index + dfd + kv)
        for m in reversed(range(len(levels))):
            f.write(bytes(offsets[m] - f.tell()))
            f.write(data[m])


def write_ktx2(
    path: str | os.PathLike,
    mips: Sequence[ArrayLike],
    *,
    dtype: str = "float16",
    array: bool = False,
) -> None:
    """Write a mip chain (a cube map, a 2-D texture or a 2-D texture array) as a KTX 2.0 file.

    Parameters
    ----------
    path : path-like
        Written atomically (a failed write leaves no partial file).
    mips : sequence of arrays, level 0 first
        Cube map levels ``(6, S, S, C)`` in OpenGL face order, or 2-D levels ``(H, W, C)`` (or
        ``(H, W)``), C in 1..4, each level half the previous (floor, at least 1); with
        ``array=True``, ``(L, H, W, C)`` levels of L layers. NaN is refused.
    dtype : {"float16", "float32", "unorm8"}
        Stored sample type (VK_FORMAT_R16G16B16A16_SFLOAT and friends, the 32-bit ones, or
        VK_FORMAT_R8G8_UNORM and friends: floats in [0, 1] rounded to c / 255, or uint8 as is).
    array : bool
        Write a texture array (layerCount = L, even for L = 1).
    """
    validate_choice(dtype, tuple(SAMPLE_TYPES), "KTX2 sample type")
    levels, cube = check_levels(mips, array=array)
    channels = levels[0].shape[-1]
    height, width = levels[0].shape[-3:-1]
    layers = levels[0].shape[0] if array else 0
    texel = channels * SAMPLE_TYPES[dtype].itemsize
    align = texel * 4 // math.gcd(texel, 4)
    dfd = data_format_descriptor(dtype, channels)
    kv = _key_value_data(
        ((b"KTXorientation", b"rd"), (b"KTXwriter", f"bakeshop {__version__}".encode()))
    )
    index_end = _HEADER.size + _LEVEL.size * len(levels)
    dfd_offset = index_end
    kv_offset = dfd_offset + len(dfd)
    data = [np.ascontiguousarray(encode(level, SAMPLE_TYPES[dtype])).tobytes() for level in levels]
    offsets = [0] * len(levels)
    position = kv_offset + len(kv)
    for m in reversed(range(len(levels))):  # the smallest level first
        position = _pad(position, align)
        offsets[m] = position
        position += len(data[m])
    header = _HEADER.pack(
        IDENTIFIER, VK_FORMATS[dtype, channels], SAMPLE_TYPES[dtype].itemsize, width, height, 0,
        layers, 6 if cube else 1, len(levels), 0, dfd_offset, len(dfd), kv_offset, len(kv), 0, 0,
    )  # fmt: skip
    index = b"".join(
        _LEVEL.pack(offsets[m], len(data[m]), len(data[m])) for m in range(len(levels))
    )
    with (
        _intent.intent(path, "mips", levels, dtype=dtype, array=array),
        atomic_path(path) as tmp,
        open(tmp, "wb") as f,
    ):
        f.write(header + index + dfd + kv)
        for m in reversed(range(len(levels))):
            f.write(bytes(offsets[m] - f.tell()))
            f.write(data[m])


@names_its_file
def read_ktx2_blocks(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[BlockTexture, dict]:
    """Read a block-compressed KTX 2.0 file without decoding it (Zstandard levels inflated).

    Returns
    -------
    texture : bakeshop.io.compress.BlockTexture
    metadata : dict
        As :func:`read_ktx2` returns it.
    """
    texture, metadata = _read(path, max_pixels, decode=False)
    if texture is None:
        raise UnsupportedError("this KTX2 file is not block-compressed; read it with read_ktx2")
    return texture, metadata


@names_its_file
def read_ktx2(
    path: str | os.PathLike, *, max_pixels: int = MAX_PIXELS
) -> tuple[list[np.ndarray], dict]:
    """Read a KTX 2.0 file (a cube map, a 2-D texture or a 2-D texture array with its mips) as
    float mips.

    Float files are returned as stored; block-compressed files (with or without Zstandard) are
    decoded with bakeshop's own decoders (:func:`bakeshop.io.compress.decode_image`).

    Returns
    -------
    mips : list of float32 arrays
        Level 0 first; ``(6, S, S, C)`` per level for a cube map, ``(H, W, C)`` for a 2-D
        texture, ``(L, H, W, C)`` for a texture array. ``unorm8`` samples read as c / 255.
    metadata : dict
        ``format`` ("KTX2"), ``stored`` ("float16", "float32", "unorm8" or a block format's
        name), ``cube`` (bool), ``layers`` (L, 0 for a texture that is not an array),
        ``vk_format`` (int), ``supercompression`` ("none" or "zstd"),
        ``key_values`` (dict of str to bytes) and ``dfd`` (bytes).

    Raises
    ------
    bakeshop.errors.FormatError
        Not a KTX2 file, an inconsistent header or level index, or a truncated file.
    bakeshop.errors.UnsupportedError
        Other formats and supercompression schemes, 3-D textures, cube map arrays and
        block-compressed arrays.
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


def _read_at(f: BinaryIO, offset: int, size: int, what: str) -> bytes:
    """``size`` bytes of ``f`` from ``offset`` (:func:`bakeshop.io._files.read_payload`)."""
    f.seek(offset)
    return read_payload(f, size, what)


def _read_levels(
    f: BinaryIO, max_pixels: int, decode: bool
) -> tuple[list[np.ndarray] | BlockTexture | None, dict]:
    """The header and level index of the KTX2 file ``f``, checked against its size and the
    decode budget; then each level read (and inflated) in turn: never the whole file."""
    from bakeshop.io.compress.formats import FORMATS, level_bytes

    file_size = os.fstat(f.fileno()).st_size
    data = f.read(_HEADER.size)
    if len(data) < _HEADER.size or not sniff(data):
        raise FormatError("not a KTX2 file (bad identifier)")
    (_, vk_format, type_size, width, height, depth, layers, faces, level_count, scheme,
     dfd_offset, dfd_length, kv_offset, kv_length, _, _) = _HEADER.unpack_from(data)  # fmt: skip
    block = next((f for f in FORMATS.values() if f.vk == vk_format), None)
    match = [k for k, v in VK_FORMATS.items() if v == vk_format]
    if block is None and not match:
        raise UnsupportedError(
            f"VkFormat {vk_format} is not supported (only float, 8-bit unorm and BC1/3/4/5/6H/7)"
        )
    if block is not None:
        if type_size != 1:
            raise FormatError(f"typeSize {type_size} of a block format (must be 1)")
    else:
        dtype, channels = match[0]
        if type_size != SAMPLE_TYPES[dtype].itemsize:
            raise FormatError(f"typeSize {type_size} does not match VkFormat {vk_format}")
    schemes = {v: k for k, v in SUPERCOMPRESSION.items()}
    if scheme not in schemes:
        raise UnsupportedError(f"supercompression scheme {scheme} is not supported")
    if depth:
        raise UnsupportedError("3-D textures are not supported")
    if faces not in (1, 6):
        raise FormatError(f"faceCount is {faces} (expected 1 or 6)")
    cube = faces == 6
    if layers and (cube or block is not None):
        what = "cube map" if cube else "block-compressed"
        raise UnsupportedError(f"{what} arrays are not supported")
    if not (1 <= width and 1 <= height and width * height * max(layers, 1) <= max_pixels):
        raise FormatError(f"KTX2 size {width}x{height} out of range (limit {max_pixels} pixels)")
    if cube and width != height:
        raise FormatError(f"a cube map's faces must be square; the header says {width}x{height}")
    levels = max(level_count, 1)
    if levels > MAX_LEVELS or max(width, height) >> (levels - 1) == 0:
        raise FormatError(
            f"{levels} mip levels is more than {with_article(width)}x{height} texture has"
        )
    check_payload(_HEADER.size + _LEVEL.size * levels, file_size, "level index")
    for offset, length, what in ((dfd_offset, dfd_length, "format descriptor"),
                                 (kv_offset, kv_length, "key/value data")):  # fmt: skip
        check_payload(offset + length, file_size, what)
    if scheme:
        try:
            import zstandard
        except ImportError:
            raise BakeshopError(
                "this KTX2 file is Zstandard-supercompressed: install bakeshop[compress]"
            ) from None
        inflater = zstandard.ZstdDecompressor()
    table = read_payload(f, _LEVEL.size * levels, "level index")
    index = [_LEVEL.unpack_from(table, _LEVEL.size * m) for m in range(levels)]
    sizes = []
    for m, (offset, length, full) in enumerate(index):
        h, w = mip_size(height, m), mip_size(width, m)
        if block is not None:
            expected = faces * level_bytes(block, w, h)
        else:
            expected = max(layers, 1) * faces * h * w * channels * SAMPLE_TYPES[dtype].itemsize
        if full != expected or (not scheme and length != expected):
            raise FormatError(f"level {m}: byteLength {length}, expected {expected}")
        check_payload(offset + length, file_size, f"level {m}")
        sizes.append(expected)
    images = max(layers, 1) * faces
    check_chain_decode(
        width, height, levels, images, channels if block is None else block.channels,
        sum(sizes), file_size, decode=decode,
    )  # fmt: skip
    raw_levels = []
    for m, ((offset, length, _), expected) in enumerate(zip(index, sizes, strict=True)):
        level = _read_at(f, offset, length, f"level {m}")
        if scheme:
            # the output is capped by the size the index declares (zstandard trusts a frame's
            # own content size over the cap, so a frame declaring another size is refused first)
            try:
                declared = zstandard.frame_content_size(level)
                if declared not in (-1, expected):  # -1: the frame does not say
                    raise FormatError(
                        f"level {m}: its Zstandard frame declares {declared} bytes, the level "
                        f"index {expected}"
                    )
                level = inflater.decompress(level, max_output_size=expected)
            except zstandard.ZstdError as e:
                raise FormatError(f"level {m}: corrupt Zstandard data ({e})") from None
            if len(level) != expected:
                raise FormatError(f"level {m} inflates to {len(level)} bytes, expected {expected}")
        raw_levels.append(level)
    metadata = {
        "format": NAME,
        "stored": block.name if block is not None else dtype,
        "cube": cube,
        "layers": layers,
        "vk_format": vk_format,
        "supercompression": schemes[scheme],
        "key_values": _key_values(_read_at(f, kv_offset, kv_length, "key/value data"), "<"),
        "dfd": _read_at(f, dfd_offset, dfd_length, "format descriptor"),
    }
    if block is not None:
        from bakeshop.io.compress.texture import BlockTexture

        texture = BlockTexture(block, width, height, cube, tuple(raw_levels))
        return (texture.decode() if decode else texture), metadata
    if not decode:
        return None, metadata
    stored = np.dtype(SAMPLE_TYPES[dtype])
    mips = []
    for m, raw in enumerate(raw_levels):
        h, w = mip_size(height, m), mip_size(width, m)
        values = np.frombuffer(raw, stored)
        if dtype in UNORM_DTYPES:
            values = unsigned_to_float(values, 8)
        values = values.reshape(max(layers, 1) * faces, h, w, channels).astype(np.float32)
        mips.append(values if cube or layers else values[0])
    return mips, metadata
