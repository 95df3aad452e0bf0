"""Tangent-space normal maps: encodings, blend methods, tiling, transfer into a mesh's UVs, height.

Import from the submodules, each named for what it holds:

- :mod:`bakeshop.normals.encoding`: files and values <-> unit vectors (GL/DX, BC5, checks).
- :mod:`bakeshop.normals.blend`: macro + detail with every established method and the exact one.
- :mod:`bakeshop.normals.tiling`: placing a tileable detail map (scale, offset, rotation, masks).
- :mod:`bakeshop.normals.transfer`: baking a detail map into a mesh's macro UV layout.
- :mod:`bakeshop.normals.height`: height map -> normal map.
"""
