"""Panorama layouts: where each texel looks, how much of the sphere it covers, and where a
direction lands.

Every layout answers three questions, and everything spherical in bakeshop (remapping, SH
projection, irradiance, sun detection) is written against them, never against one layout:

- :meth:`Layout.directions`: the unit direction of each texel centre, with a validity mask
  (False outside the disk of the disk layouts and in the unused squares of a cross);
- :meth:`Layout.solid_angles`: the exact solid angle of each texel (0 where invalid); they sum
  to 4*pi over a layout;
- :meth:`Layout.coordinates`: the continuous texel coordinates of directions (texel ``i``'s
  centre is at ``x = i + 0.5``).

The world frame is right-handed, +Y up, -Z forward, +X right (DESIGN.md). Texel ``(i, j)`` is
``(column, row)``, row 0 at the top; ``u = (i + 0.5) / W``, ``v = (j + 0.5) / H`` at its centre.
Sizes: :meth:`Layout.shape` turns a user size (an int, or ``(width, height)``) into the
layout's array shape.
"""

from __future__ import annotations

from bakeshop.errors import validate_choice
from bakeshop.sphere import cube as _cube
from bakeshop.sphere._guess import guess_layout
from bakeshop.sphere.layouts.base import MAX_EDGE, MAX_TEXELS, Layout, power_of_two_edge
from bakeshop.sphere.layouts.cubemap import CUBE, Cube, CubeView
from bakeshop.sphere.layouts.disk import (
    Angular,
    AngularPhysical,
    DualParaboloid,
    MirrorBall,
    MirrorBallPhysical,
)
from bakeshop.sphere.layouts.latlong import LatLong
from bakeshop.sphere.layouts.octahedral import Octahedral
from bakeshop.sphere.layouts.openexr import OpenEXRCube, OpenEXRLatLong

__all__ = [
    "CUBE",
    "FILE_LAYOUTS",
    "LAYOUT_NAMES",
    "MAX_EDGE",
    "MAX_TEXELS",
    "Angular",
    "AngularPhysical",
    "Cube",
    "CubeView",
    "DualParaboloid",
    "LatLong",
    "Layout",
    "MirrorBall",
    "MirrorBallPhysical",
    "Octahedral",
    "OpenEXRCube",
    "OpenEXRLatLong",
    "guess_layout",
    "layout",
    "power_of_two_edge",
]

_LAYOUTS: dict[str, Layout] = {
    lay.name: lay
    for lay in (
        LatLong(),
        Angular(),
        MirrorBall(),
        AngularPhysical(),
        MirrorBallPhysical(),
        CUBE,
        Octahedral(),
        DualParaboloid(),
        OpenEXRLatLong(),
        OpenEXRCube(),
        *(CubeView(v) for v in _cube.VIEWS),
    )
}

#: every layout name :func:`layout` accepts.
LAYOUT_NAMES = tuple(_LAYOUTS)
#: the layouts one image file holds (a cube is written as a cross or a strip).
FILE_LAYOUTS = tuple(name for name in LAYOUT_NAMES if name != "cube")


def layout(name: str | Layout) -> Layout:
    """The layout called ``name``: one of :data:`LAYOUT_NAMES`.

    >>> layout("latlong").shape(512)
    (512, 1024)
    """
    if isinstance(name, Layout):
        return name
    validate_choice(name, LAYOUT_NAMES, "layout")
    return _LAYOUTS[name]
