"""Before/after cases of the sphere-sampling kernels (issue 32): the layouts' maps, remap plans
and gathers, the windows' part taps and the texel kernels, each through a function that has the
same name and signature as the old JIT kernels (before) and compiled (after)."""

from __future__ import annotations

import importlib
from collections.abc import Callable

import numpy as np


def cases() -> list[tuple[str, Callable[[], object]]]:
    from bakeshop.sphere import _plans, sample, windows

    try:  # the kernel's module before the compiled core
        from bakeshop.sphere._gather import gather_plan_clamped
    except ImportError:
        from bakeshop.sphere._native import gather_plan_clamped
    from bakeshop.sphere.layouts import layout

    texels = importlib.import_module("bakeshop.sphere.texels")
    rng = np.random.default_rng(0)
    dirs = rng.normal(size=(2_000_000, 3))
    latlong = rng.random((1024, 2048, 3), dtype=np.float32)
    flat = latlong.reshape(-1, 3)
    ll, cube = (1024, 2048), (6, 512, 512)
    bilinear = _plans.build("latlong", ll, "cube", cube, "bilinear", None)
    nearest = _plans.build("latlong", ll, "cube", cube, "nearest", None)
    base, frac, taps = bilinear
    clamped = np.empty((len(base), 3), np.float32)
    big = rng.random((2048, 4096, 3), dtype=np.float32)
    index = rng.integers(0, 6 * 512 * 512, 1_000_000)
    up = (0.0, 1.0, 0.0)
    return [
        ("sphere.maps coordinates latlong 2M dirs",
         lambda: layout("latlong").coordinates(dirs, ll)),
        ("sphere.maps directions cube 6x512^2", lambda: layout("cube").directions(cube)),
        ("sphere.maps directions angular 1024^2",
         lambda: layout("angular").directions((1024, 1024))),
        ("sphere.plan build latlong 2048x1024 -> cube 6x512^2 bilinear",
         lambda: _plans.build("latlong", ll, "cube", cube, "bilinear", None)),
        ("sphere.plan build latlong 2048x1024 -> cube 6x512^2 nearest",
         lambda: _plans.build("latlong", ll, "cube", cube, "nearest", None)),
        ("sphere.plan build cube 6x512^2 -> latlong 2048x1024 bilinear",
         lambda: _plans.build("cube", cube, "latlong", ll, "bilinear", None)),
        ("sphere.plan build+apply in parts latlong -> cube 6x512^2 bilinear",
         lambda: _plans.build("latlong", ll, "cube", cube, "bilinear", None, flat,
                              np.empty((6 * 512 * 512, 3), np.float32))),
        ("sphere.gather plan bilinear 6x512^2 RGB f32",
         lambda: _plans.apply(flat, bilinear, 2048)),
        ("sphere.gather plan nearest 6x512^2 RGB f32",
         lambda: _plans.apply(flat, nearest, 2048)),
        ("sphere.gather plan clamped bilinear 6x512^2 RGB f32",
         lambda: gather_plan_clamped(flat, 2048, base, frac, taps, 0.5, clamped)),
        ("sphere.sample bilinear 2M dirs from 2048x1024",
         lambda: sample(latlong, "latlong", dirs, filter="bilinear")),
        ("sphere.sample nearest 2M dirs from 2048x1024",
         lambda: sample(latlong, "latlong", dirs, filter="nearest")),
        ("sphere.windows part taps cube face 512^2 from latlong 2048x1024",
         lambda: windows.remap_part_taps("latlong", ll, "cube", cube, face=2, rows=(0, 512),
                                         cols=(0, 512))),
        ("sphere.windows latlong window geometry 4096x2048 rows 512",
         lambda: windows.latlong_window_geometry((2048, 4096), (256, 768))),
        ("sphere.texels check_environment 4096x2048 RGB f32",
         lambda: texels.check_environment(big, "latlong")),
        ("sphere.texels texel strips cube 6x512^2",
         lambda: sum(1 for _ in texels.texel_strips("cube", cube))),
        ("sphere.texels texels_at cube 1M", lambda: texels.texels_at("cube", cube, index)),
        ("sphere.texels cosines mirrorball 2048^2",
         lambda: texels._texel_cosines(layout("mirrorball"), (2048, 2048), up)),
    ]  # fmt: skip
