"""Block-compressed textures: BC1, BC3, BC4, BC5, BC6H and BC7, encoded, decoded and measured.

- :mod:`~bakeshop.io.compress.formats`: the formats and their numbers in every API (DXGI,
  VkFormat, OpenGL, Khronos Data Format);
- :mod:`~bakeshop.io.compress.encode`: ISPC's encoders through ``ispc-texcomp`` (and
  :mod:`~bakeshop.io.compress.bc6h_signed`, bakeshop's signed BC6H encoder);
- :mod:`~bakeshop.io.compress.decode`: bakeshop's own decoders, from the specification;
- :mod:`~bakeshop.io.compress.texture`: whole cube maps and 2-D textures with their mip chains,
  and the explicit choice for values above 65504;
- :mod:`~bakeshop.io.compress.quality` and :mod:`~bakeshop.io.compress.packing`: the quality
  measures and the RGBM/RGBD packings;
- :mod:`~bakeshop.io.compress.pipeline`: float levels to a file and its JSON sidecar.

The containers that hold them are :mod:`bakeshop.io.dds`, :mod:`bakeshop.io.ktx2` and
:mod:`bakeshop.io.ktx` (``write_*_blocks``, ``read_*_blocks``; their ``read_*`` decode).
"""

from bakeshop.io.compress.decode import decode_image
from bakeshop.io.compress.encode import HALF_MAX, QUALITIES, encode_image
from bakeshop.io.compress.formats import FORMATS, BlockFormat, block_format
from bakeshop.io.compress.texture import OVERFLOW, BlockTexture, check_range, encode_texture

__all__ = [
    "FORMATS",
    "BlockFormat",
    "block_format",
    "QUALITIES",
    "HALF_MAX",
    "OVERFLOW",
    "encode_image",
    "decode_image",
    "BlockTexture",
    "encode_texture",
    "check_range",
]
