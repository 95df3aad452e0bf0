"""The cube map: OpenGL's face table, the engine conventions, and the cross and strip pictures.

Internally a cube map is ``(6, S, S, C)`` in OpenGL face order +X, -X, +Y, -Y, +Z, -Z, each face
oriented as OpenGL's cube lookup reads it (DESIGN.md). Face ``f`` at face coordinates
``(sc, tc)`` in [-1, 1] looks along ``d = N_f + sc * U_f + tc * V_f`` (:data:`FACE_BASES`);
texel ``(i, j)`` of an ``S x S`` face has ``sc = 2 (i + 0.5) / S - 1``, ``tc = 2 (j + 0.5) / S - 1``
(row 0 is ``tc = -1``).

Engine conventions (what a cube exported for an engine holds, face ``i`` uploaded to target
``GL_TEXTURE_CUBE_MAP_POSITIVE_X + i`` or array layer ``i``):

- ``opengl``: the internal cube. OpenGL samples it with world-space vectors of the right-handed
  +Y-up frame and sees the world unmirrored.
- ``vulkan``: the same faces. Vulkan's cube face selection table (Vulkan spec, "Cube Map Face
  Selection and Transformations") is OpenGL's, and image row 0 is ``t = 0`` in both APIs; the
  flipped clip-space y of Vulkan concerns rasterisation, not texture lookups.
- ``directx``: Direct3D uses the same face table but its world is left-handed with +Z forward, so
  its sampling vector for our direction ``(x, y, z)`` is ``(x, y, -z)``. Face ``F`` of the
  exported set therefore holds OpenGL's face ``F`` of the z-mirrored world: the +/-X and +/-Y
  faces are mirrored (left-right, resp. up-down) and +Z and -Z swap, each mirrored left-right
  (:data:`DIRECTX_FACES`). This left-handed face set is also what HDRShop, CubeMapGen and cmft
  draw in their crosses and strips, which is why the crosses below are made of it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice

#: face names in OpenGL order, as file-name suffixes (the default) and in short form.
FACE_NAMES = ("posx", "negx", "posy", "negy", "posz", "negz")
FACE_NAMES_SHORT = ("px", "nx", "py", "ny", "pz", "nz")
#: face labels as printed in documentation and pictures.
FACE_LABELS = ("+X", "-X", "+Y", "-Y", "+Z", "-Z")

#: (N, U, V) per face: the direction at face coordinates (sc, tc) is N + sc*U + tc*V.
#: This is the OpenGL table of DESIGN.md (for example +X: sc = -z, tc = -y).
FACE_BASES = np.array(
    [
        [[1, 0, 0], [0, 0, -1], [0, -1, 0]],
        [[-1, 0, 0], [0, 0, 1], [0, -1, 0]],
        [[0, 1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, -1]],
        [[0, 0, 1], [1, 0, 0], [0, -1, 0]],
        [[0, 0, -1], [-1, 0, 0], [0, -1, 0]],
    ],
    dtype=np.float64,
)

#: (N, U, V) per face of OpenEXR's cube environment (``ImfEnvmap.h``, ``envmap = cube``), U to
#: the right of the stored face and V down it: each face is the world seen from inside the cube,
#: unmirrored in our right-handed frame (+X: +Y up, +Z right; +Y: +Z up, +X right; -Y: -Z up),
#: which is OpenGL's face mirrored left-right (+/-X, +/-Z) or up-down (+/-Y), in the same order.
#: Unlike OpenGL's, its face coordinates reach +-1 at the first and last texel *centres*.
OPENEXR_FACE_BASES = np.array(
    [
        [[1, 0, 0], [0, 0, 1], [0, -1, 0]],
        [[-1, 0, 0], [0, 0, -1], [0, -1, 0]],
        [[0, 1, 0], [1, 0, 0], [0, 0, -1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, 0, 1], [-1, 0, 0], [0, -1, 0]],
        [[0, 0, -1], [1, 0, 0], [0, -1, 0]],
    ],
    dtype=np.float64,
)

#: directx face F = internal face g mirrored: F -> (g, flip left-right, flip up-down).
DIRECTX_FACES = (
    (0, True, False),
    (1, True, False),
    (2, False, True),
    (3, False, True),
    (5, True, False),
    (4, True, False),
)

CONVENTIONS = ("opengl", "vulkan", "directx")


def _transform(face: np.ndarray, flip_x: bool, flip_y: bool, rot180: bool = False) -> np.ndarray:
    fx, fy = flip_x ^ rot180, flip_y ^ rot180
    if fx:
        face = face[:, ::-1]
    if fy:
        face = face[::-1]
    return face


def cube_to_faces(cube: ArrayLike, *, convention: str = "opengl") -> np.ndarray:
    """The six faces an engine of ``convention`` loads, from an internal cube.

    Parameters
    ----------
    cube : (6, S, S) or (6, S, S, C) array
        Internal cube map (OpenGL order and orientation).
    convention : {"opengl", "vulkan", "directx"}
        See the module notes: opengl and vulkan are the internal cube, directx is the face set
        of the z-mirrored (left-handed) world.

    Returns
    -------
    (6, S, S[, C]) array
        Face ``i`` goes to ``GL_TEXTURE_CUBE_MAP_POSITIVE_X + i`` (Direct3D:
        ``D3D11_TEXTURECUBE_FACE_POSITIVE_X + i``). A new array for directx, ``cube`` otherwise.
    """
    validate_choice(convention, CONVENTIONS, "cube convention")
    cube = np.asarray(cube)
    if cube.ndim not in (3, 4) or cube.shape[0] != 6 or cube.shape[1] != cube.shape[2]:
        raise ArgumentError(f"a cube map must be (6, S, S) or (6, S, S, C); got {cube.shape}")
    if convention != "directx":
        return cube
    return np.stack([_transform(cube[g], fx, fy) for g, fx, fy in DIRECTX_FACES])


def faces_to_cube(faces: ArrayLike, *, convention: str = "opengl") -> np.ndarray:
    """Inverse of :func:`cube_to_faces`: the internal cube from an engine's six faces.

    The directx transform is an involution (each face is mirrored and +Z/-Z swap), so this is
    the same operation; it is named separately so that code says which way it converts.
    """
    return cube_to_faces(faces, convention=convention)


# --- crosses and strips ---------------------------------------------------------------------

#: view name -> (columns, rows, {slot face: (column, row, rotated 180 degrees)}).
#: Slot F shows face F of the directx (left-handed) set, as HDRShop and cmft draw them.
VIEWS = {
    "cross-vertical": (
        3,
        4,
        {2: (1, 0, False), 1: (0, 1, False), 4: (1, 1, False), 0: (2, 1, False),
         3: (1, 2, False), 5: (1, 3, True)},
    ),
    "cross-horizontal": (
        4,
        3,
        {2: (1, 0, False), 1: (0, 1, False), 4: (1, 1, False), 0: (2, 1, False),
         5: (3, 1, False), 3: (1, 2, False)},
    ),
    "strip-horizontal": (6, 1, {f: (f, 0, False) for f in range(6)}),
    "strip-vertical": (1, 6, {f: (0, f, False) for f in range(6)}),
}  # fmt: skip


def view_slots(view: str) -> list[tuple[int, int, bool, bool]]:
    """Per internal face g: (column, row, flip_x, flip_y) of where and how ``view`` shows it."""
    _, _, slots = VIEWS[view]
    out: dict[int, tuple[int, int, bool, bool]] = {}
    for label, (col, row, rot) in slots.items():
        g, fx, fy = DIRECTX_FACES[label]
        out[g] = (col, row, fx ^ rot, fy ^ rot)
    return [out[g] for g in range(6)]


def cube_to_view(cube: ArrayLike, view: str, *, fill: float = 0.0) -> np.ndarray:
    """Arrange an internal cube ``(6, S, S, ...)`` into the picture ``view`` (unused: ``fill``)."""
    cube = np.asarray(cube)
    cols, rows, _ = VIEWS[view]
    s = cube.shape[1]
    out = np.full((rows * s, cols * s) + cube.shape[3:], fill, dtype=cube.dtype)
    for g, (col, row, fx, fy) in enumerate(view_slots(view)):
        out[row * s : (row + 1) * s, col * s : (col + 1) * s] = _transform(cube[g], fx, fy)
    return out


def view_to_cube(image: ArrayLike, view: str) -> np.ndarray:
    """The internal cube ``(6, S, S, ...)`` shown in the picture ``image`` of layout ``view``."""
    image = np.asarray(image)
    cols, rows, _ = VIEWS[view]
    s = image.shape[1] // cols
    faces = []
    for col, row, fx, fy in view_slots(view):
        faces.append(_transform(image[row * s : (row + 1) * s, col * s : (col + 1) * s], fx, fy))
    return np.stack(faces)
