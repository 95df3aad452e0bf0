"""The probe bake: everything a real-time renderer needs from one HDR light probe.

:func:`bake_probe` computes, from one environment in any layout:

- the environment as an OpenGL cube map (area-filtered),
- the DIM pair of :func:`bakeshop.light.dim_pair`: the sun DIM, the shadow DIM, the
  probe with its sun painted out, and the sun (direction, size, colour, irradiance),
- the environment's spherical-harmonic radiance coefficients (order 2 by default),
- the GGX prefiltered specular mip chain (:func:`bakeshop.light.specular.prefilter_ggx`),
- the split-sum DFG table (:func:`bakeshop.light.dfg.dfg_table`),

and :func:`contact_sheet` draws them side by side, tone-mapped, with labels. Arrays in, arrays
out: ``bakeshop bake-probe`` writes the files.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import with_article
from bakeshop.light import diffuse, sh, specular
from bakeshop.light.dfg import dfg_table, dfg_table_cost
from bakeshop.light.dims import dim_pair_cost, dim_pair_of
from bakeshop.light.sun import Removal, Sun
from bakeshop.resources import Cost, require
from bakeshop.sphere import check_environment, remap, remap_cost, valid_texels
from bakeshop.sphere import layout as layout_of

__all__ = ["ProbeBake", "bake_probe", "bake_probe_cost", "contact_sheet", "sheet_exposure"]

T = TypeVar("T")


class ProbeBake(NamedTuple):
    """What :func:`bake_probe` returns."""

    #: (6, S, S, C) float32: the environment as an OpenGL cube map.
    cube: np.ndarray
    #: DIM of the probe as photographed (E / pi), in the DIM layout (latlong 360x180).
    sun_dim: np.ndarray
    #: DIM of the probe without its sun.
    shadow_dim: np.ndarray
    #: the probe with the sun painted out, in the input's layout and shape (None when
    #: ``bake_probe(..., shadow_probe=False)``: then ``fill.paint`` paints it into any copy).
    shadow_probe: np.ndarray | None
    #: the sun, or None when the probe has none.
    sun: Sun | None
    #: ((order + 1)^2, C) float64: SH radiance coefficients (raw, unwindowed).
    sh: np.ndarray
    #: the DIM's SH coefficients as shown and exported: windowed just enough to be nowhere
    #: negative (:func:`bakeshop.light.sh.windowed_irradiance`), with the negative fractions.
    sh_irradiance: sh.IrradianceSH
    #: list of (6, S_m, S_m, C) float32: the GGX mip chain, roughness m / (mips - 1).
    specular: list
    #: (N, N, 2) float32: the DFG table (scale, bias on F0).
    dfg: np.ndarray
    #: the input's layout name.
    layout: str
    #: seconds spent in each step, by name.
    timings: dict
    #: how the sun is painted out of the probe (flat texel indices and their new colour
    #: values), or None when the probe has none.
    fill: Removal | None = None


def default_cube_size(shape: Sequence[int], layout: str) -> int:
    """The environment cube's face size when none is given: the power of two nearest to as many
    texels as the probe has (a quarter of a latlong's width), at most 2048."""
    lay = layout_of(layout)
    texels = valid_texels(lay, tuple(shape[: 3 if lay.cubic else 2]))
    return min(2048, layout_of("cube").default_size(texels))


def bake_probe_cost(
    shape: Sequence[int],
    layout: str,
    *,
    cube_size: int | None = None,
    dim_size: int | tuple[int, int] = (360, 180),
    specular_size: int = 256,
    mips: int = 9,
    itemsize: int = 4,
    shadow_probe: bool = True,
) -> Cost:
    """What :func:`bake_probe` of a probe of ``shape`` (with its channel axis) holds at its
    peak: what it keeps (the cube, the painted probe unless ``shadow_probe`` is False, the
    chain, the chain's cached area filter) plus the largest of its steps
    (:func:`~bakeshop.sphere.remap_cost`, :func:`~bakeshop.light.dims.dim_pair_cost`,
    :func:`~bakeshop.light.specular.prefilter_cost`, :func:`~bakeshop.light.dfg.dfg_table_cost`).
    ``work`` is the chain's (the longest step); ``seconds`` the steps' together."""
    from bakeshop.sphere import layout as get_layout

    lay = get_layout(layout)
    spatial = tuple(shape[: 3 if lay.cubic else 2])
    channels = int(shape[len(spatial)]) if len(shape) > len(spatial) else 1
    size = default_cube_size(shape, layout) if cube_size is None else cube_size
    texel = channels * itemsize
    painted = math.prod(spatial) if shadow_probe else 0  # the copy painted without the sun
    kept = (6 * size * size + painted + 8 * specular_size**2) * texel
    # the area filter matrix of the chain's source cube stays in the plan cache
    # (bakeshop.sphere.cache_info) while the environment cube's is built
    kept += remap_cost(
        lay, spatial, "cube", specular_size, filter="auto", channels=channels, itemsize=itemsize
    ).memory
    steps = [
        remap_cost(lay, spatial, "cube", size, filter="auto", channels=channels, itemsize=itemsize),
        dim_pair_cost(shape, layout, to="latlong", size=dim_size, painted=False),
        specular.prefilter_cost(shape, layout, size=specular_size, mips=mips, itemsize=itemsize),
        dfg_table_cost(),
    ]
    return Cost(
        kept + max(c.memory for c in steps),
        steps[2].work,
        f"the bake of {with_article(lay.name)} probe of {math.prod(spatial)} texels "
        f"(a 6x{size}x{size} "
        f"cube, {with_article(mips)}-level 6x{specular_size}x{specular_size} chain)",
        sum(c.seconds for c in steps),
    )


def bake_probe(
    image: ArrayLike,
    layout: str,
    *,
    cube_size: int | None = None,
    dim_size: int | tuple[int, int] = (360, 180),
    specular_size: int = 256,
    mips: int = 9,
    sh_order: int = 2,
    dfg_size: int = 128,
    shadow_probe: bool = True,
) -> ProbeBake:
    """Bake everything the renderer needs from one probe.

    The probe is read, never copied: its integrals run over strips of texels with their
    geometry computed per strip, the sun's fill is a list of texels, and the cubes of a large
    probe are area-filtered by supersampling, part by part (:func:`bakeshop.sphere.remap`).
    Beyond the probe, a bake holds its outputs (the environment cube, 12 bytes a texel in
    RGB, is the largest) and tens of megabytes of work.

    Parameters
    ----------
    image : array
        The probe (linear radiance) in ``layout``: ``(H, W, C)``, or ``(6, S, S, C)`` for a cube
        (see :func:`bakeshop.sphere.check_environment`: every output has the probe's channels).
    layout : str
        Its layout name (:data:`bakeshop.sphere.LAYOUT_NAMES`).
    cube_size : int, optional
        Face size of the environment cube. Default: the power of two nearest to a quarter of a
        latlong's width (as many texels as the probe has), at most 2048.
    dim_size : (int, int)
        Size of the two latlong DIMs.
    specular_size, mips : int
        Level 0 face size and number of levels of the GGX chain.
    sh_order : int
        Order of the SH coefficients (their irradiance is windowed with Sloan's minimal
        non-negative window, :func:`bakeshop.light.sh.minimal_window`).
    dfg_size : int
        Side of the DFG table.
    shadow_probe : bool
        Return the probe with its sun painted out as an array (a copy of the probe); False:
        ``shadow_probe`` is None and ``fill`` paints it where the caller wants it (into a
        copy: a probe painted in place has lost its sun for whatever reads it next).

    Returns
    -------
    ProbeBake
    """
    timings = {}

    def timed(name: str, fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
        started = time.perf_counter()
        result = fn(*args, **kwargs)
        timings[name] = time.perf_counter() - started
        return result

    env = check_environment(image, layout)
    image = env.image
    if cube_size is None:
        cube_size = default_cube_size(image.shape, layout)
    require(
        bake_probe_cost(
            image.shape,
            layout,
            cube_size=cube_size,
            dim_size=dim_size,
            specular_size=specular_size,
            mips=mips,
            itemsize=image.itemsize,
            shadow_probe=shadow_probe,
        )
    )
    lit, shadow, removal = timed("dims", dim_pair_of, env, to="latlong", size=dim_size)
    coeffs = timed("sh", diffuse.sh_coefficients, image, layout, order=sh_order)
    with progress.step("windowing the SH irradiance"):
        windowed = sh.windowed_irradiance(coeffs)
    chain = timed("specular", specular.prefilter_ggx, image, layout, size=specular_size, mips=mips)
    with progress.step("DFG table"):
        table = timed("dfg", dfg_table, dfg_size)
    # last: the largest output, so that no other step's work adds to it
    with progress.step("environment cube map"):
        cube = timed("cube", specular.source_cube, image, layout, size=cube_size)
    painted = None
    if shadow_probe:
        painted = image.copy()  # the fill is fractional: a float copy
        if removal is not None:
            removal.paint(painted)
        painted = env.shaped(painted)
    return ProbeBake(
        cube=env.shaped(cube),
        sun_dim=env.shaped(lit),
        shadow_dim=env.shaped(shadow),
        shadow_probe=painted,
        sun=None if removal is None else removal.sun,
        sh=coeffs,
        sh_irradiance=windowed,
        specular=[env.shaped(level) for level in chain],
        dfg=table,
        layout=layout,
        timings=timings,
        fill=removal,
    )


def _rgb(picture: np.ndarray) -> np.ndarray:
    """A picture's colour for display: ``(H, W, 3)`` (alpha dropped, grey repeated)."""
    a = np.asarray(picture)
    a = a[..., None] if a.ndim == 2 else a
    return np.ascontiguousarray(np.repeat(a, 3, axis=-1) if a.shape[-1] == 1 else a[..., :3])


def _to_latlong(image: np.ndarray, layout: str, height: int) -> np.ndarray:
    """An RGB latlong thumbnail of an environment."""
    from bakeshop.sphere import remap

    return _rgb(remap(image, layout, "latlong", height, filter="area"))


def _shadow_thumbnail(thumbnail: np.ndarray, bake: ProbeBake, probe: np.ndarray) -> np.ndarray:
    """The latlong thumbnail of the probe without its sun, from the probe's own: each texel the
    fill changed gives up its removed energy (radiance x solid angle) in the thumbnail texel
    its direction falls in (exact for a latlong reduced by an integer factor)."""
    from bakeshop.sphere import layout, texels_at

    if bake.fill is None:
        return thumbnail
    env = check_environment(probe, bake.layout)
    fill = bake.fill
    flat = env.image.reshape(-1, env.image.shape[-1])
    dirs, omega = texels_at(env.layout, env.image.shape[:-1], fill.index)
    removed = (flat[fill.index, : fill.filled.shape[1]] - fill.filled) * omega[:, None]
    lat = layout("latlong")
    shape = thumbnail.shape[:2]
    x, y = lat.coordinates(dirs, shape).T
    j = np.clip(y.astype(np.int64), 0, shape[0] - 1)
    i = np.clip(x.astype(np.int64), 0, shape[1] - 1)
    removed = removed / lat.solid_angles(shape)[j, i][:, None]
    out = thumbnail.astype(np.float64)
    np.subtract.at(out, (j, i), removed if removed.shape[1] == out.shape[2] else removed[:, :1])
    return np.maximum(out, 0).astype(np.float32)


def sheet_exposure(probe: np.ndarray, layout: str, *, thumb_height: int = 128) -> float:
    """The exposure (EV) of :func:`contact_sheet`: the probe's log-average luminance over the
    sphere (solid-angle weighted, texels that are exactly black left out) mapped to middle
    grey, metered on the sheet's latlong thumbnail."""
    from bakeshop.image import auto_exposure
    from bakeshop.sphere import layout as get_layout

    env = _to_latlong(probe, layout, thumb_height)
    lat = get_layout("latlong")
    weights = lat.solid_angles(env.shape[:2])
    lit = (env != 0).any(axis=-1)
    if lit.any():
        weights = np.where(lit, weights, 0.0)
    return auto_exposure(env, weights=weights)


def contact_sheet(
    bake: ProbeBake, probe: np.ndarray, *, thumb_height: int = 128, ev: float | None = None
) -> np.ndarray:
    """A labelled overview of a bake: ``(H, W, 3)`` uint8 sRGB (draw it, or save it as PNG).

    Every HDR panel is shown as a latlong, at one exposure (``ev``; default
    :func:`sheet_exposure`: the probe's log-average over the sphere mapped to middle grey)
    through the ACES filmic curve, so that panels compare: the probe, its cube faces (vertical
    cross, as HDRShop and cmft draw them), the probe without its sun, the sun and shadow DIMs,
    the irradiance of the SH coefficients (windowed as exported: ``bake.sh_irradiance``), each
    GGX level, and the DFG table (scale in red, bias in green, linear).

    Parameters
    ----------
    bake : ProbeBake
    probe : array
        The probe that was baked, in ``bake.layout``.
    thumb_height : int
        Height of each latlong thumbnail in pixels.
    ev : float, optional
        Exposure in stops.
    """
    from bakeshop.figures import new_figure, to_rgb
    from bakeshop.image import to_picture
    from bakeshop.sphere import layout

    env = _to_latlong(probe, bake.layout, thumb_height)
    if ev is None:
        ev = sheet_exposure(probe, bake.layout, thumb_height=thumb_height)
    cube_face = min(bake.cube.shape[1], max(1, thumb_height // 2))
    cross = remap(bake.cube, "cube", "cross-vertical", cube_face, filter="area")

    def show(img: np.ndarray) -> np.ndarray:
        return to_picture(_rgb(img), ev=ev, operator="aces").pixels

    dirs, _ = layout("latlong").directions(layout("latlong").shape(thumb_height))
    irr = bake.sh_irradiance
    sh_dim = sh.evaluate(irr.coefficients, dirs)
    sun = bake.sun
    sun_text = (
        "no sun" if sun is None else "sun at [" + ", ".join(f"{v:.2f}" for v in sun.direction) + "]"
    )
    panels = [
        (f"probe ({bake.layout})", show(env)),
        ("cube faces (vertical cross)", show(cross)),
        (f"shadow probe ({sun_text})", show(_shadow_thumbnail(env, bake, probe))),
        ("sun DIM (E/pi)", show(bake.sun_dim)),
        ("shadow DIM (E/pi)", show(bake.shadow_dim)),
        (
            f"SH irradiance (order {sh.order_of(bake.sh.shape[0])}, {irr.window.name} window)\n"
            f"< 0 on {100 * irr.negative:.1f}% (unwindowed {100 * irr.negative_raw:.1f}%)",
            show(sh_dim),
        ),
    ]
    levels = len(bake.specular)
    for m, level in enumerate(bake.specular):
        r = m / (levels - 1) if levels > 1 else 0.0
        thumb = _to_latlong(level, "cube", thumb_height)
        panels.append((f"GGX mip {m} ({level.shape[1]}px), roughness {r:.3g}", show(thumb)))
    rg = np.concatenate([bake.dfg, np.zeros_like(bake.dfg[..., :1])], axis=-1)
    panels.append(("DFG: scale (R), bias (G)", to_picture(rg, encoding="srgb").pixels))
    cols = 4
    rows = -(-len(panels) // cols)
    fig = new_figure(cols * 3.2, rows * 1.9, dpi=100)
    axes = fig.subplots(rows, cols)
    for ax in axes.flat:
        ax.axis("off")
    for ax, (title, img) in zip(axes.flat, panels, strict=False):
        ax.imshow(img, interpolation="nearest")
        ax.set_title(title, fontsize=8)
    fig.suptitle(f"bakeshop bake-probe (exposure {ev:+.2f} EV, ACES)", fontsize=10)
    fig.tight_layout()
    return to_rgb(fig)
