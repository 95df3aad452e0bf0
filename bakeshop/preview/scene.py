"""The preview's scenes as plain data: cameras, the material balls, and the golf course.

Everything here is numbers that both hosts receive (moderngl as uniforms and buffers, the
browser as JSON and one binary buffer), so the two draw the same thing.

Cameras orbit a target: the eye sits at ``target + distance (cos p sin y, sin p, cos p cos y)``
(yaw y from +Z towards +X, pitch p up, degrees), looking at the target, +Y up, with an OpenGL
perspective projection (vertical field of view, near and far planes). The viewer's JavaScript
computes the same matrices from the same numbers.

The golf course is a height field (built in, or a 16-bit PNG / EXR height map), a clubhouse and
a wall (boxes), and trees as crossed, alpha-tested billboards; the water plane is y = 0. The sun's
shadow map is an orthographic view along ``-sun`` over the scene's bounding sphere.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError

__all__ = [
    "BALL_KINDS",
    "MAX_BALLS",
    "MAX_COLUMNS",
    "Camera",
    "Golf",
    "VERTEX_FLOATS",
    "balls",
    "box_triangles",
    "default_camera",
    "golf_course",
    "height_field",
    "shadow_view_projection",
]

#: Material kinds of a ball: its Lambertian lookup or the GGX split sum.
BALL_KINDS = {"sun-dim": 0, "shadow-dim": 1, "sh": 2, "ggx": 3}
#: Floats per vertex of the golf meshes: position 3, normal 3, albedo 3, uv 2, centre 3, kind 1.
VERTEX_FLOATS = 15
#: The most balls the shader takes (balls.frag's arrays).
MAX_BALLS = 32
#: The most roughness columns of the ball grid.
MAX_COLUMNS = 9


@dataclass(frozen=True)
class Camera:
    """An orbit camera (degrees, metres)."""

    target: tuple = (0.0, 0.0, 0.0)
    yaw: float = 0.0
    pitch: float = 0.0
    distance: float = 10.0
    fov: float = 40.0
    near: float = 0.1
    far: float = 1000.0

    def __post_init__(self) -> None:
        values = [*self.target, self.yaw, self.pitch, self.distance, self.fov, self.near, self.far]
        if len(self.target) != 3 or not all(math.isfinite(float(v)) for v in values):
            raise ArgumentError("a camera needs a 3-component target and finite numbers")
        if not (0 < self.fov < 180 and 0 < self.near < self.far and self.distance > 0):
            raise ArgumentError(
                "a camera needs 0 < fov < 180 degrees, 0 < near < far and distance > 0"
            )
        if abs(self.pitch) >= 90:
            raise ArgumentError(f"pitch must be within (-90, 90) degrees, got {self.pitch}")

    @property
    def eye(self) -> np.ndarray:
        """(3,) float64: where the camera is."""
        y, p = math.radians(self.yaw), math.radians(self.pitch)
        offset = np.array([math.cos(p) * math.sin(y), math.sin(p), math.cos(p) * math.cos(y)])
        return np.asarray(self.target, np.float64) + self.distance * offset

    def view(self) -> np.ndarray:
        """(4, 4) world -> camera (right-handed, looking down -Z)."""
        eye = self.eye
        forward = np.asarray(self.target, np.float64) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, [0.0, 1.0, 0.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, up, -forward
        view[:3, 3] = -view[:3, :3] @ eye
        return view

    def projection(self, aspect: float) -> np.ndarray:
        """(4, 4) OpenGL perspective projection for width / height ``aspect``."""
        f = 1.0 / math.tan(math.radians(self.fov) / 2)
        n, fa = self.near, self.far
        proj = np.zeros((4, 4))
        proj[0, 0], proj[1, 1] = f / aspect, f
        proj[2, 2], proj[2, 3] = (fa + n) / (n - fa), 2 * fa * n / (n - fa)
        proj[3, 2] = -1.0
        return proj

    def view_projection(self, aspect: float) -> np.ndarray:
        """(4, 4) world -> clip space."""
        return self.projection(aspect) @ self.view()

    def to_dict(self) -> dict:
        """The camera as JSON numbers."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}


def default_camera(scene: str) -> Camera:
    """The camera each scene opens with."""
    if scene == "balls":
        return Camera(target=(0.0, 0.4, 0.0), yaw=0.0, pitch=4.0, distance=26.0, fov=36.0)
    if scene == "sky":
        return Camera(target=(0.0, 0.0, 0.0), yaw=0.0, pitch=0.0, distance=1.0, fov=90.0)
    if scene == "water":
        return Camera(target=(18.0, 0.0, -8.0), yaw=-35.0, pitch=22.0, distance=48.0, fov=45.0)
    return Camera(target=(0.0, 2.0, 0.0), yaw=-30.0, pitch=28.0, distance=120.0, fov=45.0)


# -- material balls -------------------------------------------------------------------------------


def balls(
    levels: int,
    *,
    albedo: float = 0.8,
    base_colour: tuple = (0.95, 0.64, 0.54),
    metalness: tuple = (0.0, 0.5, 1.0),
) -> list[dict]:
    """The material balls: a top row of three white Lambertian balls (sun DIM, shadow DIM, SH
    irradiance), then a roughness x metalness grid of GGX balls: one row per ``metalness``, one
    column per level of a ``levels``-level chain at that level's roughness m / (levels - 1), so
    each ball reads exactly one baked level (at most :data:`MAX_COLUMNS` levels are shown, evenly
    spread, when the chain has more).

    Parameters
    ----------
    levels : int
        Levels of the specular chain.
    albedo : float
        The Lambertian balls' albedo.
    base_colour : (3,) float
        The GGX balls' base colour (linear): their diffuse albedo times ``1 - metalness`` and
        their F0 ``mix(0.04, base_colour, metalness)``.
    metalness : tuple of float in [0, 1]
        One row of GGX balls each, top to bottom.

    Returns
    -------
    list of dict
        ``centre`` (3,), ``radius``, ``kind`` (a :data:`BALL_KINDS` key), ``roughness``,
        ``metalness``, ``colour`` (3,), ``label``.
    """
    if levels < 1:
        raise ArgumentError("the specular chain has no levels")
    if not metalness or not all(0.0 <= float(m) <= 1.0 for m in metalness):
        raise ArgumentError(f"metalness values must lie in [0, 1], got {metalness!r}")
    colour = tuple(float(c) for c in base_colour)
    count = min(levels, MAX_COLUMNS)
    chosen = np.unique(np.round(np.linspace(0, levels - 1, count)).astype(int))
    if len(chosen) * len(metalness) + 3 > MAX_BALLS:
        raise ArgumentError(
            f"at most {MAX_BALLS - 3} GGX balls fit, asked for {len(chosen)} x {len(metalness)}"
        )
    out = []
    white = (float(albedo),) * 3
    for i, (kind, label) in enumerate(
        (("sun-dim", "sun DIM"), ("shadow-dim", "shadow DIM"), ("sh", "SH irradiance"))
    ):
        out.append(
            {
                "centre": ((i - 1) * 3.4, 4.3, 0.0),
                "radius": 1.4,
                "kind": kind,
                "roughness": 1.0,
                "metalness": 0.0,
                "colour": white,
                "label": label,
            }
        )
    spacing = 2.4
    for row, metal in enumerate(metalness):
        y = 1.3 - row * spacing
        for k, m in enumerate(chosen):
            r = float(m) / (levels - 1) if levels > 1 else 0.0
            x = (k - (len(chosen) - 1) / 2) * spacing
            out.append(
                {
                    "centre": (x, y, 0.0),
                    "radius": 1.0,
                    "kind": "ggx",
                    "roughness": r,
                    "metalness": float(metal),
                    "colour": colour,
                    "label": f"GGX roughness {r:.3g}, metalness {float(metal):.3g}",
                }
            )
    return out


# -- the golf course ------------------------------------------------------------------------------


def height_field(x: ArrayLike, z: ArrayLike) -> np.ndarray:
    """The built-in course's height (m) at world (x, z): rolling ground about 2 m above the
    water, a pond sinking to 4 m below it north-east of the centre, and a raised green."""
    x = np.asarray(x, np.float64)
    z = np.asarray(z, np.float64)
    h = 2.0 + 1.6 * np.sin(x / 19.0) * np.cos(z / 27.0) + 0.9 * np.sin((x + 0.6 * z) / 11.0)
    pond = np.exp(-((x - 22.0) ** 2 + (z + 12.0) ** 2) / (2 * 13.0**2))
    green = np.exp(-((x + 28.0) ** 2 + (z - 20.0) ** 2) / (2 * 9.0**2))
    return h - 7.5 * pond + 1.2 * green


@dataclass
class Golf:
    """The golf course's geometry: vertex data and the occluders it was built from."""

    #: (V, VERTEX_FLOATS) float32 triangle soup (every three rows a triangle).
    vertices: np.ndarray
    #: boxes as (min corner, max corner).
    boxes: list = field(default_factory=list)
    #: trees as (base position, height, width).
    trees: list = field(default_factory=list)
    #: the terrain's extent: [-half, half] in x and z.
    half: float = 80.0
    #: (centre, radius) of a sphere holding everything (for the shadow map).
    bounds: tuple = ((0.0, 0.0, 0.0), 1.0)


def _vertex(
    pos: np.ndarray,
    normal: ArrayLike,
    albedo: ArrayLike,
    uv: ArrayLike,
    centre: ArrayLike,
    kind: float,
) -> np.ndarray:
    n = len(pos)
    out = np.empty((n, VERTEX_FLOATS), np.float32)
    out[:, 0:3] = pos
    out[:, 3:6] = normal
    out[:, 6:9] = albedo
    out[:, 9:11] = uv
    out[:, 11:14] = centre
    out[:, 14] = kind
    return out


def _terrain(heights: np.ndarray, half: float, albedo: ArrayLike) -> np.ndarray:
    """Triangles of a height grid spanning [-half, half]^2 (row 0 at z = -half), with normals
    from central differences of the heights."""
    n = heights.shape[0]
    c = np.linspace(-half, half, n)
    x, z = np.meshgrid(c, c)
    step = c[1] - c[0]
    gz, gx = np.gradient(heights, step)
    normal = np.stack([-gx, np.ones_like(heights), -gz], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    pos = np.stack([x, heights, z], -1)
    # two triangles per cell, counter-clockwise seen from above (+Y)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    a = (j * n + i).ravel()
    b, c2, d = a + 1, a + n, a + n + 1
    tris = np.stack([a, c2, b, b, c2, d], -1).reshape(-1)
    pos, normal = pos.reshape(-1, 3)[tris], normal.reshape(-1, 3)[tris]
    colour = np.broadcast_to(np.asarray(albedo, np.float32), pos.shape)
    return _vertex(pos, normal, colour, np.zeros((len(tris), 2)), np.zeros((len(tris), 3)), 0)


def box_triangles(lo: ArrayLike, hi: ArrayLike, albedo: ArrayLike) -> np.ndarray:
    """The 12 outward-facing triangles of an axis-aligned box, as vertex rows."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    rows = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = np.where(sign > 0, hi, lo).astype(np.float64).copy()
                p[u] = (lo[u], hi[u])[a]
                p[v] = (lo[v], hi[v])[b]
                corners.append(p)
            normal = np.zeros(3)
            normal[axis] = sign
            quad = [corners[k] for k in (0, 1, 2, 0, 2, 3)]
            if sign < 0:  # keep the winding counter-clockwise seen from outside
                quad = [corners[k] for k in (0, 2, 1, 0, 3, 2)]
            rows.append(
                _vertex(
                    np.array(quad),
                    np.tile(normal, (6, 1)),
                    np.tile(albedo, (6, 1)),
                    np.zeros((6, 2)),
                    np.zeros((6, 3)),
                    0,
                )
            )
    return np.concatenate(rows)


def _tree(base: ArrayLike, height: float, width: float) -> np.ndarray:
    """Two crossed vertical quads (in the x and z planes) with the tree's uv: alpha-tested by
    the shader's silhouette; normals point out of each quad, the crown centre rides along."""
    base = np.asarray(base, np.float64)
    centre = base + [0.0, 0.64 * height, 0.0]
    rows = []
    for along, normal in (((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)), ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0))):
        side = np.asarray(along) * width / 2
        corners = [
            base - side,
            base + side,
            base + side + [0, height, 0],
            base - side + [0, height, 0],
        ]
        uvs = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        order = (0, 1, 2, 0, 2, 3)
        rows.append(
            _vertex(
                np.array([corners[k] for k in order]),
                np.tile(normal, (6, 1)),
                np.tile((0.16, 0.3, 0.09), (6, 1)),
                np.array([uvs[k] for k in order]),
                np.tile(centre, (6, 1)),
                1,
            )
        )
    return np.concatenate(rows)


#: the built-in course's boxes (clubhouse, a wall by the green) and trees (x, z, height, width).
COURSE_BOXES = (
    ((-40.0, -30.0), (12.0, 7.0, 9.0), (0.62, 0.58, 0.52)),
    ((-14.0, 28.0), (14.0, 3.0, 1.0), (0.55, 0.5, 0.45)),
)
COURSE_TREES = (
    (-8.0, -6.0, 11.0, 8.0),
    (4.0, 16.0, 9.0, 7.0),
    (40.0, 10.0, 12.0, 9.0),
    (-50.0, 8.0, 10.0, 8.0),
    (10.0, -40.0, 13.0, 9.0),
    (-22.0, 44.0, 9.0, 7.0),
    (46.0, -36.0, 11.0, 8.0),
    (-30.0, -4.0, 8.0, 6.0),
)
GRASS = (0.21, 0.36, 0.12)


def golf_course(
    heights: np.ndarray | None = None,
    *,
    size: float = 160.0,
    resolution: int = 129,
    occluders: bool = True,
) -> Golf:
    """The golf course's geometry.

    Parameters
    ----------
    heights : (N, N) array, optional
        Terrain heights in metres over the square (row 0 at z = -size/2, the far edge seen from
        +Z); default the built-in :func:`height_field` sampled ``resolution`` x ``resolution``.
    size : float
        Side of the terrain, metres.
    resolution : int
        Grid points per side of the built-in terrain.
    occluders : bool
        Place the clubhouse, the wall and the trees (on the ground where they stand).
    """
    half = size / 2
    if heights is None:
        c = np.linspace(-half, half, resolution)
        grid_x, grid_z = np.meshgrid(c, c)
        heights = height_field(grid_x, grid_z)
    heights = np.asarray(heights, np.float64)
    if heights.ndim != 2 or heights.shape[0] != heights.shape[1] or heights.shape[0] < 2:
        raise ArgumentError(f"a height map must be square (N, N), N >= 2; got {heights.shape}")
    if not np.isfinite(heights).all():
        raise ArgumentError("the height map holds NaN or infinite values")
    parts = [_terrain(heights, half, GRASS)]
    boxes, trees = [], []
    n = heights.shape[0]

    def ground(x: float, z: float) -> float:
        i = int(round((x + half) / size * (n - 1)))
        j = int(round((z + half) / size * (n - 1)))
        return float(heights[min(max(j, 0), n - 1), min(max(i, 0), n - 1)])

    if occluders:
        for (x, z), (w, h, d), albedo in COURSE_BOXES:
            y = min(ground(x + sx * w / 2, z + sz * d / 2) for sx in (-1, 1) for sz in (-1, 1))
            lo, hi = (x - w / 2, y - 0.5, z - d / 2), (x + w / 2, y + h, z + d / 2)
            boxes.append((lo, hi))
            parts.append(box_triangles(lo, hi, albedo))
        for x, z, h, w in COURSE_TREES:
            base = (x, ground(x, z) - 0.3, z)
            trees.append((base, h, w))
            parts.append(_tree(base, h, w))
    vertices = np.concatenate(parts)
    lo, hi = vertices[:, :3].min(axis=0), vertices[:, :3].max(axis=0)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo) / 2)
    return Golf(
        np.ascontiguousarray(vertices),
        boxes,
        trees,
        half,
        (tuple(float(v) for v in centre), radius),
    )


def shadow_view_projection(sun_direction: ArrayLike, bounds: tuple[ArrayLike, float]) -> np.ndarray:
    """(4, 4) world -> the sun's clip space: orthographic, looking along ``-sun_direction``,
    covering the sphere ``bounds = (centre, radius)``; depth 0 nearest the sun."""
    s = np.asarray(sun_direction, np.float64)
    s = s / np.linalg.norm(s)
    centre, radius = np.asarray(bounds[0], np.float64), float(bounds[1])
    eye = centre + s * 2 * radius
    forward = -s
    helper = [0.0, 1.0, 0.0] if abs(forward[1]) < 0.99 else [1.0, 0.0, 0.0]
    right = np.cross(forward, helper)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, up, -forward
    view[:3, 3] = -view[:3, :3] @ eye
    near, far = radius, 3 * radius
    proj = np.eye(4)
    proj[0, 0] = proj[1, 1] = 1 / radius
    proj[2, 2], proj[2, 3] = -2 / (far - near), -(far + near) / (far - near)
    return proj @ view
