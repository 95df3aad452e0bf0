"""Block-compressed textures: BC1, BC3, BC4, BC5, BC6H and BC7, encoded and decoded."""

from bakeshop.io.compress.decode import decode_image
from bakeshop.io.compress.encode import QUALITIES, encode_image
from bakeshop.io.compress.formats import FORMATS, BlockFormat, block_format

__all__ = ["FORMATS", "BlockFormat", "block_format", "QUALITIES", "encode_image", "decode_image"]
