"""Transfer into a mesh's UVs: MikkTSpace tangents, rasteriser, frames, and analytic meshes."""

import base64
import json
import os
import re
import struct

import numpy as np
import pytest
from matplotlib.path import Path as PolyPath

from bakeshop.cli.main import main
from bakeshop.errors import ArgumentError, BakeshopError, FormatError
from bakeshop.io import load_mesh, write_image
from bakeshop.io.mesh import Mesh
from bakeshop.normals.tiling import place_detail
from bakeshop.normals.transfer import (
    corner_tangents,
    dilate,
    rasterize_uv,
    transfer_detail,
    world_to_tangent,
)
from tests import tolerances as tol
from tests.normals.test_tiling import normals_from_gradient, wave_height


def plane(uv2=None):
    p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    n = np.tile([0.0, 0.0, 1.0], (4, 1))
    return Mesh(p, [[0, 1, 2], [0, 2, 3]], n, p[:, :2], uv2)


def cylinder(segments=96, radius=0.3, height=1.0, uv2_scale=None):
    """Open cylinder around +Y, seam at phi = 0 facing +Z; u = phi / 2 pi, v = y / height."""
    j = np.arange(segments + 1)
    phi = 2 * np.pi * j / segments
    ring = np.stack([radius * np.sin(phi), np.zeros_like(phi), radius * np.cos(phi)], axis=1)
    p = np.concatenate([ring, ring + (0, height, 0)])
    n = np.concatenate([ring, ring]) / radius
    uv = np.concatenate(
        [
            np.stack([j / segments, np.zeros_like(phi)], 1),
            np.stack([j / segments, np.ones_like(phi)], 1),
        ]
    )
    top = segments + 1
    faces = [[k, k + 1, top + k + 1] for k in range(segments)]
    faces += [[k, top + k + 1, top + k] for k in range(segments)]
    uv2 = None if uv2_scale is None else uv * uv2_scale
    return Mesh(p, faces, n, uv, uv2)


def wave_detail(size):
    c = (np.arange(size) + 0.5) / size
    s, t = np.meshgrid(c, c[::-1])
    _, gs, gt = wave_height(s, t)
    return normals_from_gradient(gs, gt).astype(np.float32)


def test_tangents_of_a_plane_and_a_mirrored_plane():
    m = plane()
    t = corner_tangents(m.positions, m.normals, m.uv, m.faces)
    np.testing.assert_allclose(t, np.broadcast_to([1.0, 0, 0, 1], t.shape), atol=1e-15)
    mirrored = m.uv * (-1, 1) + (1, 0)
    t = corner_tangents(m.positions, m.normals, mirrored, m.faces)
    np.testing.assert_allclose(t, np.broadcast_to([-1.0, 0, 0, -1], t.shape), atol=1e-15)


def test_tangents_of_a_cylinder_are_the_analytic_circumferential_direction():
    m = cylinder()
    t = corner_tangents(m.positions, m.normals, m.uv, m.faces)
    phi = 2 * np.pi * m.uv[m.faces][..., 0]
    expected = np.stack([np.cos(phi), np.zeros_like(phi), -np.sin(phi)], axis=-1)
    np.testing.assert_allclose(t[..., :3], expected, atol=1e-12)
    assert (t[..., 3] == 1).all()


def test_tangents_are_angle_weighted_and_welded_like_mikktspace():
    """A fan around one vertex: the sum of projected face tangents weighted by corner angles;
    splitting the shared vertex into copies with identical attributes changes nothing."""
    rng = np.random.default_rng(0)
    ring = np.stack(
        [np.cos(np.linspace(0, 2 * np.pi, 7)[:-1]), np.sin(np.linspace(0, 2 * np.pi, 7)[:-1])], 1
    )
    ring = ring * rng.uniform(0.5, 1.5, (6, 1))
    p = np.concatenate([[[0, 0, 0.3]], np.c_[ring, np.zeros(6)]])
    uv = np.concatenate([[[0.5, 0.5]], 0.5 + 0.4 * ring + rng.normal(scale=0.05, size=(6, 2))])
    n = np.tile([0.0, 0.0, 1.0], (7, 1))
    faces = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)])
    t = corner_tangents(p, n, uv, faces)
    # independent: per face dP/du, projected, normalised, angle-weighted at vertex 0
    acc = np.zeros(3)
    for f in faces:
        d1, d2 = p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]
        (a, b), (c, d) = uv[f[1]] - uv[f[0]], uv[f[2]] - uv[f[0]]
        dpdu = (d * d1 - b * d2) / (a * d - b * c)
        dpdu -= dpdu @ n[0] * n[0]
        # mikktspace.c EvalTspace: the edges are projected onto the normal's plane first
        e1, e2 = d1 - d1 @ n[0] * n[0], d2 - d2 @ n[0] * n[0]
        angle = np.arccos(e1 @ e2 / np.linalg.norm(e1) / np.linalg.norm(e2))
        acc += angle * dpdu / np.linalg.norm(dpdu)
    np.testing.assert_allclose(t[:, 0, :3], np.tile(acc / np.linalg.norm(acc), (6, 1)), atol=1e-12)
    # the same fan with vertex 0 duplicated per face (identical attributes): welded back
    p2 = np.concatenate([p, np.repeat(p[:1], 5, 0)])
    faces2 = faces.copy()
    faces2[1:, 0] = np.arange(7, 12)
    t2 = corner_tangents(
        p2, np.tile([0.0, 0, 1], (12, 1)), np.concatenate([uv, np.repeat(uv[:1], 5, 0)]), faces2
    )
    np.testing.assert_allclose(t2, t, atol=1e-15)


def test_rasterizer_covers_texel_centres_like_a_point_in_polygon_test():
    rng = np.random.default_rng(1)
    uv = rng.random((30, 2))
    faces = rng.integers(0, 30, size=(12, 3))
    face, bary = rasterize_uv(uv, faces, (48, 40))
    c = np.stack(np.meshgrid(np.arange(40) + 0.5, np.arange(48) + 0.5), -1).reshape(-1, 2)
    inside = np.zeros(48 * 40, bool)
    for f in faces:
        tri = np.stack([uv[f, 0] * 40, (1 - uv[f, 1]) * 48], 1)
        inside |= PolyPath(tri).contains_points(c, radius=1e-9) | PolyPath(
            tri[::-1]
        ).contains_points(c, radius=1e-9)
    assert np.array_equal(face.reshape(-1) >= 0, inside)
    # barycentrics interpolate the texel centres
    hit = face >= 0
    corners = uv[faces[face[hit]]]
    xy = np.einsum(
        "nk,nkc->nc", bary[hit], np.stack([corners[..., 0] * 40, (1 - corners[..., 1]) * 48], -1)
    )
    np.testing.assert_allclose(xy, c[hit.reshape(-1)], atol=1e-9)


def test_world_to_tangent_inverts_the_engine_reconstruction():
    rng = np.random.default_rng(2)
    t, n = rng.normal(size=(500, 3)), rng.normal(size=(500, 3))
    sign = rng.choice([-1.0, 1.0], 500)
    m = rng.normal(size=(500, 3))
    m[:, 2] = np.abs(m[:, 2]) + 0.5
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    b = sign[:, None] * np.cross(n, t)
    world = m[:, :1] * t + m[:, 1:2] * b + m[:, 2:] * n
    world /= np.linalg.norm(world, axis=1, keepdims=True)
    np.testing.assert_allclose(world_to_tangent(world, t, sign, n), m, atol=1e-10)


def test_dilate_copies_the_nearest_island_texel():
    img = np.zeros((5, 7, 3))
    covered = np.zeros((5, 7), bool)
    covered[2, 1], covered[2, 5] = True, True
    img[2, 1], img[2, 5] = (1, 0, 0), (0, 1, 0)
    out = dilate(img, covered, pixels=3)
    np.testing.assert_array_equal(out[2, 0], (1, 0, 0))
    np.testing.assert_array_equal(out[0, 6], (0, 1, 0))
    np.testing.assert_array_equal(out[2, 3], (1, 0, 0))  # tie: either island, never background
    full = dilate(img, np.zeros((5, 7), bool))
    np.testing.assert_array_equal(full, np.broadcast_to((0, 0, 1), full.shape))
    far = dilate(img, covered, pixels=1)
    np.testing.assert_array_equal(far[0, 3], (0, 0, 1))


def test_plane_planar_projection_is_the_tiled_detail():
    d = wave_detail(64)
    out, covered = transfer_detail(plane(), d, (64, 64), projection="planar", tile=1)
    assert covered.all()
    np.testing.assert_allclose(out, place_detail(d, (64, 64)), atol=tol.TRANSFER_SAME_SAMPLES)
    tri, _ = transfer_detail(plane(), d, (64, 64), projection="triplanar")
    np.testing.assert_allclose(tri, out, atol=tol.TRANSFER_SAME_SAMPLES)


@pytest.mark.parametrize("rotation", [0.0, 30.0, -100.0])
def test_plane_second_uv_set_rotated_and_scaled_is_place_detail(rotation):
    d = wave_detail(64)
    th = np.radians(rotation)
    uv = plane().uv * 2
    uv2 = np.stack(
        [
            np.cos(th) * uv[:, 0] + np.sin(th) * uv[:, 1],
            -np.sin(th) * uv[:, 0] + np.cos(th) * uv[:, 1],
        ],
        1,
    )
    out, _ = transfer_detail(plane(uv2), d, (64, 64), projection="uv2")
    expected = place_detail(d, (64, 64), tile=2, rotation=rotation)
    np.testing.assert_allclose(out, expected, atol=tol.TRANSFER_SAME_SAMPLES)


def test_cylinder_second_uv_set_is_the_tiled_detail():
    d = wave_detail(64)
    out, covered = transfer_detail(cylinder(uv2_scale=(3, 2)), d, (64, 128), projection="uv2")
    assert covered.all()
    expected = place_detail(d, (64, 128), tile=(3, 2))
    np.testing.assert_allclose(out, expected, atol=tol.TRANSFER_SAME_SAMPLES)


def test_cylinder_planar_projection_matches_the_analytic_surface_gradient():
    radius, size = 0.3, 256
    out, _ = transfer_detail(
        cylinder(segments=256, radius=radius),
        wave_detail(size),
        (size, 2 * size),
        projection="planar",
        axis="z",
    )
    u, v = np.meshgrid((np.arange(2 * size) + 0.5) / (2 * size), 1 - (np.arange(size) + 0.5) / size)
    phi = 2 * np.pi * u
    n = np.stack([np.sin(phi), np.zeros_like(phi), np.cos(phi)], -1)
    t = np.stack([np.cos(phi), np.zeros_like(phi), -np.sin(phi)], -1)
    b = np.broadcast_to([0.0, 1.0, 0.0], n.shape)
    _, hs, ht = wave_height(radius * np.sin(phi), v)  # (s, t) = (x, y)
    g = np.stack([hs, ht, np.zeros_like(hs)], -1)  # volume gradient of h(x, y)
    world = n - (g - np.sum(g * n, -1, keepdims=True) * n)
    expected = np.stack([np.sum(world * t, -1), np.sum(world * b, -1), np.sum(world * n, -1)], -1)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    angle = np.degrees(np.arccos(np.clip(np.sum(out * expected, -1), -1, 1)))
    # faceting (256 segments) and bilinear sampling of a 256-texel tile
    assert angle.max() < tol.TRANSFER_ANALYTIC_DEG
    # box picks +-Z faces there, so it agrees where |z| dominates
    box, _ = transfer_detail(
        cylinder(segments=256, radius=radius), wave_detail(size), (size, 2 * size), projection="box"
    )
    front = np.abs(np.cos(phi)) > 0.8
    np.testing.assert_allclose(box[front], out[front], atol=tol.TRANSFER_SAME_SAMPLES)


def test_flat_detail_transfers_to_flat_and_islands_are_padded():
    m = Mesh(plane().positions, plane().faces, plane().normals, plane().uv * 0.5 + 0.25)
    flat = np.zeros((8, 8, 3), np.float32)
    flat[..., 2] = 1
    for projection in ("planar", "box", "triplanar"):
        out, covered = transfer_detail(m, flat, (32, 32), projection=projection, padding=4)
        np.testing.assert_allclose(out, np.broadcast_to((0, 0, 1), out.shape), atol=1e-7)
        assert covered.sum() == 16 * 16


def test_transfer_bad_input():
    d = wave_detail(8)
    with pytest.raises(ArgumentError, match="second UV set"):
        transfer_detail(plane(), d, (8, 8), projection="uv2")
    with pytest.raises(ArgumentError, match="projection"):
        transfer_detail(plane(), d, (8, 8), projection="spherical")
    with pytest.raises(ArgumentError, match="faces"):
        Mesh(np.zeros((3, 3)), [[0, 1, 5]], None, np.zeros((3, 2)))
    with pytest.raises(ArgumentError, match="NaN"):
        Mesh(np.zeros((3, 3)), [[0, 1, 2]], None, np.full((3, 2), np.nan))


def write_gltf(path, mesh):
    """A minimal glTF 2.0 file with POSITION, NORMAL, TEXCOORD_0/1 (v down) and indices."""
    arrays = [
        mesh.positions.astype(np.float32),
        mesh.normals.astype(np.float32),
        (mesh.uv * (1, -1) + (0, 1)).astype(np.float32),
        (mesh.uv2 * (1, -1) + (0, 1)).astype(np.float32),
        mesh.faces.astype(np.uint32).reshape(-1),
    ]
    blob, views, accessors = b"", [], []
    for a in arrays:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": a.nbytes})
        kind = {3: "VEC3", 2: "VEC2"}.get(a.shape[1] if a.ndim == 2 else 0, "SCALAR")
        acc = {
            "bufferView": len(views) - 1,
            "componentType": 5126 if a.dtype == np.float32 else 5125,
            "count": len(a),
            "type": kind,
        }
        if kind == "VEC3" and len(accessors) == 0:
            acc["min"], acc["max"] = a.min(0).tolist(), a.max(0).tolist()
        accessors.append(acc)
        blob += a.tobytes()
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [
            {
                "primitives": [
                    {
                        "attributes": {
                            "POSITION": 0,
                            "NORMAL": 1,
                            "TEXCOORD_0": 2,
                            "TEXCOORD_1": 3,
                        },
                        "indices": 4,
                    }
                ]
            }
        ],
        "buffers": [
            {
                "byteLength": len(blob),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(),
            }
        ],
        "bufferViews": views,
        "accessors": accessors,
    }
    path.write_text(json.dumps(doc))


def test_load_gltf_with_two_uv_sets_and_obj(tmp_path):
    import trimesh

    m = cylinder(segments=16, uv2_scale=(3, 2))
    write_gltf(tmp_path / "c.gltf", m)
    got = load_mesh(tmp_path / "c.gltf")
    np.testing.assert_allclose(got.positions, m.positions, atol=1e-6)
    np.testing.assert_array_equal(got.faces, m.faces)
    np.testing.assert_allclose(got.uv, m.uv, atol=1e-6)
    np.testing.assert_allclose(got.uv2, m.uv2, atol=1e-6)
    tm = trimesh.Trimesh(
        m.positions,
        m.faces,
        vertex_normals=m.normals,
        process=False,
        visual=trimesh.visual.TextureVisuals(uv=m.uv),
    )
    tm.export(tmp_path / "c.obj")
    obj = load_mesh(tmp_path / "c.obj")
    assert obj.uv2 is None and len(obj.faces) == len(m.faces)
    # the same surface: every OBJ vertex (position, uv) is one of the cylinder's
    key = {tuple(np.round(np.r_[p, t], 5)) for p, t in zip(m.positions, m.uv, strict=True)}
    assert all(
        tuple(np.round(np.r_[p, t], 5)) in key for p, t in zip(obj.positions, obj.uv, strict=True)
    )
    with pytest.raises(FormatError, match="mesh extension"):
        load_mesh(tmp_path / "c.xyz")


def test_load_glb_written_by_trimesh_keeps_uvs_up(tmp_path):
    """trimesh writes glTF's v-down TEXCOORD_0; load_mesh turns it back to v up."""
    import trimesh

    m = cylinder(segments=12)
    material = trimesh.visual.material.PBRMaterial()
    tm = trimesh.Trimesh(
        m.positions,
        m.faces,
        vertex_normals=m.normals,
        process=False,
        visual=trimesh.visual.TextureVisuals(uv=m.uv, material=material),
    )
    tm.export(tmp_path / "c.glb")
    got = load_mesh(tmp_path / "c.glb")
    assert got.uv2 is None
    key = {tuple(np.round(np.r_[p, t], 5)) for p, t in zip(m.positions, m.uv, strict=True)}
    assert all(
        tuple(np.round(np.r_[p, t], 5)) in key for p, t in zip(got.positions, got.uv, strict=True)
    )


def _lying(doc):
    """The glTF document of write_gltf with its first index (accessor 4) set to 10**6."""
    blob = bytearray(base64.b64decode(doc["buffers"][0]["uri"].partition(",")[2]))
    start = doc["bufferViews"][4]["byteOffset"]
    blob[start : start + 4] = np.uint32(10**6).tobytes()
    doc["buffers"][0]["uri"] = "data:;base64," + base64.b64encode(bytes(blob)).decode()


LYING_GLTF = {
    "an index past the vertices": (_lying, "indexes vertex 1000000, past its"),
    "an accessor past its bufferView": (
        lambda doc: doc["accessors"][4].update(count=10**6),
        "accessor 4's 1000000 elements end at byte 4000000, past the",
    ),
    "an accessor offset past its bufferView": (
        lambda doc: doc["accessors"][0].update(byteOffset=10**9), "past the"
    ),
    "a bufferView past its buffer": (
        lambda doc: doc["bufferViews"][2].update(byteLength=10**6), "bufferView 2 ends at byte"
    ),
    "a bufferView of a buffer that is not there": (
        lambda doc: doc["bufferViews"][0].update(buffer=1), "buffer is 1, not an index below 1"
    ),
    "a glTF without buffers": (lambda doc: doc.pop("buffers"), "buffer is 0, not an index below 0"),
    "a byteLength that is not a number": (
        lambda doc: doc["bufferViews"][0].update(byteLength="12"), "byteLength is '12'"
    ),
    "an accessor that is not there": (
        lambda doc: doc["meshes"][0]["primitives"][0].update(indices=9), "not an index below 5"
    ),
    "a buffer shorter than its byteLength": (
        lambda doc: doc["buffers"][0].update(byteLength=10**6), "bytes, not its 1000000"
    ),
    "a buffer that is a FIFO": (
        lambda doc: doc["buffers"][0].update(uri="fifo.bin"), "named pipe"
    ),
    **{
        f"a buffer at {uri}": (
            lambda doc, uri=uri: doc["buffers"][0].update(uri=uri),
            f"buffer 0's uri {uri!r} is not a file in the glTF's folder",
        )
        for uri in ("../../../../etc/passwd", "%2e%2e/%2e%2e/etc/passwd", "/etc/passwd",
                    "file:///etc/passwd", "file:fifo.bin")
    },
}  # fmt: skip


@pytest.fixture
def gltf_with(tmp_path):
    """A glTF file written by write_gltf and changed by ``edit`` (beside it, a FIFO)."""

    def make(edit):
        path = tmp_path / "lying.gltf"
        write_gltf(path, cylinder(segments=16, uv2_scale=(3, 2)))
        doc = json.loads(path.read_text())
        edit(doc)
        path.write_text(json.dumps(doc))
        os.mkfifo(tmp_path / "fifo.bin")
        return path

    return make


@pytest.mark.parametrize("case", LYING_GLTF)
def test_a_gltf_whose_numbers_point_outside_its_data_is_refused(gltf_with, case):
    edit, message = LYING_GLTF[case]
    path = gltf_with(edit)
    with pytest.raises(BakeshopError, match=re.escape(message)) as e:
        load_mesh(path)
    assert e.value.path in (str(path), str(path.parent / "fifo.bin"))


def _glb(json_length: int, chunk: bytes) -> bytes:
    """A GLB whose JSON chunk says ``json_length`` bytes, with ``chunk`` after the JSON."""
    js = b'{"asset": {"version": "2.0"}}   '
    return b"glTF" + struct.pack("<III", 2, 0, json_length) + b"JSON" + js + chunk


GLB_CHUNKS = {
    "JSON past the end": (_glb(1 << 20, b""), "the JSON of 1,048,576 bytes runs past"),
    "JSON over the bound": (_glb(1 << 31, b""), "more than the 64 MiB read from a glTF"),
    "binary past the end": (
        _glb(32, struct.pack("<I", 1 << 30) + b"BIN\0" + bytes(16)),
        "the binary chunk of 1,073,741,824 bytes runs past",
    ),
}


@pytest.mark.parametrize("case", GLB_CHUNKS)
def test_a_glb_is_read_chunk_by_chunk_each_length_checked_first(tmp_path, case):
    data, message = GLB_CHUNKS[case]
    path = tmp_path / "lying.glb"
    path.write_bytes(data)
    with pytest.raises(BakeshopError, match=re.escape(message)):
        load_mesh(path)


def test_a_large_gltf_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from bakeshop import resources

    big = tmp_path / "big.gltf"
    with open(big, "wb") as f:
        f.truncate(65 << 20)  # sparse: nothing written
    with pytest.raises(BakeshopError, match="more than the 64 MiB read from a glTF"):
        load_mesh(big)
    glb = tmp_path / "big.glb"
    glb.write_bytes(_glb(32, struct.pack("<I", 48 << 20) + b"BIN\0"))
    with open(glb, "r+b") as f:
        f.truncate(f.seek(0, 2) + (48 << 20))
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": 40 << 20})
    with pytest.raises(BakeshopError, match="the binary chunk of 50,331,648 bytes needs about"):
        load_mesh(glb)


@pytest.mark.parametrize("command", [["float"], ["normals", "transfer"]])
def test_the_commands_that_read_a_mesh_refuse_it_in_one_line(gltf_with, capsys, command):
    path = gltf_with(_lying)
    extra = [str(path.parent / "d.png"), str(path.parent / "o.png"), "--size", "8"]
    if command == ["normals", "transfer"]:
        flat = np.broadcast_to(np.float32([0.5, 0.5, 1.0]), (8, 8, 3))  # a flat normal map
        write_image(path.parent / "d.png", flat)
    args = [*command, str(path), *(extra if command != ["float"] else [])]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: {path}: ") and err.count("\n") == 1
    assert "indexes vertex 1000000" in err
