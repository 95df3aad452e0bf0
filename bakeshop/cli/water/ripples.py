"""``bakeshop water ripples``: impact ripples as flipbooks, ring tables and rain atlases."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import click
import numpy as np

from bakeshop import progress
from bakeshop.cli._numbers import Integer, Number, Numbers
from bakeshop.cli._paths import OUT_DIR
from bakeshop.cli.water._group import CONTEXT, RIPPLE_TEXEL_BYTES, water
from bakeshop.cli.water._sets import (
    TextureSet,
    _parse_outputs,
    _preview_indices,
    _write_previews,
)
from bakeshop.errors import ArgumentError, with_article
from bakeshop.resources import Cost, require

_RIPPLE_OUTPUTS = ("flipbook", "ring", "ring-texture", "rain")


def _parse_impacts(
    impacts: Sequence[tuple[float, float, float]],
) -> list[tuple[float, float, float]]:
    for x, y, t in impacts:
        if t < 0:
            raise ArgumentError(f"invalid impact {x:g},{y:g},{t:g}: its time T must be >= 0")
    return [(x, y, t) for x, y, t in impacts]


@water.command(context_settings=CONTEXT)
@click.argument("out_dir", type=OUT_DIR)
@click.option("--model", type=click.Choice(("analytic", "wave")), default="analytic",
              show_default=True, help="analytic: the exact linear ring of one drop "
              "(capillary-gravity dispersion, viscous decay); wave: a wave-equation height field "
              "with many impacts (tileable with --edges periodic).")  # fmt: skip
@click.option(
    "--drop-diameter",
    type=Number(1e-4, 0.05),
    default=0.004,
    show_default=True,
    metavar="M",
    help="Drop diameter, m, in [1e-4, 0.05].",
)
@click.option(
    "--drop-speed",
    type=Number(0, 20),
    default=6.0,
    show_default=True,
    metavar="M/S",
    help="Impact speed, m/s, in [0, 20] (raindrops: 2-9).",
)
@click.option(
    "--energy",
    type=Number(0, 100, low_open=True),
    default=None,
    metavar="J",
    help="Wave energy, J, in (0, 100]; overrides the drop's.",
)
@click.option(
    "--energy-fraction",
    type=Number(0, 1),
    default=0.05,
    show_default=True,
    help="Share of the drop's kinetic energy that becomes waves, in [0, 1] (a choice).",
)
@click.option(
    "--crater",
    type=Number(0.5, 20),
    default=2.0,
    show_default=True,
    help="Crater width in drop diameters, in [0.5, 20].",
)
@click.option(
    "--depth",
    type=Number(1e-3, None, allow_inf=True),
    default=math.inf,
    metavar="M",
    help="Water depth, m (default deep).",
)
@click.option(
    "--gravity",
    type=Number(0.1, 100),
    default=9.81,
    show_default=True,
    help="m/s^2, in [0.1, 100].",
)
@click.option(
    "--surface-tension",
    type=Number(0, 1),
    default=0.0728,
    show_default=True,
    help="N/m, in [0, 1] (0: gravity waves only).",
)
@click.option("--no-viscosity", is_flag=True, help="No viscous damping of the ring.")
@click.option(
    "--size",
    type=Number(1e-3, 100),
    default=0.25,
    show_default=True,
    metavar="M",
    help="Texture side, m, in [0.001, 100].",
)
@click.option(
    "--resolution",
    type=click.Choice(("64", "128", "256", "512", "1024")),
    default="256",
    show_default=True,
    help="Texels per side.",
)
@click.option(
    "--duration",
    type=Number(1e-3, 60),
    default=0.8,
    show_default=True,
    metavar="S",
    help="Seconds covered by the frames, in [0.001, 60].",
)
@click.option(
    "--frames", type=Integer(1, 1024), default=32, show_default=True, help="Frames, 1 to 1024."
)
@click.option("--outputs", default="flipbook,ring,ring-texture,rain", show_default=True,
              metavar="LIST", help="flipbook: normal-map frames; ring: the (time, radius) "
              "lookup table of one ring, for shaders; ring-texture: one ring with time in a "
              "channel (direction, arrival time, strength); rain: a tileable atlas of drops "
              "with random phases (analytic model).")  # fmt: skip
@click.option(
    "--rain-cells",
    type=Integer(1, 64),
    default=4,
    show_default=True,
    help="Rain atlas: drops per side, 1 to 64 (must divide the resolution).",
)
@click.option(
    "--speed",
    type=Number(0.01, 100),
    default=None,
    metavar="M/S",
    help="Wave model: wave speed c, m/s (default: the ring's front speed).",
)
@click.option(
    "--damping",
    type=Number(0, 100),
    default=0.5,
    show_default=True,
    metavar="1/S",
    help="Wave model: damping rate of the velocity, 1/s, in [0, 100].",
)
@click.option(
    "--edges",
    type=click.Choice(("periodic", "reflect", "absorb")),
    default="periodic",
    show_default=True,
    help="Wave model: edge condition.",
)
@click.option(
    "--courant",
    type=Number(0.01, 0.866),
    default=0.5,
    show_default=True,
    help="Wave model: c dt / dx, in [0.01, 0.866] (the stability limit).",
)
@click.option(
    "--impact",
    "impacts",
    multiple=True,
    type=Numbers(-1e5, 1e5, count=3),
    metavar="X,Y,T",
    help="Wave model: an impact at (X, Y) m at T s (T >= 0); repeatable.",
)
@click.option(
    "--rain",
    type=Integer(0, 10000),
    default=8,
    show_default=True,
    help="Wave model: random impacts over the duration, 0 to 10000.",
)
@click.option(
    "--normal-format",
    type=click.Choice(("png16", "png8", "exr")),
    default="png16",
    show_default=True,
    help="Normal maps: packed (n + 1) / 2.",
)
@click.option("--layout", type=click.Choice(("frames", "atlas", "array")), default="frames",
              show_default=True, help="Flipbook as numbered frames, one atlas, or a texture "
              "array.")  # fmt: skip
@click.option("--container", type=click.Choice(("ktx2", "dds")), default="ktx2", show_default=True,
              help="Texture array container (--layout array).")  # fmt: skip
@click.option("--seed", type=Integer(0, 2**63 - 1), default=0, show_default=True,
              help="Random drops: the rain atlas's phases and the wave model's --rain "
              "impacts; the same seed gives the same drops.")  # fmt: skip
@click.option("--name", default="ripples", show_default=True, help="Prefix of the file names.")
@click.option("--no-preview", is_flag=True, help="Skip the preview PNGs.")
def ripples(out_dir: Path, **o: Any) -> None:
    """Impact ripples: the exact ring of a drop (front at the group velocity, energy spread over
    the circle, viscous decay) as a normal-map flipbook, a (time, radius) lookup table that a
    shader animates any number of drops with, and a tileable rain atlas of drops with random
    phases; or a wave-equation field with many impacts. Physical inputs in SI units.

    \b
    Example:
      bakeshop water ripples drop/ --drop-diameter 0.004 --drop-speed 6 --size 0.25
      bakeshop water ripples puddle/ --model wave --size 2 --resolution 512 --rain 40 \\
          --duration 4 --frames 64 --layout atlas
    """
    from bakeshop.io import write_image, write_json
    from bakeshop.water import ripples as rp
    from bakeshop.water.textures import pack_normals, sidecar

    outputs = _parse_outputs(o["outputs"], _RIPPLE_OUTPUTS)
    n = int(o["resolution"])
    water_kw = dict(depth=o["depth"], gravity=o["gravity"], surface_tension=o["surface_tension"],
                    viscosity=0.0 if o["no_viscosity"] else 1e-6)  # fmt: skip
    crater = rp.drop_crater(drop_diameter=o["drop_diameter"], drop_speed=o["drop_speed"],
                            energy_fraction=o["energy_fraction"], width_factor=o["crater"],
                            energy=o["energy"], **water_kw)  # fmt: skip
    if crater.width * 4 > o["size"]:
        raise ArgumentError(
            f"the crater ({crater.width * 1000:.3g} mm wide) does not fit "
            f"{with_article(format(o['size'], 'g'))} m "
            "texture: use a larger --size or a smaller drop"
        )
    frames = o["frames"]
    times = np.linspace(0, o["duration"], frames, endpoint=frames == 1)
    files: list = []
    previews: list[np.ndarray] | np.ndarray = []
    fmt = o["normal_format"]
    params: dict = {"model": o["model"], "crater": crater.to_dict()}
    if o["model"] == "wave" and set(outputs) - {"flipbook"}:
        outputs = [x for x in outputs if x == "flipbook"] or ["flipbook"]
    if "flipbook" in outputs:
        # every frame's normals (float32) and their packed texels (at most float32 too) are held
        gathered = frames * n * n * RIPPLE_TEXEL_BYTES
        require(Cost(gathered, frames, f"a flipbook of {frames} frames of {n}x{n} normals"))
    out_dir.mkdir(parents=True, exist_ok=True)  # after every check: a refusal creates nothing
    if "flipbook" in outputs:
        sink = TextureSet(out_dir, o["name"], o["layout"], container=o["container"],
                          columns=None, gutter=0, mips=True, frames=frames)  # fmt: skip
        if o["model"] == "analytic":
            with progress.step("integrating the ring"):
                normals = rp.ring_normals(crater, size=o["size"], resolution=n, times=times,
                                          damping=not o["no_viscosity"])  # fmt: skip
            sink.add("normal", pack_normals(normals), fmt, np.arange(frames))
            previews = normals
        else:
            speed = o["speed"] or crater.front_speed
            dx = o["size"] / n
            sim = rp.WaveEquation(n, o["size"], speed, dt=o["courant"] * dx / speed,
                                  damping=o["damping"], edges=o["edges"])  # fmt: skip
            rng = np.random.default_rng(o["seed"])
            hits = _parse_impacts(o["impacts"]) + [
                (float(x), float(y), float(t))
                for x, y, t in zip(rng.uniform(0, o["size"], o["rain"]),
                                   rng.uniform(0, o["size"], o["rain"]),
                                   rng.uniform(0, o["duration"], o["rain"]), strict=True)
            ]  # fmt: skip
            impacts = [rp.Impact(x, y, t, crater.amplitude, max(crater.width, 2 * dx))
                       for x, y, t in hits]  # fmt: skip
            step = o["duration"] / max(frames, 1)
            steps = max(1, round(step / sim.dt))
            params["wave"] = {"speed_m_s": speed, "dt_s": sim.dt, "courant": sim.courant,
                              "damping_per_s": o["damping"], "edges": o["edges"],
                              "steps_per_frame": steps, "impacts": hits}  # fmt: skip
            stack = []
            for i, (_, h) in enumerate(progress.track(
                    rp.simulate(sim, frames=frames, steps_per_frame=steps, impacts=impacts),
                    "simulating", total=frames)):  # fmt: skip
                normals = rp.height_normals(h, dx, periodic=o["edges"] == "periodic")
                sink.add("normal", pack_normals(normals[None]), fmt, [i])
                stack.append(normals)
            previews = np.stack(stack)
        sink.finish()
        files += sink.files
    if "ring" in outputs:
        radius = o["size"] / 2
        with progress.step("tabulating the ring"):
            lut = rp.ring_lut(crater, radius=radius, duration=o["duration"], radii=n, steps=n,
                              damping=not o["no_viscosity"])  # fmt: skip
        path = out_dir / f"{o['name']}_ring_lut.exr"
        write_image(path, lut, pixel_type="float")
        files.append({"output": "ring", "file": path.name, "rows": "time 0 (top) to duration",
                      "columns": "radius 0 to radius", "radius_m": radius,
                      "duration_s": o["duration"],
                      "channels": "R height (m), G d height / d r (m/m), B 0"})  # fmt: skip
    if "ring-texture" in outputs:
        with progress.step("measuring the ring's arrival times"):
            texture, info = rp.ring_texture(crater, size=o["size"], resolution=n,
                                            duration=o["duration"],
                                            damping=not o["no_viscosity"])  # fmt: skip
        path = out_dir / f"{o['name']}_ring_texture.png"
        write_image(path, texture, bits=16)
        channels = (
            "RG outward direction packed (d + 1) / 2; B time of the strongest slope / "
            "duration; A strongest |d eta / dr| / slope_max"
        )
        files.append({"output": "ring-texture", "file": path.name, **info, "channels": channels})
    if "rain" in outputs:
        atlas = rp.rain_atlas(resolution=n, cells=o["rain_cells"], seed=o["seed"])
        path = out_dir / f"{o['name']}_rain_atlas.png"
        write_image(path, atlas, bits=16)
        files.append({"output": "rain", "file": path.name, "cells": o["rain_cells"],
                      "cell_size_m": o["size"] / o["rain_cells"], "margin_cells": 0.35,
                      "channels": "RG offset from the drop centre in cells, packed (d + 1) / 2; "
                      "B phase in [0, 1); A 1 within the drop's reach"})  # fmt: skip
    if not o["no_preview"] and len(previews):
        picks = previews[_preview_indices(len(previews))]
        pictures = _write_previews(out_dir, o["name"], picks, previews[-1])
        files.append({"output": "preview", "files": pictures})
    doc = sidecar(kind="ripples", size=o["size"], resolution=n, loop_period=None, frames=frames,
                  files=files, parameters=params)  # fmt: skip
    doc["duration_s"] = o["duration"]
    write_json(out_dir / f"{o['name']}.json", doc)
    click.echo(
        f"{o['name']}: crater {crater.amplitude * 1000:.3g} mm deep, {crater.width * 1000:.3g} mm "
        f"wide ({crater.energy * 1000:.3g} mJ), ring front {crater.front_speed:.3f} m/s; "
        f"{frames} frames over {o['duration']:g} s on {o['size']:g} m"
    )
