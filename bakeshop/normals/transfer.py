"""Transfer ("unwrap") a tileable detail normal map into a mesh's macro UV layout.

Given the low-poly mesh with its UV set (the layout of the macro normal map) and a detail map
applied through a second UV set or a planar, box or triplanar projection in object space, this
bakes the detail into the macro layout, so it can then be blended with the macro map texel by
texel (:mod:`bakeshop.normals.blend`):

1. **Tangents**: MikkTSpace-compatible per-corner tangents for each UV set
   (:func:`corner_tangents`), so the baked map decodes correctly in engines that reconstruct
   the tangent frame with MikkTSpace (Unreal, Unity, Blender, glTF viewers).
2. **Rasterise** each triangle in macro UV space (:func:`rasterize_uv`): every texel centre
   inside a triangle gets the triangle and its barycentric coordinates.
3. **Detail coordinates and sample**: interpolate the second UV set or project the interpolated
   object-space position; sample the detail bilinearly with wrap-around from its mip chain at
   the level of the triangle's footprint (:mod:`bakeshop.normals.tiling`).
4. **Rotate** the detail normal into the world: through the detail UV set's MikkTSpace frame
   (uv2), or as the surface gradient of the projected height (planar, box, triplanar;
   Mikkelsen 2020), then into the macro tangent frame with the exact inverse of the frame an
   engine reconstructs (:func:`world_to_tangent`).
5. **Dilate** UV islands (:func:`dilate`) so mip levels do not bleed background into seams.

Texture coordinates have v up (OBJ, trimesh, OpenGL): (u, v) lies at column u W and row
(1 - v) H of a W x H map (:func:`bakeshop.io.load_mesh` converts glTF's v-down ones).

References
----------
M. S. Mikkelsen, "Simulation of wrinkled surfaces revisited", MSc thesis, University of
Copenhagen, 2008, and the reference implementation ``mikktspace.c``
(https://github.com/mmikk/MikkTSpace).
M. S. Mikkelsen, "Surface Gradient-Based Bump Mapping Framework", JCGT 9(3), 2020,
https://jcgt.org/published/0009/03/04/.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import ArgumentError, validate_choice
from bakeshop.io.mesh import Mesh
from bakeshop.normals import _native
from bakeshop.normals.encoding import normalize
from bakeshop.normals.tiling import as_pair, mip_chain

PROJECTIONS = ("uv2", "planar", "box", "triplanar")
AXES = ("x", "y", "z")

#: the (s, t) axes of the planar projection along each object axis, seen from that axis' +
#: side with the other axes right and up: along z (x, y); along x (-z, y); along y (x, -z).
PROJECTION_AXES = {
    "x": (np.array([0.0, 0.0, -1.0]), np.array([0.0, 1.0, 0.0])),
    "y": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0])),
    "z": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])),
}

__all__ = [
    "PROJECTIONS",
    "corner_tangents",
    "rasterize_uv",
    "world_to_tangent",
    "dilate",
    "transfer_detail",
]


# --- tangents ------------------------------------------------------------------------------


def corner_tangents(
    positions: np.ndarray, normals: np.ndarray, uv: np.ndarray, faces: np.ndarray
) -> np.ndarray:
    """MikkTSpace tangents and bitangent signs at the corners of each triangle.

    Follows ``mikktspace.c`` in the common case: each triangle's tangent is the direction of
    increasing u, dP/du = (t31_v d1 - t21_v d2) / (2 * signed UV area) with d1, d2 its edges;
    at each corner it is projected onto the plane of the vertex normal (Gram-Schmidt),
    normalised, weighted by the corner's angle (between its two edges, themselves projected
    onto that plane) and summed over the triangles that share the vertex, where "vertex"
    means the same position, normal and UV, and triangles of opposite UV orientation
    (mirrored islands) are kept apart; the sum is normalised. The sign is +1
    for triangles whose UVs keep their orientation, -1 for mirrored ones; an engine then
    builds the bitangent B = sign * cross(N, T).

    Differences from ``mikktspace.c``: triangles with a degenerate UV or position triangle
    contribute nothing (MikkTSpace gives them the tangent of a neighbour sharing the vertex; a
    corner touched only by degenerate triangles gets the projection of +X, or +Y, here), and
    quads are taken as the two triangles the mesh already holds (MikkTSpace may pick its own
    diagonal for an untriangulated quad). On meshes without such triangles the results agree.

    Parameters
    ----------
    positions, normals : (V, 3) float arrays
    uv : (V, 2) float array
    faces : (F, 3) int array

    Returns
    -------
    (F, 3, 4) float64: unit tangent (x, y, z) and sign w at each corner.
    """
    p = positions[faces]
    t = uv[faces]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    t21, t31 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    area = t21[:, 0] * t31[:, 1] - t21[:, 1] * t31[:, 0]
    sign = np.where(area > 0, 1.0, -1.0)
    vos = t31[:, 1, None] * d1 - t21[:, 1, None] * d2
    length = np.linalg.norm(vos, axis=1)
    ok = (area != 0) & (length > 0)
    vos = np.where(ok[:, None], vos * (sign / np.where(ok, length, 1))[:, None], 0.0)
    # "vertex" = same position, normal and uv; slot = vertex x orientation
    key = np.concatenate([positions, normals, uv], axis=1)
    _, vertex = np.unique(key, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1)
    slots = vertex[faces] * 2 + (sign > 0)[:, None]
    acc = np.zeros((2 * (vertex.max() + 1), 3))
    n = normals[faces]

    def onto_plane(
        v: np.ndarray, normal: np.ndarray
    ) -> np.ndarray:  # unit projection onto the plane of ``normal``, 0 if none
        v = v - np.einsum("ij,ij->i", v, normal)[:, None] * normal
        length = np.linalg.norm(v, axis=1, keepdims=True)
        return np.where(length > 0, v / np.where(length > 0, length, 1), 0.0)

    for k in range(3):
        # the corner's angle between its edges, both projected onto the normal's plane
        a = onto_plane(p[:, (k + 1) % 3] - p[:, k], n[:, k])
        b = onto_plane(p[:, (k + 2) % 3] - p[:, k], n[:, k])
        angle = np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1, 1))
        angle = np.where((a != 0).any(axis=1) & (b != 0).any(axis=1), angle, 0.0)
        np.add.at(acc, slots[:, k], onto_plane(vos, n[:, k]) * angle[:, None])
    tangent = acc[slots]  # (F, 3, 3)
    tl = np.linalg.norm(tangent, axis=2, keepdims=True)
    missing = tl[..., 0] <= 1e-12
    if missing.any():
        nn = n[missing]
        fallback = np.where(np.abs(nn[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        fallback -= np.einsum("ij,ij->i", fallback, nn)[:, None] * nn
        tangent[missing] = fallback
        tl = np.linalg.norm(tangent, axis=2, keepdims=True)
    out = np.empty(faces.shape + (4,))
    out[..., :3] = tangent / tl
    out[..., 3] = sign[:, None]
    return out


# --- rasterisation and dilation -----------------------------------------------------------


def rasterize_uv(
    uv: np.ndarray, faces: np.ndarray, shape: tuple[int, int]
) -> tuple[np.ndarray, np.ndarray]:
    """Which triangle covers each texel centre of a UV layout, and where.

    Parameters
    ----------
    uv : (V, 2) float array
        Texture coordinates, v up; (u, v) lies at column u W, row (1 - v) H.
    faces : (F, 3) int array
    shape : (H, W)

    Returns
    -------
    face : (H, W) int32
        Index of the triangle whose closed interior holds the texel centre, -1 where none
        does. Where UV triangles overlap (stacked or mirrored islands) the later one wins.
    bary : (H, W, 3) float64
        Barycentric coordinates of the texel centre in that triangle (0 where uncovered).
    """
    height, width = (int(s) for s in shape)
    tex = np.empty((len(uv), 2))
    tex[:, 0] = uv[:, 0] * width
    tex[:, 1] = (1 - uv[:, 1]) * height
    face = np.full((height, width), -1, np.int32)
    bary = np.zeros((height, width, 3))
    _native.rasterize(tex, np.ascontiguousarray(faces, np.int64), face, bary)
    return face, bary


def dilate(
    image: ArrayLike,
    covered: ArrayLike,
    *,
    pixels: int | None = 16,
    background: ArrayLike = (0.0, 0.0, 1.0),
) -> np.ndarray:
    """Extend UV islands over the empty texels around them (edge padding).

    The islands grow ring by ring, ``pixels`` rings at most: each texel of a new ring copies
    a neighbour (of 8) from the ring before, as bakers' edge padding does; texels farther than
    ``pixels`` steps (chessboard distance) take ``background``. Mip levels then average
    island texels with copies of their own borders instead of the background, so seams do
    not bleed. ``pixels=None`` fills every texel.

    Parameters
    ----------
    image : (H, W, C) array
    covered : (H, W) bool array
    pixels : int or None
    background : sequence of C floats

    Returns
    -------
    (H, W, C) array, a new array of image's dtype.
    """
    out = np.array(image)
    _pad(out, covered, pixels, background)
    return out


def _pad(out: np.ndarray, covered: ArrayLike, pixels: int | None, background: ArrayLike) -> None:
    """:func:`dilate` in place."""
    if pixels is not None and pixels < 0:
        raise ArgumentError(f"padding must be >= 0 texels; got {pixels}")
    filled = np.array(covered, dtype=bool, order="C")
    if out.ndim != 3 or out.shape[:2] != filled.shape:
        raise ArgumentError(f"image {out.shape} and coverage {filled.shape} do not match")
    # the kernel copies whole texels: their bytes, whatever the dtype (src/normals/transfer.hpp)
    texels = np.ascontiguousarray(out).reshape(out.shape[0], out.shape[1], -1)
    _native.dilate(texels.view(np.uint8), filled, -1 if pixels is None else int(pixels))
    if texels is not out:
        out[...] = texels
    out[~filled] = background


# --- frames and the per-texel kernel ------------------------------------------------------


def world_to_tangent(
    world: ArrayLike, tangent: ArrayLike, sign: ArrayLike, normal: ArrayLike
) -> np.ndarray:
    """Tangent-space normal m that an engine turns back into the world normal ``world``.

    MikkTSpace's pixel shader reconstructs normalize(m_x T + m_y B + m_z N) with the
    interpolated, unnormalised T and N and B = sign * cross(N, T); this is its exact inverse,
    m = normalize([T B N]^-1 world), computed with the cofactors (B x N, N x T, T x B).

    Parameters
    ----------
    world, tangent, normal : (N, 3) float arrays
    sign : (N,) float array of +-1

    Returns
    -------
    (N, 3) float64 unit normals in the tangent frame; (0, 0, 1) where the frame is degenerate.
    """
    w, t, s, n = (np.ascontiguousarray(a, np.float64) for a in (world, tangent, sign, normal))
    out = np.empty((len(w), 3))
    _native.world_to_tangent(w, t, s, n, out)
    return out


def _face_lod(detail_texels: np.ndarray, macro_texels: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """log2 of each face's footprint: detail texels per macro texel (GPU-style max axis).

    ``detail_texels`` (F, 3, 2) are the detail texel coordinates at the face's corners.
    """
    d = detail_texels
    m = macro_texels[faces]
    dm = np.stack([m[:, 1] - m[:, 0], m[:, 2] - m[:, 0]], axis=2)  # (F, 2, 2) columns
    dd = np.stack([d[:, 1] - d[:, 0], d[:, 2] - d[:, 0]], axis=2)
    det = dm[:, 0, 0] * dm[:, 1, 1] - dm[:, 0, 1] * dm[:, 1, 0]
    ok = np.abs(det) > 1e-300
    inv = (
        np.stack(
            [np.stack([dm[:, 1, 1], -dm[:, 0, 1]], 1), np.stack([-dm[:, 1, 0], dm[:, 0, 0]], 1)], 1
        )
        / np.where(ok, det, 1.0)[:, None, None]
    )
    jac = dd @ inv  # detail texels per macro texel
    footprint = np.maximum(
        np.linalg.norm(jac[:, :, 0], axis=1), np.linalg.norm(jac[:, :, 1], axis=1)
    )
    return np.where(ok, np.log2(np.maximum(footprint, 1.0)), 0.0)


def transfer_detail(
    mesh: Mesh,
    detail: ArrayLike,
    shape: tuple[int, int],
    *,
    projection: str = "uv2",
    tile: float | tuple[float, float] = 1.0,
    offset: tuple[float, float] = (0.0, 0.0),
    rotation: float = 0.0,
    axis: str = "z",
    sharpness: float = 4.0,
    strength: float = 1.0,
    padding: int | None = 16,
) -> tuple[np.ndarray, np.ndarray]:
    """Bake a tileable detail normal map into the mesh's macro UV layout (module notes).

    Parameters
    ----------
    mesh : bakeshop.io.mesh.Mesh
        The low-poly mesh; ``mesh.uv`` is the macro layout.
    detail : (h, w, 3) float array
        Unit normals of one tile of the detail (OpenGL tangent frame).
    shape : (H, W)
        Size of the output (the macro map's).
    projection : {"uv2", "planar", "box", "triplanar"}
        How the detail is applied: through ``mesh.uv2``; projected along ``axis``; per triangle
        along the object axis closest to its normal; or blended over the three axes with
        weights |N_i|^sharpness.
    tile : float or (float, float)
        Repetitions of the detail per unit of uv2, or per object-space unit for projections.
    offset, rotation
        Pattern offset (tiles) and counter-clockwise rotation (degrees), as in
        :func:`bakeshop.normals.tiling.place_detail`.
    axis : {"x", "y", "z"}
        Projection axis of ``"planar"`` (see :data:`PROJECTION_AXES`).
    sharpness : float
        Exponent of the triplanar weights.
    strength : float
        Height scale of the detail: its normals become normalize(s x, s y, z).
    padding : int or None
        Texels of dilation around UV islands (None: fill the whole map).

    Returns
    -------
    normals : (H, W, 3) float32
        The detail in the macro map's tangent frame (MikkTSpace), flat (0, 0, 1) far from
        islands. Blend it onto the macro map with ``tile=1``.
    covered : (H, W) bool
        Texels whose centre lies in a triangle.

    Notes
    -----
    For uv2, the world normal is normalize(d_x T2 + d_y B2 + d_z N) with the MikkTSpace frame
    of the second UV set, as a shader sampling the detail through uv2 computes it. For the
    projections the detail is a height field h(s, t) over the projection plane, displaced
    along the surface normal; its surface gradient is the projection of the volume gradient
    g = h_s e_s + h_t e_t onto the tangent plane, and the world normal is normalize(N - g +
    (g . N) N) (Mikkelsen 2020, section on triplanar projection); triplanar sums the three
    surface gradients with the weights.
    """
    validate_choice(projection, PROJECTIONS, "projection")
    validate_choice(axis, AXES, "projection axis")
    if mesh.uv is None:
        raise ArgumentError("the mesh has no texture coordinates (a macro UV set is needed)")
    if projection == "uv2" and mesh.uv2 is None:
        raise ArgumentError(
            "the mesh has no second UV set (glTF TEXCOORD_1); use a planar, box or "
            "triplanar projection"
        )
    d = np.asarray(detail)
    if d.ndim != 3 or d.shape[2] != 3:
        raise ArgumentError(f"a detail normal map must be (h, w, 3); got shape {d.shape}")
    height, width = (int(s) for s in shape)
    if height < 1 or width < 1 or height * width > 1 << 28:
        raise ArgumentError(f"invalid output size {width}x{height}")
    if not math.isfinite(strength):
        raise ArgumentError(f"strength must be finite; got {strength}")
    if strength != 1:
        d = normalize(d * np.array([strength, strength, 1.0], np.float32))
    if not 0 <= sharpness <= 64:
        raise ArgumentError(f"triplanar sharpness must be in [0, 64]; got {sharpness}")
    tu, tv = as_pair(tile, "tile")
    ou, ov = as_pair(offset, "offset")
    if tu == 0 or tv == 0 or not math.isfinite(rotation):
        raise ArgumentError("tile must be non-zero and rotation finite")
    chain = mip_chain(d)
    th = math.radians(rotation)
    place = np.array(
        [tu, tv, ou, ov, math.cos(th), math.sin(th), math.copysign(1, tu), math.copysign(1, tv)]
    )
    faces = mesh.faces
    assert mesh.normals is not None  # Mesh computes the normals a file lacks
    with progress.step("tangents"):
        frame = corner_tangents(mesh.positions, mesh.normals, mesh.uv, faces)
        frame2 = frame
        if projection == "uv2":
            assert mesh.uv2 is not None  # checked on entry
            frame2 = corner_tangents(mesh.positions, mesh.normals, mesh.uv2, faces)
    with progress.step("rasterising"):
        face_map, bary = rasterize_uv(mesh.uv, faces, (height, width))
    covered = face_map >= 0
    texels = np.flatnonzero(covered)

    # per-face level of detail from the Jacobian of detail texels w.r.t. macro texels
    macro_texels = np.stack([mesh.uv[:, 0] * width, (1 - mesh.uv[:, 1]) * height], axis=1)
    h0, w0 = (int(v) for v in chain.shapes[0])

    def face_lods(st: np.ndarray) -> np.ndarray:  # (F, 3, 2) pattern coordinates at the corners
        a, b = st[..., 0] * tu, st[..., 1] * tv
        qu = place[4] * a + place[5] * b
        qv = -place[5] * a + place[4] * b
        return _face_lod(np.stack([qu * w0, -qv * h0], axis=-1), macro_texels, faces)

    axes = np.array([PROJECTION_AXES[a] for a in AXES])  # (3, 2, 3): e_s, e_t per axis
    corners = mesh.positions[faces]
    if projection == "uv2":
        assert mesh.uv2 is not None  # checked on entry
        lod = face_lods(mesh.uv2[faces])[:, None]
    else:
        lod = np.stack([face_lods(corners @ axes[k].T) for k in range(3)], axis=1)
    face_normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    box_axis = np.argmax(np.abs(face_normal), axis=1)
    out = np.zeros((height * width, 3), np.float32)
    out[:, 2] = 1
    uv2 = mesh.uv2 if mesh.uv2 is not None else mesh.uv
    with progress.step("transferring"):
        _native.shade(  # the per-texel kernel: src/normals/transfer.hpp
            texels.astype(np.int64, copy=False),
            face_map.reshape(-1),
            bary.reshape(-1, 3),
            faces,
            mesh.normals,
            mesh.positions,
            uv2,
            frame,
            frame2,
            chain.texels,
            chain.offsets,
            chain.shapes,
            np.ascontiguousarray(lod),
            box_axis,
            PROJECTIONS.index(projection),
            AXES.index(axis),
            float(sharpness),
            place,
            axes,
            out,
        )
    normals = out.reshape(height, width, 3)
    _pad(normals, covered, padding, (0.0, 0.0, 1.0))
    return normals, covered
