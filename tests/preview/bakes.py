"""Small bakes for the preview tests, made in memory (no files outside the repository)."""

import numpy as np

from bakeshop.light import dfg_table
from bakeshop.preview import Bake, Sun
from bakeshop.sphere import layout, remap

#: towards the test sun: up and to the right of forward (-Z).
SUN = np.array([0.55, 0.45, -0.70]) / np.linalg.norm([0.55, 0.45, -0.70])


def sky(d):
    """A smooth sky over a darker ground, with structure in every direction."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    up = np.clip(y, 0, 1)
    r = 0.4 + 0.5 * up + 0.3 * np.clip(d @ SUN, 0, 1) ** 8 + 0.05 * np.sin(5 * x) * np.cos(3 * z)
    g = 0.35 + 0.4 * up + 0.1 * x * x + 0.05 * np.sin(4 * z)
    b = 0.2 + 0.9 * up + 0.1 * z
    ground = y < 0
    r, g, b = (np.where(ground, c * (0.4 + 0.2 * x), c) for c in (r, g, b))
    return np.stack([r, g, b], -1)


def synthetic_bake(*, size: int = 32, levels: int = 5, uniform: float | None = None) -> Bake:
    """A bake whose every table holds distinct, smooth values (the renderer must show what the
    files hold, whatever made them): the sky as the cube; level m of the chain the sky blurred
    into a smaller face and scaled by 1 + m/10 (so a wrong level is visible); DIMs of smooth
    functions; a real DFG table; random SH; a sun. ``uniform``: every radiance and DIM that
    value instead."""
    lat_dirs, _ = layout("latlong").directions((64, 128))
    pano = sky(lat_dirs).astype(np.float32)
    if uniform is not None:
        pano = np.full_like(pano, uniform)
    cube = remap(pano, "latlong", "cube", size)
    chain = [
        remap(pano * (1 + m / 10 if uniform is None else 1), "latlong", "cube", max(1, size >> m))
        for m in range(levels)
    ]
    dim_dirs, _ = layout("latlong").directions((32, 64))
    x, y, z = (dim_dirs[..., k] for k in range(3))
    sun_dim = np.stack([1.2 + 0.8 * x + 0.3 * y, 1.0 + 0.5 * y - 0.2 * z, 0.8 + 0.6 * z * y], -1)
    shadow_dim = 0.3 * sun_dim + 0.1 * np.stack([y * y, x * z, np.ones_like(x)], -1)
    if uniform is not None:
        sun_dim = shadow_dim = np.full_like(sun_dim, uniform)
    sh = np.random.default_rng(7).normal(size=(9, 3)) * 0.2
    sh[0] = 2.0
    return Bake(
        cube=np.ascontiguousarray(cube[..., :3], np.float32),
        specular=[np.ascontiguousarray(c[..., :3], np.float32) for c in chain],
        sun_dim=sun_dim.astype(np.float32),
        shadow_dim=shadow_dim.astype(np.float32),
        dfg=dfg_table(16, samples=256),
        sh=sh,
        sun=Sun(SUN, np.array([3.0, 2.8, 2.2]), 0.02),
    )
