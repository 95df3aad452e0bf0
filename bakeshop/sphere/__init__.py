"""Directions on the unit sphere and every panorama layout.

>>> from bakeshop.sphere import layout, remap, sample
>>> L = layout("latlong")
>>> dirs, valid = L.directions(L.shape(256))          # (256, 512, 3), (256, 512)
>>> omega = L.solid_angles(L.shape(256))               # sums to 4 pi

Layouts: ``latlong``, ``angular`` (Debevec light probe), ``mirrorball``, ``cube`` (internal
``(6, S, S, C)``, OpenGL order and orientation), the cube's pictures ``cross-vertical``,
``cross-horizontal``, ``strip-horizontal``, ``strip-vertical``, ``octahedral`` and
``dual-paraboloid``. See docs/panoramas.md for pictures and conventions.
"""

from bakeshop.sphere.cube import (
    CONVENTIONS,
    FACE_NAMES,
    FACE_NAMES_SHORT,
    cube_to_faces,
    cube_to_view,
    faces_to_cube,
    view_to_cube,
)
from bakeshop.sphere.layouts import LAYOUT_NAMES, Layout, guess_layout, layout
from bakeshop.sphere.sampling import FILTERS, as_rotation, remap, rotation_matrix, sample

__all__ = [
    "CONVENTIONS",
    "FACE_NAMES",
    "FACE_NAMES_SHORT",
    "FILTERS",
    "LAYOUT_NAMES",
    "Layout",
    "as_rotation",
    "cube_to_faces",
    "cube_to_view",
    "faces_to_cube",
    "guess_layout",
    "layout",
    "remap",
    "rotation_matrix",
    "sample",
    "view_to_cube",
]
