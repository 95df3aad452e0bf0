"""The reference water shader (GLSL 3.30) and an offscreen renderer that runs it.

``bakeshop/water/shaders/water.frag`` reads what ``bakeshop water`` writes: the ocean normal
flipbook as a texture array (frame = time x frame rate, blended with the next; tiled by world
position / tile size), the fresnel-baked latlong environment for reflection, refraction by
Snell's law onto a bottom at a given depth with murk by the underwater path length (beam
attenuation, ambient light fading with depth, in-scatter), and the rain atlas with the ring
lookup table for ripples. :func:`render_water` draws it with moderngl in an offscreen OpenGL
context (EGL; Mesa's llvmpipe without a GPU), so the textures are proven to drive a real
driver; its ``mode`` also exposes the shader's intermediate values for checking.

Needs moderngl: ``pip install 'bakeshop[preview]'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from importlib import resources
from types import ModuleType
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, UnsupportedError

if TYPE_CHECKING:
    import moderngl as mgl

    from bakeshop.water import murk

#: Uniforms of Jerlov type IB water (bakeshop.water.murk), for scenes that do not set their own.
DEFAULT_WATER = {"c": (0.392, 0.154, 0.144), "kd": (0.346, 0.067, 0.035),
                 "inscatter": (0.0023, 0.0114, 0.0181)}  # fmt: skip

#: Outputs of the shader's uMode.
MODES = {"colour": 0, "normal": 1, "path": 2, "ripple": 3}


def shader_sources() -> tuple[str, str]:
    """(vertex, fragment) GLSL sources of the reference water shader."""
    root = resources.files("bakeshop.water").joinpath("shaders")
    return root.joinpath("water.vert").read_text(), root.joinpath("water.frag").read_text()


def look_at(
    camera: ArrayLike, target: ArrayLike, *, fov: float = 60.0, aspect: float = 1.0
) -> np.ndarray:
    """Inverse view-projection matrix (4, 4) of a perspective camera at ``camera`` looking at
    ``target`` (world, +Y up), vertical field of view ``fov`` degrees."""
    eye = np.asarray(camera, dtype=np.float64)
    forward = np.asarray(target, dtype=np.float64) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    if np.linalg.norm(right) < 1e-9:
        right = np.cross(forward, [0.0, 0.0, -1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, up, -forward
    view[:3, 3] = -view[:3, :3] @ eye
    f = 1 / math.tan(math.radians(fov) / 2)
    near, far = 0.1, 1000.0
    proj = np.zeros((4, 4))
    proj[0, 0], proj[1, 1] = f / aspect, f
    proj[2, 2], proj[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    proj[3, 2] = -1
    return np.linalg.inv(proj @ view)


def orthographic_down(
    x0: float, z0: float, width: float, depth: float, height: float = 10.0
) -> np.ndarray:
    """Inverse view-projection (4, 4) of a view straight down onto the rectangle
    [x0, x0 + width] x [z0, z0 + depth] of the water plane (pixel row 0 at z0, the top of the
    image: -Z is up the picture, as in the textures)."""
    # NDC (-1..1) -> world: x = x0 + (ndc_x + 1) / 2 width; image top (ndc_y = 1) -> z0
    inv = np.zeros((4, 4))
    inv[0, 0], inv[0, 3] = width / 2, x0 + width / 2
    inv[2, 1], inv[2, 3] = -depth / 2, z0 + depth / 2
    inv[1, 2], inv[1, 3] = -height, 0.0  # ndc z = 1 (far) -> y = -height, below the plane
    inv[3, 3] = 1
    return inv


@dataclass
class WaterScene:
    """Everything the shader reads (SI units). Texture arrays as they are stored.

    normals : (F, N, N, C) packed normal frames in [0, 1] (C = 3, or 2 for BC5-ready maps), or
        None for flat water; frame_rate (1/s) and tile_size (m).
    environment : (H, 2H, 3) fresnel-baked latlong, linear.
    water : dict with ``c``, ``kd`` (1/m) and ``inscatter`` (3,) (see bakeshop.water.murk);
        bottom_depth (m).
    rain, ring : the rain atlas (N, N, 4) and the ring LUT (T, R, >= 2), with rain_cell,
        rain_tile, ring_radius (m) and ring_duration (s); None for no ripples.
    """

    normals: np.ndarray | None = None
    frame_rate: float = 1.0
    tile_size: float = 64.0
    normal_strength: float = 1.0
    environment: np.ndarray | None = None
    ior: float = 1.333
    bottom_depth: float = 4.0
    water: dict = field(default_factory=lambda: dict(DEFAULT_WATER))
    rain: np.ndarray | None = None
    ring: np.ndarray | None = None
    rain_cell: float = 0.25
    rain_tile: float = 1.0
    ring_radius: float = 0.125
    ring_duration: float = 1.0
    ripple_strength: float = 1.0


def _context() -> tuple[ModuleType, mgl.Context]:
    try:
        import moderngl
    except ImportError:  # pragma: no cover - depends on the install
        raise UnsupportedError(
            "rendering the water shader needs moderngl: pip install 'bakeshop[preview]'"
        ) from None
    try:
        # moderngl's stub types every **settings value as a dict; backend is a string
        return moderngl, moderngl.create_context(standalone=True, backend="egl")  # type: ignore[arg-type]
    except Exception:  # noqa: BLE001 - fall back to the platform's default backend
        return moderngl, moderngl.create_context(standalone=True)


def render_water(
    scene: WaterScene,
    *,
    width: int,
    height: int,
    inv_view_proj: np.ndarray,
    time: float = 0.0,
    mode: str = "colour",
) -> np.ndarray:
    """Render the reference shader offscreen; returns ``(height, width, 4)`` float32, row 0
    at the top. ``mode``: "colour", "normal" (world normal), "path" (underwater path length m,
    bottom hit x, z) or "ripple" (ripple slope d eta / dr, mask)."""
    if mode not in MODES:
        raise ArgumentError(f"unknown mode {mode!r}; choose one of {', '.join(MODES)}")
    moderngl, ctx = _context()
    try:
        vertex, fragment = shader_sources()
        prog = ctx.program(vertex_shader=vertex, fragment_shader=fragment)
        fbo = ctx.framebuffer(color_attachments=[ctx.texture((width, height), 4, dtype="f4")])
        fbo.use()
        textures: list[mgl.Texture | mgl.TextureArray] = []

        def bind(name: str, unit: int, tex: mgl.Texture | mgl.TextureArray) -> None:
            tex.use(unit)
            if name in prog:
                cast("mgl.Uniform", prog[name]).value = unit
            textures.append(tex)

        normals = scene.normals
        if normals is None:
            normals = np.full((1, 2, 2, 3), 0.5, np.float32)
            normals[..., 2] = 1.0
        normals = np.ascontiguousarray(normals, np.float32)
        frames, n, _, comps = normals.shape
        arr = ctx.texture_array((n, n, frames), comps, normals.tobytes(), dtype="f4")
        arr.repeat_x = arr.repeat_y = True
        arr.filter = (moderngl.LINEAR, moderngl.LINEAR)
        bind("uNormals", 0, arr)
        env = scene.environment
        if env is None:
            env = np.ones((8, 16, 3), np.float32) * 0.05
        env = np.ascontiguousarray(env, np.float32)
        et = ctx.texture((env.shape[1], env.shape[0]), 3, env.tobytes(), dtype="f4")
        et.filter = (moderngl.LINEAR, moderngl.LINEAR)
        bind("uEnv", 1, et)
        rain = scene.rain if scene.rain is not None else np.zeros((2, 2, 4), np.float32)
        rt = ctx.texture((rain.shape[1], rain.shape[0]), 4,
                         np.ascontiguousarray(rain, np.float32).tobytes(), dtype="f4")  # fmt: skip
        rt.filter = (moderngl.NEAREST, moderngl.NEAREST)  # offsets and phases are not blended
        rt.repeat_x = rt.repeat_y = True
        bind("uRain", 2, rt)
        ring = scene.ring if scene.ring is not None else np.zeros((2, 2, 2), np.float32)
        ring = np.ascontiguousarray(ring[..., :2], np.float32)
        lt = ctx.texture((ring.shape[1], ring.shape[0]), 2, ring.tobytes(), dtype="f4")
        lt.filter = (moderngl.LINEAR, moderngl.LINEAR)
        lt.repeat_x = lt.repeat_y = False
        bind("uRing", 3, lt)
        values = {
            "uInvViewProj": tuple(np.asarray(inv_view_proj, np.float32).T.ravel()),
            "uMode": MODES[mode],
            "uNormalXY": comps == 2,
            "uFrames": frames,
            "uFrameRate": float(scene.frame_rate),
            "uTime": float(time),
            "uTileSize": float(scene.tile_size),
            "uNormalStrength": float(scene.normal_strength if scene.normals is not None else 0),
            "uIor": float(scene.ior),
            "uBottomDepth": float(scene.bottom_depth),
            "uWaterC": tuple(float(v) for v in scene.water["c"]),
            "uWaterKd": tuple(float(v) for v in scene.water["kd"]),
            "uWaterInscatter": tuple(float(v) for v in scene.water["inscatter"]),
            "uRainCell": float(scene.rain_cell),
            "uRainTile": float(scene.rain_tile),
            "uRingRadius": float(scene.ring_radius),
            "uRingDuration": float(scene.ring_duration),
            "uRippleStrength": float(scene.ripple_strength if scene.rain is not None else 0),
        }
        for name, value in values.items():
            if name in prog:
                cast("mgl.Uniform", prog[name]).value = value
        vao = ctx.vertex_array(prog, [])
        ctx.viewport = (0, 0, width, height)
        vao.render(moderngl.TRIANGLES, vertices=3)
        image = np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32)
        image = image.reshape(height, width, 4)[::-1].copy()  # GL's first row is the bottom
        for tex in textures:
            tex.release()
        vao.release()
        fbo.release()
        prog.release()
        return image
    finally:
        ctx.release()


def scene_water(w: murk.Water) -> dict:
    """The shader's water uniforms from a :class:`bakeshop.water.murk.Water`."""
    from bakeshop.water import murk

    return {
        "c": murk.channel_coefficients(w)["rgb"],
        "kd": murk.channel_coefficients(w, which="diffuse")["rgb"],
        "inscatter": murk.inscatter(w, 1e6, 0.0)[:3],
    }
