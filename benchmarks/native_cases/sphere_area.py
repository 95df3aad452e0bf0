"""Before/after cases of the area filter's kernels (issue 32, slice sphere-area): each thunk
runs a function of bakeshop.sphere whose name and signature are the same under the old JIT (main at
b7d1cc9) and compiled; the inputs are built here, outside the thunks."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def cases() -> list[tuple[str, Callable[[], object]]]:
    from bakeshop.sphere import area, layout, reductions, remap
    from bakeshop.sphere.rotation import rotation_key

    rng = np.random.default_rng(32)
    probe = (rng.random((512, 1024, 3), np.float32) ** 4).astype(np.float32)
    flat = probe.reshape(-1, 3)
    big = (rng.random((2048, 4096, 3), np.float32) ** 4).astype(np.float32)
    big_flat = big.reshape(-1, 3)
    fine_cube = np.ascontiguousarray(remap(big, "latlong", "cube", 1024, filter="bilinear"))
    latlong, cubemap = layout("latlong"), layout("cube")
    big_omega = latlong.solid_angles((2048, 4096)).reshape(-1)
    turned = rotation_key((20, 10, 0))

    # the matrix the balancing and the gather cases run on (the gather's cached)
    plan = area._build("latlong", (512, 1024), "cube", (6, 128, 128), None)
    area.area_remap(flat, latlong, (512, 1024), cubemap, (6, 128, 128), None)
    indptr, indices, values = plan
    omega_in = latlong.solid_angles((512, 1024)).reshape(-1)
    omega_out = cubemap.solid_angles((6, 128, 128)).reshape(-1)

    def build(src: str, shape: tuple, dst: str, dst_shape: tuple, rot: bytes | None) -> object:
        # the whole matrix, uncached: geometry, rows, balancing
        return area._build(src, shape, dst, dst_shape, rot)

    return [
        ("sphere.area matrix latlong 1024x512 -> cube 128",
         lambda: build("latlong", (512, 1024), "cube", (6, 128, 128), None)),
        ("sphere.area matrix latlong 1024x512 -> octahedral 512 rotated",
         lambda: build("latlong", (512, 1024), "octahedral", (512, 512), turned)),
        ("sphere.area matrix latlong 1024x512 -> latlong 1280x640 (cut into parts)",
         lambda: build("latlong", (512, 1024), "latlong", (640, 1280), None)),
        ("sphere.area matrix cube 128 -> mirrorball 512 (cut into parts)",
         lambda: build("cube", (6, 128, 128), "mirrorball", (512, 512), None)),
        ("sphere.area balance latlong 1024x512 -> cube 128",
         lambda: area._balance(indptr, indices, values.copy(), omega_out, omega_in)),
        ("sphere.area gather latlong 1024x512 -> cube 128 (x20)",
         lambda: [area.area_remap(flat, latlong, (512, 1024), cubemap, (6, 128, 128), None)
                  for _ in range(20)]),
        ("sphere.area supersample latlong 4096x2048 -> cube 256 (k=4)",
         lambda: area.supersample(big_flat, latlong, (2048, 4096), cubemap, (6, 256, 256), None,
                                  4)),
        ("sphere.reductions reduce_cube 1024 -> 256",
         lambda: reductions.reduce_cube(fine_cube, 256)),
        ("sphere.area peak_candidates latlong 4096x2048",
         lambda: area.peak_candidates(big_flat, big_omega)),
    ]  # fmt: skip
