"""Tangent-space normal maps: encodings, blend methods, tiling, transfer into a mesh's UVs, height.

The public functions are here; the submodules, each named for what it holds:

- :mod:`bakeshop.normals.encoding`: stored values <-> unit vectors (GL/DX, BC5, checks).
- :mod:`bakeshop.normals.blend`: macro + detail with every established method and the exact one.
- :mod:`bakeshop.normals.tiling`: placing a tileable detail map (scale, offset, rotation, masks).
- :mod:`bakeshop.normals.transfer`: baking a detail map into a mesh's macro UV layout.
- :mod:`bakeshop.normals.height`: height map -> normal map.
"""

from bakeshop.normals.blend import blend
from bakeshop.normals.encoding import (
    NormalCheck,
    check_normals,
    convert_convention,
    convert_normal_map,
    decode_normals,
    encode_normals,
    normalize,
)
from bakeshop.normals.height import height_to_normal
from bakeshop.normals.tiling import DetailLayer, apply_layers, mask_weights, place_detail
from bakeshop.normals.transfer import corner_tangents, rasterize_uv, transfer_detail

__all__ = [
    "DetailLayer",
    "NormalCheck",
    "apply_layers",
    "blend",
    "check_normals",
    "convert_convention",
    "convert_normal_map",
    "corner_tangents",
    "decode_normals",
    "encode_normals",
    "height_to_normal",
    "mask_weights",
    "normalize",
    "place_detail",
    "rasterize_uv",
    "transfer_detail",
]
