"""Triangle meshes from files: OBJ, STL, PLY, OFF and glTF (.gltf, .glb), through trimesh.

:func:`load_mesh` is the one mesh reader of bakeshop: the normal-map transfer takes its UV sets,
the buoyancy bench welds and closes it (:func:`bakeshop.buoyancy.closed_mesh`). Vertices keep
the file's order; texture coordinates have v up (OBJ, trimesh, OpenGL), so (u, v) lies at
column u W and row (1 - v) H of a W x H map; glTF's v-down coordinates are converted.
"""

from __future__ import annotations

import io
import json
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bakeshop.errors import ArgumentError, FormatError
from bakeshop.io._files import check_input

#: extensions :func:`load_mesh` reads.
MESH_EXTENSIONS = (".obj", ".stl", ".ply", ".off", ".gltf", ".glb")


@dataclass
class Mesh:
    """A triangle mesh with its vertex attributes.

    Attributes
    ----------
    positions : (V, 3) float64
        Object-space positions (metres where a physical size matters).
    faces : (F, 3) int64
        Counter-clockwise triangles (vertex indices).
    normals : (V, 3) float64, optional
        Unit vertex normals as an engine shades with them (the file's, else angle-weighted).
    uv : (V, 2) float64, optional
        The first UV set, v up.
    uv2 : (V, 2) float64, optional
        A second UV set (glTF's TEXCOORD_1), v up.
    """

    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None = None
    uv: np.ndarray | None = None
    uv2: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.positions = np.asarray(self.positions, np.float64)
        self.faces = np.asarray(self.faces, np.int64)
        v = len(self.positions)
        if self.positions.ndim != 2 or self.positions.shape[1] != 3:
            raise ArgumentError(f"positions must be (V, 3); got {self.positions.shape}")
        if self.faces.ndim != 2 or self.faces.shape[1] != 3 or len(self.faces) == 0:
            raise ArgumentError(f"faces must be (F, 3) with F > 0; got {self.faces.shape}")
        if self.faces.min() < 0 or self.faces.max() >= v:
            raise ArgumentError("faces index vertices that do not exist")
        if not np.isfinite(self.positions).all():
            raise ArgumentError("positions contain NaN or infinite values")
        if self.normals is None:
            self.normals = angle_weighted_normals(self.positions, self.faces)
        for name in ("normals", "uv", "uv2"):
            a = getattr(self, name)
            if a is None:
                continue
            a = np.asarray(a, np.float64)
            width = 3 if name == "normals" else 2
            if a.shape != (v, width):
                raise ArgumentError(f"{name} must be ({v}, {width}); got {a.shape}")
            if not np.isfinite(a).all():
                raise ArgumentError(f"{name} contain NaN or infinite values")
            setattr(self, name, a)


def angle_weighted_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Vertex normals: the sum of the incident faces' unit normals weighted by the corner's
    angle (Thürmer and Wüthrich 1998), normalised; (0, 0, 1) for an isolated vertex."""
    p = positions[faces]
    normals = np.zeros_like(positions)
    face_n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    face_n /= np.maximum(np.linalg.norm(face_n, axis=1, keepdims=True), 1e-300)
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        cos = np.einsum("ij,ij->i", a, b) / np.maximum(
            np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300
        )
        np.add.at(normals, faces[:, k], face_n * np.arccos(np.clip(cos, -1, 1))[:, None])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return np.where(length > 0, normals / np.where(length > 0, length, 1), (0.0, 0.0, 1.0))


def _gltf_with_named_texcoords(path: Path) -> tuple[bytes, str]:
    """The glTF's JSON (and GLB binary chunk) with TEXCOORD_n renamed to _TEXCOORD_n, which
    trimesh keeps as plain vertex attributes (its own UV handling keeps only TEXCOORD_0 and
    only on primitives with a material)."""
    data = path.read_bytes()
    binary = None
    try:
        if path.suffix.lower() == ".glb":
            if len(data) < 20 or data[:4] != b"glTF":
                raise FormatError("not a binary glTF file (bad magic bytes)", path)
            length = struct.unpack_from("<I", data, 12)[0]
            header = json.loads(data[20 : 20 + length])
            rest = data[20 + length :]
            if len(rest) >= 8:
                size = struct.unpack_from("<I", rest, 0)[0]
                binary = rest[8 : 8 + size]
        else:
            header = json.loads(data)
    except (ValueError, struct.error) as e:
        raise FormatError(f"not a glTF file ({e})", path) from None
    for mesh in header.get("meshes", []):
        for prim in mesh.get("primitives", []):
            attrs = prim.get("attributes", {})
            for key in [k for k in attrs if k.startswith("TEXCOORD_")]:
                attrs["_" + key] = attrs.pop(key)
    payload = json.dumps(header).encode()
    if binary is not None:
        payload += b" " * (-len(payload) % 4)
        binary += b"\0" * (-len(binary) % 4)
        chunks = struct.pack("<I4s", len(payload), b"JSON") + payload
        chunks += struct.pack("<I4s", len(binary), b"BIN\0") + binary
        return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks, "glb"
    return payload, "gltf"


def load_mesh(path: str | os.PathLike) -> Mesh:
    """Read a triangle mesh with its normals and UV sets.

    All meshes of a scene are merged with their node transforms applied. The first UV set is
    ``vt`` (OBJ) or ``TEXCOORD_0``; ``uv2`` is glTF's ``TEXCOORD_1`` when present. Normals are
    the file's (``vn``, ``NORMAL``), else trimesh's vertex normals. Vertices are not welded:
    a vertex split at a UV or normal seam stays split, as the engine draws it.

    Parameters
    ----------
    path : path-like
        A .obj, .stl, .ply, .off, .gltf or .glb file.

    Returns
    -------
    Mesh

    Raises
    ------
    FormatError
        An unreadable file, or one with no triangles.
    """
    import trimesh

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in MESH_EXTENSIONS:
        raise FormatError(
            f"unsupported mesh extension {ext!r}; use one of {', '.join(MESH_EXTENSIONS)}", path
        )
    check_input(path)
    gltf = ext in (".gltf", ".glb")
    try:
        if gltf:
            data, kind = _gltf_with_named_texcoords(path)
            resolver = trimesh.resolvers.FilePathResolver(str(path))
            mesh = trimesh.load(
                io.BytesIO(data), file_type=kind, force="mesh", process=False, resolver=resolver
            )
        else:
            mesh = trimesh.load(path, force="mesh", process=False, maintain_order=True)
    except FormatError:
        raise
    except Exception as e:  # trimesh raises many types for corrupt files
        raise FormatError(f"cannot read the mesh: {e}", path) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise FormatError("the file holds no triangles", path)
    if gltf:
        attrs = mesh.vertex_attributes
        uv, uv2 = (attrs.get(f"_TEXCOORD_{k}") for k in (0, 1))
        uv = None if uv is None else np.asarray(uv, np.float64) * (1, -1) + (0, 1)
        uv2 = None if uv2 is None else np.asarray(uv2, np.float64) * (1, -1) + (0, 1)
    else:
        uv, uv2 = getattr(mesh.visual, "uv", None), None
    if uv is not None and len(uv) != len(mesh.vertices):
        uv = None
    try:
        return Mesh(mesh.vertices, mesh.faces, np.asarray(mesh.vertex_normals), uv, uv2)
    except ArgumentError as e:
        raise FormatError(e.reason, path) from None
