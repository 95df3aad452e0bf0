"""Before/after cases of the `pictures` slice of issue 32 (bakeshop.image display and resize,
bakeshop.normals blend, tiling and transfer, bakeshop.photo merge): each thunk calls a public
function whose name and signature are the same under the old JIT (main before the port) and the C++
kernels, on inputs built once here."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def _unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _sphere_mesh():  # an icosphere with a latitude-longitude UV set and a scaled copy as uv2
    import trimesh

    from bakeshop.io.mesh import Mesh

    sphere = trimesh.creation.icosphere(subdivisions=5)
    v = sphere.vertices
    uv = np.stack(
        [
            0.5 + np.arctan2(v[:, 1], v[:, 0]) / (2 * np.pi),
            0.5 + np.arcsin(np.clip(v[:, 2], -1, 1)) / np.pi,
        ],
        1,
    )
    return Mesh(v, sphere.faces, np.asarray(sphere.vertex_normals), uv, uv * [2.0, 1.5] + 0.1)


def cases() -> list[tuple[str, Callable[[], object]]]:
    from bakeshop.image import resize_area, srgb_decode, srgb_encode, to_srgb8
    from bakeshop.normals.blend import blend
    from bakeshop.normals.tiling import mip_chain, place_detail, sample_wrapped
    from bakeshop.normals.transfer import dilate, rasterize_uv, transfer_detail, world_to_tangent
    from bakeshop.photo.merge import merge_stack
    from bakeshop.photo.response import known_response
    from bakeshop.photo.stack import make_stack

    rng = np.random.default_rng(0)
    hdr = rng.exponential(0.5, (2048, 4096, 3)).astype(np.float32)
    display = rng.uniform(0, 1, (2048, 2048, 4)).astype(np.float32)
    macro = _unit(rng.normal(0, 0.3, (2048, 2048, 3)) + [0, 0, 1]).astype(np.float32)
    detail_big = _unit(rng.normal(0, 0.3, (2048, 2048, 3)) + [0, 0, 1]).astype(np.float32)
    detail = _unit(rng.normal(0, 0.3, (512, 512, 3)) + [0, 0, 1]).astype(np.float32)
    chain = mip_chain(detail)
    n = 2_000_000
    xs, ys, lods = rng.uniform(-512, 1024, n), rng.uniform(-512, 1024, n), rng.uniform(0, 6, n)
    mesh = _sphere_mesh()
    face, _ = rasterize_uv(mesh.uv, mesh.faces, (2048, 2048))
    covered = face >= 0
    noise = rng.normal(0, 1, (2048, 2048, 3)).astype(np.float32)
    m = 2_000_000
    world, tangent, normal = (_unit(rng.normal(0, 1, (m, 3))) for _ in range(3))
    sign = np.sign(rng.normal(0, 1, m))
    times = [1 / 64, 1 / 16, 1 / 4, 1.0, 4.0]
    radiance = rng.exponential(0.3, (1024, 2048, 3))
    frames = [
        np.clip(np.rint(np.clip(radiance * t, 0, 1) ** (1 / 2.2) * 255), 0, 255).astype(np.uint8)
        for t in times
    ]
    stack = make_stack(frames, times)
    response = known_response("gamma", gamma=2.2)
    shifts = [[0, 0], [0.5, -0.25], [1, 2], [-1.5, 0.75], [0, 0]]

    return [
        ("image.display srgb_encode 4096x2048x3 f32", lambda: srgb_encode(hdr)),
        ("image.display srgb_decode 4096x2048x3 f32", lambda: srgb_decode(hdr)),
        ("image.display to_srgb8 2048x2048x4", lambda: to_srgb8(display)),
        (
            "image.display to_srgb8 dither 2048x2048x4",
            lambda: to_srgb8(display, dither="triangular", seed=1),
        ),
        ("image.resize box 4096x2048x3 -> 1024x512", lambda: resize_area(hdr, (1024, 512))),
        ("image.resize separable 4096x2048x3 -> 1000x500", lambda: resize_area(hdr, (1000, 500))),
        (
            "image.resize upsample 1024x512x3 -> 3000x1500",
            lambda: resize_area(hdr[:512, :1024], (3000, 1500)),
        ),
        ("normals.blend exact 2048x2048 f32", lambda: blend(macro, detail_big, method="exact")),
        ("normals.blend rnm 2048x2048 f32", lambda: blend(macro, detail_big, method="rnm")),
        (
            "normals.tiling sample_wrapped 2M points",
            lambda: sample_wrapped(chain, xs, ys, lod=lods),
        ),
        (
            "normals.tiling place_detail 2048x2048 from 512x512",
            lambda: place_detail(detail, (2048, 2048), tile=(6.5, 6.5), rotation=30, chain=chain),
        ),
        (
            "normals.transfer rasterize_uv 20k faces 2048x2048",
            lambda: rasterize_uv(mesh.uv, mesh.faces, (2048, 2048)),
        ),
        ("normals.transfer dilate 2048x2048 all", lambda: dilate(noise, covered, pixels=None)),
        (
            "normals.transfer world_to_tangent 2M",
            lambda: world_to_tangent(world, tangent, sign, normal),
        ),
        (
            "normals.transfer transfer_detail uv2 1024x1024",
            lambda: transfer_detail(mesh, detail, (1024, 1024), projection="uv2", tile=4),
        ),
        (
            "normals.transfer transfer_detail triplanar 1024x1024",
            lambda: transfer_detail(mesh, detail, (1024, 1024), projection="triplanar", tile=4),
        ),
        ("photo.merge 5 frames 2048x1024", lambda: merge_stack(stack, response)),
        (
            "photo.merge 5 frames 2048x1024 ghost + subpixel shifts",
            lambda: merge_stack(stack, response, ghost=0.25, shifts=shifts),
        ),
    ]
