"""The block-compressed texture formats bakeshop writes, as plain data.

Each :class:`BlockFormat` names one format and the numbers every container and API uses for it:
the DXGI format (DDS's DX10 header, Direct3D), the VkFormat (KTX2, Vulkan), the OpenGL internal
format and base format (KTX 1, ``glCompressedTexImage2D``) and the Khronos Data Format colour
model (the KTX2 data format descriptor). Sources: Microsoft, "DXGI_FORMAT enumeration";
Khronos, "Vulkan VkFormat"; the OpenGL extensions EXT_texture_compression_s3tc,
EXT_texture_sRGB, ARB_texture_compression_rgtc and ARB_texture_compression_bptc; Khronos Data
Format Specification 1.3, section 5.6 (``khr_df.h``).

All formats store 4x4 texel blocks, rows of blocks top to bottom; a level of W x H texels holds
``ceil(W/4) * ceil(H/4)`` blocks (the 2x2 and 1x1 levels of a mip chain hold one padded block).
"""

from __future__ import annotations

from dataclasses import dataclass

from bakeshop.errors import ArgumentError

__all__ = ["BlockFormat", "FORMATS", "block_format", "level_bytes"]


@dataclass(frozen=True)
class BlockFormat:
    """One block-compressed format and its numbers in every API."""

    #: bakeshop's name ("bc6h", "bc7-srgb", ...).
    name: str
    #: bytes per 4x4 block (8 or 16).
    block_bytes: int
    #: channels bakeshop decodes it to (BC4: 1, BC5: 2, BC6H: 3, BC1/BC3/BC7: 4).
    channels: int
    #: half-float values (BC6H); the others store 8-bit unsigned normalised values.
    hdr: bool
    #: signed values (BC6H SF16).
    signed: bool
    #: the RGB channels are stored with the sRGB transfer function (the alpha never is).
    srgb: bool
    #: DXGI_FORMAT.
    dxgi: int
    #: VkFormat.
    vk: int
    #: OpenGL internal format (glInternalFormat of KTX 1).
    gl: int
    #: OpenGL base internal format (glBaseInternalFormat of KTX 1).
    gl_base: int
    #: Khronos Data Format colour model (KHR_DF_MODEL_BC1A ... BC7).
    df_model: int


GL_RED, GL_RG, GL_RGB, GL_RGBA = 0x1903, 0x8227, 0x1907, 0x1908

#: every format bakeshop writes, by name.
FORMATS: dict[str, BlockFormat] = {
    f.name: f
    for f in (
        # BC1 as DXGI_FORMAT_BC1_UNORM / VK_FORMAT_BC1_RGBA_UNORM_BLOCK: the blocks the encoder
        # writes always use the four-colour mode, so the punch-through alpha never occurs.
        BlockFormat("bc1", 8, 4, False, False, False, 71, 133, 0x83F1, GL_RGBA, 128),
        BlockFormat("bc1-srgb", 8, 4, False, False, True, 72, 134, 0x8C4D, GL_RGBA, 128),
        BlockFormat("bc3", 16, 4, False, False, False, 77, 137, 0x83F3, GL_RGBA, 130),
        BlockFormat("bc3-srgb", 16, 4, False, False, True, 78, 138, 0x8C4F, GL_RGBA, 130),
        BlockFormat("bc4", 8, 1, False, False, False, 80, 139, 0x8DBB, GL_RED, 131),
        BlockFormat("bc5", 16, 2, False, False, False, 83, 141, 0x8DBD, GL_RG, 132),
        BlockFormat("bc6h", 16, 3, True, False, False, 95, 143, 0x8E8F, GL_RGB, 133),
        BlockFormat("bc6h-signed", 16, 3, True, True, False, 96, 144, 0x8E8E, GL_RGB, 133),
        BlockFormat("bc7", 16, 4, False, False, False, 98, 145, 0x8E8C, GL_RGBA, 134),
        BlockFormat("bc7-srgb", 16, 4, False, False, True, 99, 146, 0x8E8D, GL_RGBA, 134),
    )
}


def block_format(name: str) -> BlockFormat:
    """The :class:`BlockFormat` called ``name``; :class:`ArgumentError` listing them if none."""
    try:
        return FORMATS[name]
    except KeyError:
        raise ArgumentError(
            f"unknown block format {name!r}; choose one of: {', '.join(FORMATS)}"
        ) from None


def level_bytes(fmt: BlockFormat, width: int, height: int) -> int:
    """Bytes of one W x H image (one face of one level) in ``fmt``: whole 4x4 blocks."""
    return -(-width // 4) * -(-height // 4) * fmt.block_bytes
