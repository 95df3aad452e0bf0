"""The layouts' scalar maps, for numba code outside :mod:`bakeshop.sphere`.

These are the functions every layout and every sampling kernel is computed with, so a numba
kernel elsewhere (a prefilter's cube lookups, say) finds texels exactly as ``remap`` does. A
layout is named by its kind number (:attr:`Layout.kind`) and its grid ``(h, w)``
(:meth:`Layout.grid`); coordinates are ``(face, x, y)``, texel ``i``'s centre at
``x = i + 0.5``.

- ``direction(kind, h, w, f, x, y) -> (dx, dy, dz)``: the unit direction at coordinates;
- ``coordinates(kind, h, w, x, y, z) -> (f, x, y)``: the coordinates of a direction;
- ``cube_face(x, y, z) -> (face, sc, tc)``: OpenGL's major-axis rule, sc and tc in [-1, 1];
- ``valid(kind, h, w, f, i, j) -> bool``: whether texel (f, i, j) holds data.
"""

from bakeshop.sphere._maps import coordinates, cube_face, direction, valid

__all__ = ["coordinates", "cube_face", "direction", "valid"]
