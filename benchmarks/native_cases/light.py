"""Before/after cases of bakeshop.light's kernels (issue 32): the old JIT at b7d1cc9, C++ after.

Each case calls a function whose name and signature are the same on both sides; the inputs are
made here, outside the timed thunks. The environment is a synthetic sky: a smooth gradient with
noise and a small bright sun, so that ``auto``'s bins split as on a real probe.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from bakeshop.light import dfg, diffuse, fresnel, sh, specular
from bakeshop.light.sun_texels import TexelArrays
from bakeshop.sphere import layout


def _sky(width: int, height: int) -> np.ndarray:
    rng = np.random.default_rng(32)
    lat = np.linspace(1.0, 0.0, height)[:, None, None]
    sky = (0.2 + 0.8 * lat) * np.array([0.5, 0.7, 1.0]) + 0.05 * rng.random((height, width, 3))
    sun_y, sun_x, r = height // 4, width // 3, max(1, width // 512)
    sky[sun_y - r : sun_y + r + 1, sun_x - r : sun_x + r + 1] = 5e4
    return sky.astype(np.float32)


def cases() -> list[tuple[str, Callable[[], object]]]:
    sky = _sky(2048, 1024)
    small = _sky(512, 256)
    lat = layout("latlong")
    dirs, _ = lat.directions((1024, 2048))
    dirs = np.ascontiguousarray(dirs.reshape(-1, 3))
    omega = lat.solid_angles((1024, 2048)).reshape(-1)
    values = sky.reshape(-1, 3)
    hdirs = np.ascontiguousarray(lat.directions((512, 1024))[0].reshape(-1, 3))
    homega = lat.solid_angles((512, 1024)).reshape(-1)
    hvalues = _sky(1024, 512).reshape(-1, 3)
    sdirs = np.ascontiguousarray(lat.directions((256, 512))[0].reshape(-1, 3))
    somega = lat.solid_angles((256, 512)).reshape(-1)
    svalues = small.reshape(-1, 3).astype(np.float64)
    normals = np.ascontiguousarray(lat.directions((45, 90))[0].reshape(-1, 3))
    cosines = np.linspace(0.0, 1.0, 4_000_000)
    cube = specular.source_cube(small, "latlong", size=64)
    texels = TexelArrays(values, dirs, omega)
    centre = np.array([0.0, 1.0, 0.0])
    return [
        (
            "light.diffuse irradiance auto 2048x1024 -> 180x90",
            lambda: diffuse.irradiance(sky, "latlong", size=(180, 90)),
        ),
        ("light.diffuse compress 2048x1024", lambda: diffuse.compress(values, dirs, omega)),
        (
            "light.diffuse cosine_sum 90x45 normals x 512x256 sources",
            lambda: diffuse.cosine_sum(normals, sdirs, svalues * somega[:, None]),
        ),
        ("light.sh project order 2, 2048x1024", lambda: sh.project(values, dirs, omega, order=2)),
        ("light.sh project order 4, 1024x512", lambda: sh.project(hvalues, hdirs, homega, order=4)),
        ("light.sh basis order 8, 512x256", lambda: sh.basis(sdirs, 8)),
        ("light.fresnel fresnel_dielectric 4M", lambda: fresnel.fresnel_dielectric(cosines)),
        ("light.fresnel bake_fresnel 2048x1024", lambda: fresnel.bake_fresnel(sky, "latlong")),
        ("light.dfg dfg_table 64, 1024 samples", lambda: dfg.dfg_table(64, samples=1024)),
        (
            "light.dfg dfg_terms 2048 points, 1024 samples",
            lambda: dfg.dfg_terms(np.linspace(0, 1, 2048), 0.5, samples=1024),
        ),
        ("light.sun_texels brightest 2048x1024", lambda: texels.brightest(centre, 2.0)),
        ("light.sun_texels cap 2048x1024", lambda: texels.cap(centre, 0.9)),
        (
            "light.specular prefilter_ggx 6x64, 7 levels",
            lambda: specular.prefilter_ggx(cube, "cube", size=64, mips=7),
        ),
    ]
