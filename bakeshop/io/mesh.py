"""Triangle meshes from files: OBJ, STL, PLY, OFF and glTF (.gltf, .glb), through trimesh.

:func:`load_mesh` is the one mesh reader of bakeshop: the normal-map transfer takes its UV sets,
the buoyancy bench welds and closes it (:func:`bakeshop.buoyancy.closed_mesh`). Vertices keep
the file's order; texture coordinates have v up (OBJ, trimesh, OpenGL), so (u, v) lies at
column u W and row (1 - v) H of a W x H map; glTF's v-down coordinates are converted.
"""

from __future__ import annotations

import base64
import binascii
import io
import json
import os
import struct
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np

from bakeshop.errors import ArgumentError, BakeshopError, FormatError, UnsupportedError
from bakeshop.io._files import check_input
from bakeshop.resources import Cost, require

#: extensions :func:`load_mesh` reads.
MESH_EXTENSIONS = (".obj", ".stl", ".ply", ".off", ".gltf", ".glb")
#: glTF accessor component types (numpy dtypes) and components per element of each type.
GLTF_COMPONENT_TYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
#: the largest glTF JSON read, bytes: a .gltf file, or a GLB's JSON chunk.
GLTF_JSON_MAX = 64 << 20
GLTF_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


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


def _gltf_count(item: dict, key: str, what: str, path: Path, limit: int | None = None) -> int:
    """``item[key]``, a byte count or index (below ``limit``) read from a glTF file."""
    value = item.get(key, 0 if key == "byteOffset" else None)
    bound = 1 << 62 if limit is None else limit
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value < bound:
        return value
    wanted = "a count" if limit is None else f"an index below {limit}"
    raise FormatError(f"{what}'s {key} is {value!r}, not {wanted}", path)


def _beside(path: Path, uri: str, what: str) -> Path:
    """The file a relative ``uri`` names in ``path``'s folder or below it; a scheme
    (``file:``, ``http:``), an absolute path or one that leaves the folder is refused."""
    folder = path.parent.resolve()
    file = (folder / unquote(uri)).resolve()
    if urlsplit(uri).scheme or not file.is_relative_to(folder):
        raise FormatError(
            f"{what}'s uri {uri!r} is not a file in the glTF's folder (nothing else is read)", path
        )
    return file


def _gltf_buffers(header: dict, binary: bytes | None, path: Path) -> list[bytes]:
    """Each buffer's bytes, exactly ``byteLength`` of them: from the GLB's binary chunk, a data
    URI, or a regular file in ``path``'s folder or below it (checked, and bounded by memory,
    before it is read)."""
    buffers = []
    for i, spec in enumerate(header.get("buffers", [])):
        what = f"buffer {i}"
        length = _gltf_count(spec, "byteLength", what, path)
        uri = spec.get("uri")
        if uri is None:
            if i != 0 or binary is None:
                raise FormatError(f"{what} has no uri and the file no binary chunk", path)
            blob = binary
        elif not isinstance(uri, str):
            raise FormatError(f"{what}'s uri is not a string", path)
        elif uri.startswith("data:"):
            try:
                blob = base64.b64decode(uri.partition(",")[2], validate=True)
            except binascii.Error as e:
                raise FormatError(f"{what}'s data URI is not base64 ({e})", path) from None
        else:
            file = _beside(path, uri, what)
            if check_input(file).st_size < length:
                raise FormatError(f"{what} ({uri}) is shorter than its {length} bytes", path)
            require(Cost(length, length, f"{what} ({uri}) of {length:,} bytes"), path)
            with open(file, "rb") as f:
                blob = f.read(length)
        if len(blob) < length:
            raise FormatError(f"{what} holds {len(blob)} bytes, not its {length}", path)
        buffers.append(blob[:length])
    return buffers


def _gltf_accessor(header: dict, buffers: list[bytes], index: int) -> np.ndarray:
    """The (count,) values of a SCALAR accessor whose layout :func:`_gltf_check` checked."""
    accessor = header["accessors"][index]
    view = header["bufferViews"][accessor["bufferView"]]
    dtype = np.dtype(GLTF_COMPONENT_TYPES[accessor["componentType"]])
    return np.ndarray(
        (accessor["count"],),
        dtype,
        buffers[view["buffer"]],
        view.get("byteOffset", 0) + accessor.get("byteOffset", 0),
        (view.get("byteStride") or dtype.itemsize,),
    )


def _gltf_check(header: dict, buffers: list[bytes], path: Path) -> None:
    """Refuse a glTF whose numbers point outside its data: each bufferView within its buffer,
    each accessor's ``count`` elements (at their stride) within its bufferView, each
    primitive's accessors existing and its indices below its POSITION count."""
    views = header.get("bufferViews", [])
    for i, view in enumerate(views):
        what = f"bufferView {i}"
        b = _gltf_count(view, "buffer", what, path, len(buffers))
        end = _gltf_count(view, "byteOffset", what, path) + _gltf_count(
            view, "byteLength", what, path
        )
        if end > len(buffers[b]):
            raise FormatError(
                f"{what} ends at byte {end}, past the {len(buffers[b])} of buffer {b}", path
            )
        stride = view.get("byteStride")
        if stride is not None and (_gltf_count(view, "byteStride", what, path) % 4 or stride > 252):
            raise FormatError(f"{what}'s byteStride {stride} is not 4, 8 ... 252", path)
    accessors = header.get("accessors", [])
    for i, accessor in enumerate(accessors):
        what = f"accessor {i}"
        if "bufferView" not in accessor or "sparse" in accessor:
            raise UnsupportedError(
                f"{what} has no bufferView (sparse or compressed data is not read)", path
            )
        view = views[_gltf_count(accessor, "bufferView", what, path, len(views))]
        kind, components = accessor.get("componentType"), accessor.get("type")
        if kind not in GLTF_COMPONENT_TYPES or components not in GLTF_COMPONENTS:
            raise FormatError(f"{what} has componentType {kind!r} and type {components!r}", path)
        element = np.dtype(GLTF_COMPONENT_TYPES[kind]).itemsize * GLTF_COMPONENTS[components]
        count = _gltf_count(accessor, "count", what, path)
        stride = view.get("byteStride") or element
        end = _gltf_count(accessor, "byteOffset", what, path) + (count - 1) * stride + element
        if count and end > view["byteLength"]:
            raise FormatError(
                f"{what}'s {count} elements end at byte {end}, past the {view['byteLength']} of "
                f"bufferView {accessor['bufferView']}",
                path,
            )
    for m, mesh in enumerate(header.get("meshes", [])):
        for p, primitive in enumerate(mesh.get("primitives", [])):
            what = f"mesh {m} primitive {p}"
            attributes = primitive.get("attributes", {})
            for key in attributes:
                _gltf_count(attributes, key, what, path, len(accessors))
            vertices = accessors[_gltf_count(attributes, "POSITION", what, path, len(accessors))]
            if "indices" in primitive:
                index = _gltf_count(primitive, "indices", what, path, len(accessors))
                if accessors[index]["componentType"] not in (5121, 5123, 5125):
                    raise FormatError(f"{what}'s indices are not unsigned integers", path)
                values = _gltf_accessor(header, buffers, index)
                if values.size and int(values.max()) >= vertices["count"]:
                    raise FormatError(
                        f"{what} indexes vertex {int(values.max())}, past its "
                        f"{vertices['count']} vertices",
                        path,
                    )


def _gltf_chunk(f: io.BufferedReader, length: int, what: str, path: Path) -> bytes:
    """The next ``length`` bytes of ``f``, ``what`` of the glTF ``path``, checked against the
    file's size and the memory bound before they are read."""
    left = os.fstat(f.fileno()).st_size - f.tell()
    if length > left:
        raise FormatError(f"{what} of {length:,} bytes runs past the file's end", path)
    require(Cost(length, length, f"{what} of {length:,} bytes"), path)
    return f.read(length)


def _gltf_read(path: Path) -> tuple[dict, bytes | None]:
    """The glTF's JSON (at most :data:`GLTF_JSON_MAX` bytes) and a GLB's binary chunk (None
    for a .gltf), read chunk by chunk."""
    with open(path, "rb") as f:
        if path.suffix.lower() != ".glb":
            length = os.fstat(f.fileno()).st_size
        else:
            head = f.read(20)
            if len(head) < 20 or head[:4] != b"glTF":
                raise FormatError("not a binary glTF file (bad magic bytes)", path)
            length = struct.unpack_from("<I", head, 12)[0]
        if length > GLTF_JSON_MAX:
            raise UnsupportedError(
                f"its JSON is {length:,} bytes, more than the {GLTF_JSON_MAX >> 20} MiB read "
                "from a glTF (keep the buffers in the binary chunk or .bin files, not in data "
                "URIs)",
                path,
            )
        header = json.loads(_gltf_chunk(f, length, "the JSON", path))
        if path.suffix.lower() != ".glb" or len(tail := f.read(8)) < 8:
            return header, None
        length = struct.unpack_from("<I", tail, 0)[0]
        return header, _gltf_chunk(f, length, "the binary chunk", path)


def _gltf_geometry(path: Path) -> tuple[bytes, dict[str, bytes]]:
    """The glTF's JSON reduced to its geometry, checked by :func:`_gltf_check`, with each
    buffer named by its index and TEXCOORD_n renamed to _TEXCOORD_n (trimesh keeps those as
    plain vertex attributes; its own UV handling keeps only TEXCOORD_0 and only on primitives
    with a material); and the buffers by name. Materials and images are dropped, so nothing but
    the checked buffers is ever read."""
    try:
        header, binary = _gltf_read(path)
        buffers = _gltf_buffers(header, binary, path)
        _gltf_check(header, buffers, path)
    except (ValueError, struct.error, AttributeError, TypeError, KeyError) as e:
        if isinstance(e, BakeshopError):
            raise
        raise FormatError(f"not a glTF file ({e})", path) from None
    for key in ("images", "textures", "samplers", "materials"):
        header.pop(key, None)
    for mesh in header.get("meshes", []):
        for prim in mesh.get("primitives", []):
            prim.pop("material", None)
            attrs = prim["attributes"]
            for key in [k for k in attrs if k.startswith("TEXCOORD_")]:
                attrs["_" + key] = attrs.pop(key)
    named = {}
    for i, spec in enumerate(header.get("buffers", [])):
        spec["uri"] = f"buffer{i}.bin"
        named[spec["uri"]] = buffers[i]
    return json.dumps(header).encode(), named


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
            header, buffers = _gltf_geometry(path)
            resolver = trimesh.resolvers.ZipResolver(buffers)
            mesh = trimesh.load(
                io.BytesIO(header), file_type="gltf", force="mesh", process=False, resolver=resolver
            )
        else:
            mesh = trimesh.load(path, force="mesh", process=False, maintain_order=True)
    except BakeshopError:
        raise
    except Exception as e:  # trimesh raises many types for corrupt files
        raise FormatError(f"cannot read the mesh: {e}", path) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise FormatError("the file holds no triangles", path)
    faces = np.asarray(mesh.faces)
    if faces.min() < 0 or faces.max() >= len(mesh.vertices):  # before trimesh indexes with them
        raise FormatError(f"a face indexes vertex {faces.max()} of {len(mesh.vertices)}", path)
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
