"""Offscreen rendering of a bake with moderngl (EGL; Mesa's llvmpipe without a GPU).

:class:`Renderer` uploads a :class:`~bakeshop.preview.bake.Bake` once (the cube, every level of
the specular chain as the mips of one cube texture, the DIM pair, the DFG table) and draws
:class:`View` s of it into float framebuffers: linear radiance out, row 0 at the top. The
command line turns that into a picture with bakeshop's display rule
(:func:`bakeshop.image.to_picture`); ``display=True`` runs the shaders' own tone mapping instead
(what the browser shows), so the two can be compared.

Needs moderngl: ``pip install 'bakeshop[preview]'``.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from types import ModuleType
from typing import TYPE_CHECKING, Protocol, TypeVar, Union, cast

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, UnsupportedError, validate_choice
from bakeshop.preview.glsl import program_sources
from bakeshop.preview.scene import (
    BALL_KINDS,
    MAX_BALLS,
    Camera,
    Golf,
    balls,
    default_camera,
    golf_course,
    shadow_view_projection,
)

if TYPE_CHECKING:
    import moderngl as mgl

    from bakeshop.preview.bake import Bake
    from bakeshop.water.shader import WaterScene

__all__ = ["DIFFUSE", "OPERATORS", "SCENES", "Renderer", "View"]


class _GLObject(Protocol):
    def release(self) -> None: ...


_O = TypeVar("_O", bound=_GLObject)
#: the textures a program samples.
_Texture = Union["mgl.Texture", "mgl.TextureCube", "mgl.TextureArray"]
#: the shader's display transform: (exposure EV, tone-map operator).
Display = tuple[float, str]

#: What a view shows.
SCENES = ("sky", "balls", "golf", "water")
#: The golf course's diffuse lighting: the DIM pair by the shadow map, or one source everywhere.
DIFFUSE = {"pair": 0, "sun": 1, "shadow": 2, "sh": 3}
#: Tone operators of the shaders' display step (bakeshop.image's names).
OPERATORS = {"none": 0, "reinhard": 1, "aces": 2}
#: Water reflections: the fresnel-baked latlong, or fresnel times the HDR cube.
REFLECTIONS = {"fresnel": 0, "hdr": 1}
#: Side of the sun's shadow map, texels.
SHADOW_SIZE = 2048
#: The shadow lookup's offset along the normal, in shadow-map texels.
SHADOW_OFFSET_TEXELS = 1.5
#: GL enums used directly.
_SEAMLESS = 0x884F  # GL_TEXTURE_CUBE_MAP_SEAMLESS
_CUBE_POSITIVE_X, _RGBA, _FLOAT = 0x8515, 0x1908, 0x1406
#: Largest framebuffer side accepted.
MAX_SIDE = 8192


@dataclass(frozen=True)
class View:
    """One picture of a bake: the scene, its size and camera, and the viewer's toggles."""

    scene: str = "balls"
    width: int = 1280
    height: int = 720
    camera: Camera | None = None
    #: the golf course's diffuse lighting (:data:`DIFFUSE`).
    diffuse: str = "pair"
    #: the sky: -1 the environment cube, m >= 0 level m of the specular chain.
    sky_level: float = -1.0
    #: add sun.json's sun as a light to the GGX balls (the chain already holds it).
    sun_light: bool = False
    #: the pond on the golf course.
    water: bool = True
    #: the water's reflection (:data:`REFLECTIONS`).
    reflection: str = "fresnel"
    #: seconds (the water's animation).
    time: float = 0.0

    def __post_init__(self) -> None:
        validate_choice(self.scene, SCENES, "preview scene")
        validate_choice(self.diffuse, tuple(DIFFUSE), "diffuse lighting")
        validate_choice(self.reflection, tuple(REFLECTIONS), "water reflection")
        for side in (self.width, self.height):
            if not (isinstance(side, int) and 1 <= side <= MAX_SIDE):
                raise ArgumentError(f"a view is 1..{MAX_SIDE} pixels on a side, got {side!r}")
        if not np.isfinite(self.time) or not np.isfinite(self.sky_level):
            raise ArgumentError("time and sky level must be finite")

    @property
    def eye(self) -> Camera:
        """The camera (the scene's default when none was given)."""
        return self.camera if self.camera is not None else default_camera(self.scene)

    def to_dict(self) -> dict:
        """The view as JSON numbers (the browser's URL parameters are these)."""
        return {
            "scene": self.scene,
            "width": self.width,
            "height": self.height,
            "camera": self.eye.to_dict(),
            "diffuse": self.diffuse,
            "sky_level": self.sky_level,
            "sun_light": self.sun_light,
            "water": self.water,
            "reflection": self.reflection,
            "time": self.time,
        }


def _moderngl() -> ModuleType:
    try:
        import moderngl
    except ImportError:  # pragma: no cover - depends on the install
        raise UnsupportedError(
            "bakeshop preview renders with moderngl: pip install 'bakeshop[preview]'"
        ) from None
    return moderngl


def _context(moderngl: ModuleType) -> mgl.Context:
    """A standalone OpenGL 3.3 context: EGL (headless; Mesa's llvmpipe without a GPU), else the
    platform's default; an :class:`UnsupportedError` naming what to install when neither
    works."""
    try:
        return moderngl.create_context(standalone=True, backend="egl")
    except Exception as egl:  # noqa: BLE001 - any driver failure: try the default backend
        try:
            return moderngl.create_context(standalone=True)
        except Exception:  # noqa: BLE001
            raise UnsupportedError(
                f"no OpenGL 3.3 context ({str(egl).splitlines()[0] if str(egl) else egl!r}): "
                "install libEGL and Mesa (Debian: apt-get install libegl1 libgl1-mesa-dri)"
            ) from None


def _gl_function(name: str, restype: type | None, *argtypes: type) -> Callable[..., object]:
    """A GL entry point of the current context (moderngl has no call for a cube's mip level)."""
    prototype = ctypes.CFUNCTYPE(restype, *argtypes)
    for library, loader in (("EGL", "eglGetProcAddress"), ("GL", "glXGetProcAddress")):
        path = ctypes.util.find_library(library)
        if path is None:
            continue
        lib = ctypes.CDLL(path)
        get = getattr(lib, loader, None)
        if get is None:
            continue
        get.restype = ctypes.c_void_p
        get.argtypes = [ctypes.c_char_p]
        address = get(name.encode())
        if address:
            return prototype(address)
    raise UnsupportedError(f"this OpenGL has no {name}")


def _rgba(a: ArrayLike) -> np.ndarray:
    a = np.asarray(a, np.float32)
    out = np.ones(a.shape[:-1] + (4,), np.float32)
    out[..., : min(a.shape[-1], 4)] = a[..., :4]
    return np.ascontiguousarray(out)


class Renderer:
    """Draws views of one bake offscreen; upload once, render many.

    Parameters
    ----------
    bake : Bake
    golf : Golf, optional
        The golf course (default :func:`~bakeshop.preview.scene.golf_course`).
    water : bakeshop.water.shader.WaterScene, optional
        The water's textures and constants (normals flipbook, ripples, murk); default flat
        Jerlov IB water whose fresnel-baked reflection is made from the bake's cube.
    """

    def __init__(
        self, bake: Bake, *, golf: Golf | None = None, water: WaterScene | None = None
    ) -> None:
        moderngl = _moderngl()
        self.moderngl = moderngl
        self.bake = bake
        self.golf = golf if golf is not None else golf_course()
        self.ctx = _context(moderngl)
        self.ctx.enable_direct(_SEAMLESS)
        self._programs: dict[str, mgl.Program] = {}
        self._objects: list[_GLObject] = []
        self._upload(water)

    # -- setup ------------------------------------------------------------------------------

    def close(self) -> None:
        """Release the context and everything in it."""
        for obj in self._objects + list(self._programs.values()):
            obj.release()
        self._objects, self._programs = [], {}
        self.ctx.release()

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _keep(self, obj: _O) -> _O:
        self._objects.append(obj)
        return obj

    def program(self, name: str) -> mgl.Program:
        """The compiled program ``name`` (:data:`bakeshop.preview.glsl.PROGRAMS`)."""
        if name not in self._programs:
            vertex, fragment = program_sources(name, "gl")
            self._programs[name] = self.ctx.program(vertex_shader=vertex, fragment_shader=fragment)
        return self._programs[name]

    def _texture2d(
        self, a: ArrayLike, *, repeat_x: bool = False, linear: bool = True
    ) -> mgl.Texture:
        mgl = self.moderngl
        a = _rgba(a)
        tex = self._keep(self.ctx.texture((a.shape[1], a.shape[0]), 4, a.tobytes(), dtype="f4"))
        f = mgl.LINEAR if linear else mgl.NEAREST
        tex.filter = (f, f)
        tex.repeat_x, tex.repeat_y = repeat_x, False
        return tex

    def _cube(self, levels: Sequence[np.ndarray]) -> mgl.TextureCube:
        """One cube texture holding ``levels`` as its mips, faces uploaded rows in order."""
        mgl = self.moderngl
        first = _rgba(levels[0])
        s = first.shape[1]
        tex = self._keep(self.ctx.texture_cube((s, s), 4, first.tobytes(), dtype="f4"))
        if len(levels) > 1:
            tex.build_mipmaps(0, len(levels) - 1)
            sub = _gl_function(
                "glTexSubImage2D",
                None,
                ctypes.c_uint,
                ctypes.c_int,
                ctypes.c_int,
                ctypes.c_int,
                ctypes.c_int,
                ctypes.c_int,
                ctypes.c_uint,
                ctypes.c_uint,
                ctypes.c_void_p,
            )
            tex.use(15)
            for m, level in enumerate(levels[1:], start=1):
                level = _rgba(level)
                side = level.shape[1]
                for face in range(6):
                    data = np.ascontiguousarray(level[face])
                    sub(
                        _CUBE_POSITIVE_X + face,
                        m,
                        0,
                        0,
                        side,
                        side,
                        _RGBA,
                        _FLOAT,
                        data.ctypes.data,
                    )
            tex.filter = (mgl.LINEAR_MIPMAP_LINEAR, mgl.LINEAR)
        else:
            tex.filter = (mgl.LINEAR, mgl.LINEAR)
        return tex

    def _upload(self, water: WaterScene | None) -> None:
        b = self.bake
        self.textures: dict[str, _Texture] = {
            "uEnvCube": self._cube([b.cube]),
            "uSpecular": self._cube(b.specular),
            "uSunDim": self._texture2d(b.sun_dim, repeat_x=True),
            "uShadowDim": self._texture2d(b.shadow_dim, repeat_x=True),
            "uDfg": self._texture2d(b.dfg),
        }
        self._water_given = water
        self.water: WaterScene | None = None
        self._mesh: mgl.Buffer | None = None
        self._shadow: mgl.Texture | None = None

    def _upload_golf(self) -> None:
        """The golf course's mesh and the water's textures, on the first golf view (the sky
        and the balls need neither)."""
        if self._mesh is not None:
            return
        mgl = self.moderngl
        self.water = resolve_water(self.bake, self._water_given)
        arrays = water_arrays(self.water)
        normals = arrays["normals"]
        frames, n, _, comps = normals.shape
        arr = self._keep(
            self.ctx.texture_array((n, n, frames), comps, normals.tobytes(), dtype="f4")
        )
        arr.repeat_x = arr.repeat_y = True
        arr.filter = (mgl.LINEAR, mgl.LINEAR)
        self.textures["uNormals"] = arr
        self.textures["uEnv"] = self._texture2d(arrays["env"], repeat_x=True)
        rt = self._texture2d(arrays["rain"], linear=False)
        rt.repeat_x = rt.repeat_y = True
        self.textures["uRain"] = rt
        self.textures["uRing"] = self._texture2d(arrays["ring"])
        vertices = np.ascontiguousarray(self.golf.vertices, np.float32)
        self._mesh = self._keep(self.ctx.buffer(vertices))

    # -- uniforms ---------------------------------------------------------------------------

    def _bind(self, prog: mgl.Program, extra: dict[str, _Texture] | None = None) -> None:
        units = dict(self.textures, **(extra or {}))
        for unit, (name, tex) in enumerate(units.items()):
            if name in prog:
                tex.use(unit)
                cast("mgl.Uniform", prog[name]).value = unit

    def uniforms(self, view: View, *, display: Display | None = None) -> dict:
        """The uniforms every program shares, by name (the browser sets the same)."""
        b = self.bake
        sun = b.sun
        values = {
            "uSpecularLevels": float(len(b.specular)),
            "uSh": np.asarray(b.sh, np.float32),
            "uSunDirection": tuple(sun.direction) if sun else (0.0, 0.0, 0.0),
            "uSunIrradiance": tuple(sun.irradiance) if sun else (0.0, 0.0, 0.0),
            "uSunRadius": float(sun.radius) if sun else 0.0,
            "uSkyLevel": float(view.sky_level),
            "uDisplay": display is not None,
            "uExposure": float(display[0]) if display else 0.0,
            "uOperator": OPERATORS[display[1]] if display else 0,
        }
        return values

    @staticmethod
    def _set(prog: mgl.Program, values: dict) -> None:
        for name, value in values.items():
            if name not in prog:
                continue
            uniform = cast("mgl.Uniform", prog[name])
            if isinstance(value, np.ndarray):
                uniform.write(np.ascontiguousarray(value, np.float32).tobytes())
            elif isinstance(value, (tuple, list)):
                uniform.value = tuple(float(v) for v in value)
            else:
                uniform.value = value

    # -- drawing ----------------------------------------------------------------------------

    def _target(
        self, width: int, height: int, attachments: int = 1, depth: bool = False
    ) -> tuple[mgl.Framebuffer, list[mgl.Texture], mgl.Renderbuffer | None]:
        ctx = self.ctx
        colours = [ctx.texture((width, height), 4, dtype="f4") for _ in range(attachments)]
        for c in colours:
            c.filter = (self.moderngl.NEAREST, self.moderngl.NEAREST)
        rb = ctx.depth_renderbuffer((width, height)) if depth else None
        return ctx.framebuffer(color_attachments=colours, depth_attachment=rb), colours, rb

    @staticmethod
    def _read(fbo: mgl.Framebuffer, width: int, height: int, attachment: int = 0) -> np.ndarray:
        data = fbo.read(components=4, dtype="f4", attachment=attachment)
        return np.frombuffer(data, np.float32).reshape(height, width, 4)[::-1].copy()

    def render(self, view: View, *, mode: int = 0, display: Display | None = None) -> np.ndarray:
        """Draw ``view``; returns ``(height, width, 4)`` float32, row 0 at the top.

        Parameters
        ----------
        view : View
        mode : int
            The shaders' ``uMode``: 0 the shaded colour; balls: 1 (normal, ball index + 1);
            golf: 1 (normal, lit), 2 (albedo, lit), 5 (world position, 1 where drawn) from
            the scene pass (before the water and the sky); 3 (normal, 1 on
            water), 4 (path length, depth, 0, 1 on water) from the water pass.
        display : (ev, operator), optional
            Tone-map and sRGB-encode in the shader (the browser's path) instead of returning
            linear radiance.
        """
        if view.scene in ("sky", "balls"):
            return self._balls(view, mode, display)
        return self._golf(view, mode, display)

    def ball_list(self, view: View) -> list[dict]:
        """The balls ``view`` shows (:func:`bakeshop.preview.scene.balls`; none on the sky)."""
        return balls(len(self.bake.specular)) if view.scene == "balls" else []

    def _balls(self, view: View, mode: int, display: Display | None) -> np.ndarray:
        w, h = view.width, view.height
        prog = self.program("balls")
        self._bind(prog)
        items = self.ball_list(view)
        geometry = np.zeros((MAX_BALLS, 4), np.float32)
        material = np.zeros((MAX_BALLS, 4), np.float32)
        colour = np.zeros((MAX_BALLS, 4), np.float32)
        for i, ball in enumerate(items):
            geometry[i] = (*ball["centre"], ball["radius"])
            material[i] = (BALL_KINDS[ball["kind"]], ball["roughness"], ball["metalness"], 0.0)
            colour[i, :3] = ball["colour"]
        values = self.uniforms(view, display=display)
        values.update(
            {
                "uInvViewProj": _matrix(np.linalg.inv(view.eye.view_projection(w / h))),
                "uMode": int(mode),
                "uBallCount": len(items),
                "uBalls": geometry,
                "uBallMaterial": material,
                "uBallColor": colour,
                "uSunLight": bool(view.sun_light),
            }
        )
        self._set(prog, values)
        fbo, colours, _ = self._target(w, h)
        try:
            fbo.use()
            self.ctx.viewport = (0, 0, w, h)
            vao = self.ctx.vertex_array(prog, [])
            vao.render(self.moderngl.TRIANGLES, vertices=3)
            vao.release()
            return self._read(fbo, w, h)
        finally:
            fbo.release()
            for c in colours:
                c.release()

    def shadow_matrix(self) -> np.ndarray | None:
        """(4, 4) world -> the sun's clip space, or None without a sun."""
        if self.bake.sun is None:
            return None
        return shadow_view_projection(self.bake.sun.direction, self.golf.bounds)

    def _shadow_map(self) -> mgl.Texture | None:
        self._upload_golf()
        if self._shadow is None and self.bake.sun is not None:
            ctx, mgl = self.ctx, self.moderngl
            depth = self._keep(ctx.depth_texture((SHADOW_SIZE, SHADOW_SIZE)))
            depth.compare_func = ""
            depth.filter = (mgl.NEAREST, mgl.NEAREST)
            fbo = ctx.framebuffer(depth_attachment=depth)
            prog = self.program("shadow")
            sun_view = shadow_view_projection(self.bake.sun.direction, self.golf.bounds)
            self._set(prog, {"uViewProj": _matrix(sun_view)})
            vao = self._mesh_vao(prog)
            fbo.use()
            ctx.viewport = (0, 0, SHADOW_SIZE, SHADOW_SIZE)
            fbo.clear(depth=1.0)
            ctx.enable(mgl.DEPTH_TEST)
            vao.render(mgl.TRIANGLES)
            ctx.disable(mgl.DEPTH_TEST)
            vao.release()
            fbo.release()
            self._shadow = depth
        return self._shadow

    def _mesh_vao(self, prog: mgl.Program) -> mgl.VertexArray:
        """The golf meshes bound to ``prog``'s attributes (those it does not read skipped)."""
        parts, names = [], []
        for size, name in zip(_SIZES, _ATTRIBUTES, strict=True):
            if name in prog:
                parts.append(f"{size}f")
                names.append(name)
            else:
                parts.append(f"{4 * size}x")
        return self.ctx.vertex_array(prog, [(self._mesh, " ".join(parts), *names)])

    def _golf(self, view: View, mode: int, display: Display | None) -> np.ndarray:
        self._upload_golf()
        assert self.water is not None  # resolved by _upload_golf
        ctx, mgl = self.ctx, self.moderngl
        w, h = view.width, view.height
        shadow = self._shadow_map()
        vp = view.eye.view_projection(w / h)
        common = self.uniforms(view, display=display)
        scene = self.program("scene")
        extra: dict[str, _Texture] = {"uShadowMap": shadow} if shadow is not None else {}
        self._bind(scene, extra)
        values = dict(
            common,
            **shadow_uniforms(self.bake, self.golf),
            uViewProj=_matrix(vp),
            uMode=int(mode if mode in (1, 2) else 0),
            uDiffuse=DIFFUSE[view.diffuse],
        )
        self._set(scene, values)
        fbo, (colour, position), rb = self._target(w, h, attachments=2, depth=True)
        out, (final,), _ = self._target(w, h)
        try:
            fbo.use()
            ctx.viewport = (0, 0, w, h)
            fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
            ctx.enable(mgl.DEPTH_TEST)
            vao = self._mesh_vao(scene)
            vao.render(mgl.TRIANGLES)
            vao.release()
            ctx.disable(mgl.DEPTH_TEST)
            if mode in (1, 2, 5):
                return self._read(fbo, w, h, attachment=1 if mode == 5 else 0)
            compose = self.program("compose")
            self._bind(compose, {"uSceneColor": colour, "uScenePosition": position})
            values = dict(
                common,
                **water_uniforms(self.water),
                uInvViewProj=_matrix(np.linalg.inv(vp)),
                uMode={3: 1, 4: 2}.get(mode, 0),
                uWater=bool(view.water),
                uReflection=REFLECTIONS[view.reflection],
                uTime=float(view.time),
            )
            self._set(compose, values)
            out.use()
            vao = ctx.vertex_array(compose, [])
            vao.render(mgl.TRIANGLES, vertices=3)
            vao.release()
            return self._read(out, w, h)
        finally:
            for obj in (fbo, colour, position, rb, out, final):
                if obj is not None:  # rb is, when the target has no depth
                    obj.release()


#: the vertex attributes of the golf meshes and their floats (scene.VERTEX_FLOATS in all).
_ATTRIBUTES = ("aPosition", "aNormal", "aAlbedo", "aUv", "aCentre", "aKind")
_SIZES = (3, 3, 3, 2, 3, 1)


def _matrix(m: ArrayLike) -> tuple[float, ...]:
    """A (4, 4) matrix as GLSL's column-major tuple."""
    return tuple(float(v) for v in np.asarray(m, np.float64).T.ravel())


def resolve_water(bake: Bake, water: WaterScene | None = None) -> WaterScene:
    """The water the golf course shows: ``water`` (a :class:`bakeshop.water.shader.WaterScene`)
    or the default calm Jerlov IB water, with the bake's fresnel-baked reflection
    (:func:`fresnel_environment`) where it has none."""
    from bakeshop.water.shader import WaterScene

    water = water if water is not None else WaterScene()
    if water.environment is None:
        water = replace(water, environment=fresnel_environment(bake))
    return water


def water_arrays(water: WaterScene) -> dict[str, np.ndarray]:
    """The water's textures as both hosts upload them (float32): ``normals`` (F, N, N, C) (a
    flat 2 x 2 frame when there is none), ``env`` (H, 2H, 4), ``rain`` (N, N, 4) and ``ring``
    (T, R, 4) (zeros when there are no ripples)."""
    if water.environment is None:
        raise ArgumentError("the water has no reflection environment: see resolve_water")
    normals = water.normals
    if normals is None:
        normals = np.zeros((1, 2, 2, 3), np.float32) + (0.5, 0.5, 1.0)
    rain = water.rain if water.rain is not None else np.zeros((2, 2, 4), np.float32)
    ring = water.ring if water.ring is not None else np.zeros((2, 2, 2), np.float32)
    return {
        "normals": np.ascontiguousarray(normals, np.float32),
        "env": _rgba(water.environment),
        "rain": _rgba(rain),
        "ring": _rgba(np.asarray(ring)[..., :2]),
    }


def water_uniforms(water: WaterScene) -> dict:
    """The water pass's view-independent uniforms (water.frag's), by name."""
    normals = water_arrays(water)["normals"]
    return {
        "uFrames": int(normals.shape[0]),
        "uNormalXY": normals.shape[-1] == 2,
        "uFrameRate": float(water.frame_rate),
        "uTileSize": float(water.tile_size),
        "uNormalStrength": float(water.normal_strength if water.normals is not None else 0),
        "uIor": float(water.ior),
        "uBottomDepth": float(water.bottom_depth),
        "uWaterC": tuple(float(v) for v in water.water["c"]),
        "uWaterKd": tuple(float(v) for v in water.water["kd"]),
        "uWaterInscatter": tuple(float(v) for v in water.water["inscatter"]),
        "uRainCell": float(water.rain_cell),
        "uRainTile": float(water.rain_tile),
        "uRingRadius": float(water.ring_radius),
        "uRingDuration": float(water.ring_duration),
        "uRippleStrength": float(water.ripple_strength if water.rain is not None else 0),
    }


def shadow_uniforms(bake: Bake, golf: Golf) -> dict:
    """The scene pass's shadow uniforms: ``uHasShadows``, ``uShadowOffset`` (metres: 1.5 texels
    of the :data:`SHADOW_SIZE` map over the scene's bounding sphere) and ``uShadowViewProj``
    (column-major, when the bake has a sun)."""
    values = {
        "uHasShadows": bake.sun is not None,
        "uShadowOffset": SHADOW_OFFSET_TEXELS * 2 * golf.bounds[1] / SHADOW_SIZE,
    }
    if bake.sun is not None:
        values["uShadowViewProj"] = _matrix(shadow_view_projection(bake.sun.direction, golf.bounds))
    return values


def fresnel_environment(bake: Bake, *, height: int = 256) -> np.ndarray:
    """The water's fresnel-baked reflection (what ``bakeshop fresnel`` makes and an engine
    ships): the bake's cube as a latlong, times the exact reflectance of calm water
    (:func:`bakeshop.light.bake_fresnel`, mirrored below the horizon so filtering is seamless)."""
    from bakeshop.light import bake_fresnel
    from bakeshop.sphere import remap

    latlong = remap(bake.cube, "cube", "latlong", height, filter="auto")
    return np.asarray(bake_fresnel(latlong, "latlong", below="mirror"), np.float32)
