"""The mode strings of bakeshop as ``Literal`` types, and the cube's faces as an ``IntEnum``.

Functions check a mode with :func:`bakeshop.errors.validate_choice`, which repeats the bad
value and lists the valid ones; these aliases let a type checker and an editor do it first.
"""

from __future__ import annotations

import enum
from typing import Literal, get_args

#: every panorama layout (:data:`bakeshop.sphere.LAYOUT_NAMES`).
LayoutName = Literal[
    "latlong",
    "angular",
    "mirrorball",
    "angular-physical",
    "mirrorball-physical",
    "cube",
    "octahedral",
    "dual-paraboloid",
    "openexr-latlong",
    "openexr-cube",
    "cross-vertical",
    "cross-horizontal",
    "strip-horizontal",
    "strip-vertical",
]
#: remap filters (:func:`bakeshop.sphere.remap`).
Filter = Literal["nearest", "bilinear", "area", "auto"]
#: engine conventions of exported cube faces (:func:`bakeshop.sphere.cube_to_faces`).
Convention = Literal["opengl", "vulkan", "directx"]
#: irradiance methods (:func:`bakeshop.light.irradiance`).
IrradianceMethod = Literal["auto", "exact", "sh"]
#: tone-mapping operators (:func:`bakeshop.image.tonemap`).
ToneOperator = Literal["none", "reinhard", "aces"]


class Face(enum.IntEnum):
    """The six cube faces in OpenGL order: index ``i`` is ``GL_TEXTURE_CUBE_MAP_POSITIVE_X + i``
    and the first axis of a ``(6, S, S, C)`` cube."""

    POSITIVE_X = 0
    NEGATIVE_X = 1
    POSITIVE_Y = 2
    NEGATIVE_Y = 3
    POSITIVE_Z = 4
    NEGATIVE_Z = 5


def choices(alias: object) -> tuple[str, ...]:
    """The strings of a ``Literal`` alias, in order (for ``validate_choice`` and ``--help``)."""
    return get_args(alias)
