"""Tangent-space normal maps: encodings, blend methods, tiling, transfer into a mesh's UVs, height.

The public functions are here; the submodules, each named for what it holds:

- :mod:`bakeshop.normals.encoding`: stored values <-> unit vectors (GL/DX, BC5, checks).
- :mod:`bakeshop.normals.blend`: macro + detail with every established method and the exact one.
- :mod:`bakeshop.normals.tiling`: placing a tileable detail map (scale, offset, rotation, masks).
- :mod:`bakeshop.normals.transfer`: baking a detail map into a mesh's macro UV layout.
- :mod:`bakeshop.normals.height`: height map -> normal map.
"""

from typing import TYPE_CHECKING

from bakeshop._lazy import export_lazily

# names load from their module when first read (a command's options name the methods and
# encodings without loading the kernels)
export_lazily(
    __name__,
    {
        "blend": "blend",
        "NormalCheck": "encoding",
        "check_normals": "encoding",
        "convert_convention": "encoding",
        "convert_normal_map": "encoding",
        "decode_normals": "encoding",
        "encode_normals": "encoding",
        "normalize": "encoding",
        "height_to_normal": "height",
        "DetailLayer": "tiling",
        "apply_layers": "tiling",
        "mask_weights": "tiling",
        "place_detail": "tiling",
        "corner_tangents": "transfer",
        "rasterize_uv": "transfer",
        "transfer_detail": "transfer",
    },
)

if TYPE_CHECKING:  # what the table loads, for type checkers (tests/test_lazy.py)
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
