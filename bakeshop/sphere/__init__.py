"""Directions on the unit sphere and every panorama layout.

>>> from bakeshop.sphere import layout, remap, sample
>>> L = layout("latlong")
>>> dirs, valid = L.directions(L.shape(256))          # (256, 512, 3), (256, 512)
>>> omega = L.solid_angles(L.shape(256))               # sums to 4 pi

Layouts: ``latlong``, ``angular`` (Debevec light probe) and ``mirrorball`` as HDRShop reads
them (centre forward, -Z), ``angular-physical`` and ``mirrorball-physical`` (the exact
reflection in a photographed ball, centre +Z), ``cube`` (internal ``(6, S, S, C)``, OpenGL
order and orientation), the cube's pictures ``cross-vertical``, ``cross-horizontal``,
``strip-horizontal``, ``strip-vertical``, ``octahedral``, ``dual-paraboloid``, and OpenEXR's
environment maps ``openexr-latlong`` and ``openexr-cube`` (``ImfEnvmap.h``). Every spherical
function takes ``(image, layout)`` and checks it with :func:`check_environment` (one rule for
shapes, channels and values). See docs/panoramas.md for pictures and docs/conventions.md for
the conventions. :mod:`bakeshop.sphere.windows` computes a part of a remap from a window of
its source (images larger than memory, :mod:`bakeshop.huge`).
"""

from typing import TYPE_CHECKING

from bakeshop._lazy import export_lazily

# names load from their module when first read (scipy and the kernels only where needed)
export_lazily(
    __name__,
    {
        "cache_info": "_cache",
        "clear_caches": "_cache",
        "CONVENTIONS": "cube",
        "FACE_LABELS": "cube",
        "FACE_NAMES": "cube",
        "FACE_NAMES_SHORT": "cube",
        "cube_to_faces": "cube",
        "cube_to_view": "cube",
        "faces_to_cube": "cube",
        "view_to_cube": "cube",
        "FILE_LAYOUTS": "layouts",
        "LAYOUT_NAMES": "layouts",
        "Layout": "layouts",
        "guess_layout": "_guess",
        "layout": "layouts",
        "as_rotation": "rotation",
        "rotation_matrix": "rotation",
        "FILTERS": "sampling",
        "auto_filter": "sampling",
        "remap": "sampling",
        "remap_cost": "sampling",
        "remap_shape": "sampling",
        "sample": "sampling",
        "valid_texels": "sampling",
        "Environment": "texels",
        "Texels": "texels",
        "check_environment": "texels",
        "texel_cosines": "texels",
        "texel_geometry": "texels",
        "texels": "texels",
        "STRIP_TEXELS": "texels",
        "texel_rows": "texels",
        "texel_strips": "texels",
        "texels_at": "texels",
        "persist_caches": "_cache",
    },
)

if TYPE_CHECKING:  # what the table loads, for type checkers (tests/test_lazy.py)
    from bakeshop.sphere._cache import (
        cache_info,
        clear_caches,
        persist_caches,
    )
    from bakeshop.sphere._guess import (
        guess_layout,
    )
    from bakeshop.sphere.cube import (
        CONVENTIONS,
        FACE_LABELS,
        FACE_NAMES,
        FACE_NAMES_SHORT,
        cube_to_faces,
        cube_to_view,
        faces_to_cube,
        view_to_cube,
    )
    from bakeshop.sphere.layouts import (
        FILE_LAYOUTS,
        LAYOUT_NAMES,
        Layout,
        layout,
    )
    from bakeshop.sphere.rotation import (
        as_rotation,
        rotation_matrix,
    )
    from bakeshop.sphere.sampling import (
        FILTERS,
        auto_filter,
        remap,
        remap_cost,
        remap_shape,
        sample,
        valid_texels,
    )
    from bakeshop.sphere.texels import (
        STRIP_TEXELS,
        Environment,
        Texels,
        check_environment,
        texel_cosines,
        texel_geometry,
        texel_rows,
        texel_strips,
        texels,
        texels_at,
    )

__all__ = [
    "STRIP_TEXELS",
    "persist_caches",
    "CONVENTIONS",
    "FACE_LABELS",
    "FACE_NAMES",
    "FACE_NAMES_SHORT",
    "FILE_LAYOUTS",
    "FILTERS",
    "LAYOUT_NAMES",
    "Environment",
    "Layout",
    "Texels",
    "as_rotation",
    "auto_filter",
    "cache_info",
    "check_environment",
    "clear_caches",
    "cube_to_faces",
    "cube_to_view",
    "faces_to_cube",
    "guess_layout",
    "layout",
    "remap",
    "remap_cost",
    "remap_shape",
    "valid_texels",
    "rotation_matrix",
    "sample",
    "texel_cosines",
    "texel_geometry",
    "texel_rows",
    "texel_strips",
    "texels",
    "texels_at",
    "view_to_cube",
]
