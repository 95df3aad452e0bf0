"""``bakeshop water murk``: underwater murk constants and lookup tables."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from bakeshop.cli._numbers import Number, Size
from bakeshop.cli._paths import OUT_DIR
from bakeshop.cli.water._group import CONTEXT, water

if TYPE_CHECKING:
    from bakeshop.water.murk import Water


@water.command(context_settings=CONTEXT)
@click.argument("out_dir", type=OUT_DIR)
@click.option("--water-type", type=click.Choice(("pure", "I", "IA", "IB", "II", "III", "1C",
              "3C", "5C", "7C", "9C")), default="IB", show_default=True,  # fmt: skip
              help="Jerlov's water types (Jerlov 1976): I-III open ocean (clearest first), 1C-9C "
              "coastal; pure: pure sea water.")  # fmt: skip
@click.option("--visibility", type=Number(0.05, 200, low_open=True), default=None, metavar="M",
              help="Instead of the type's own clarity: the black-disk sighting range in metres "
              "(the water type sets the colour).")  # fmt: skip
@click.option(
    "--sun-zenith",
    type=Number(0, 80),
    default=30.0,
    show_default=True,
    metavar="DEG",
    help="Sun of Jerlov's Kd profiles, degrees, in [0, 80].",
)
@click.option(
    "--max-distance",
    type=Number(0.1, 1000),
    default=None,
    metavar="M",
    help="LUT path lengths up to this, m (default: where 1 % of the light is left).",
)
@click.option(
    "--max-depth",
    type=Number(0.1, 1000),
    default=20.0,
    show_default=True,
    metavar="M",
    help="LUT depths up to this, m.",
)
@click.option(
    "--lut-size",
    type=Size(4096, low=2),
    default="64x32",
    show_default=True,
    metavar="DxZ",
    help="LUT samples: path lengths x depths.",
)
@click.option("--name", default="murk", show_default=True, help="Prefix of the file names.")
@click.option("--no-preview", is_flag=True, help="Skip the preview PNG.")
def murk(out_dir: Path, **o: Any) -> None:
    """Underwater murk constants from measured water: per-channel beam attenuation (what fades
    the view, absorption + scattering) and diffuse attenuation (what dims the light with depth),
    for Unreal's Single Layer Water, Unity HDRP, Crest, a plain GLSL function and Source-style
    linear fog, plus transmittance and in-scatter lookup tables over (path length, depth).

    Writes NAME.json (all constants, SI units), NAME.glsl, NAME_transmittance.exr (1 row over
    path length), NAME_inscatter.exr (rows: depth, columns: path length) and a preview of a
    white and a grey target fading into the water.

    \b
    Example:
      bakeshop water murk murk/ --water-type IB
      bakeshop water murk lake/ --water-type 3C --visibility 4
    """
    from bakeshop.io import write_image, write_json, write_text
    from bakeshop.water import murk as mk

    size = o["lut_size"]
    distances, depths = size if isinstance(size, tuple) else (size, size)
    if o["visibility"] is not None:
        w = mk.from_visibility(o["visibility"], o["water_type"])
    else:
        w = mk.water(o["water_type"], sun_zenith=o["sun_zenith"])
    beam = mk.channel_coefficients(w)
    diffuse = mk.channel_coefficients(w, which="diffuse")
    reach = o["max_distance"] or mk._e_folding(w.attenuation, 3, 0.01)
    lut = mk.murk_lut(w, max_distance=reach, max_depth=o["max_depth"], distances=distances,
                      depths=depths)  # fmt: skip
    out_dir.mkdir(parents=True, exist_ok=True)
    name = o["name"]
    write_image(out_dir / f"{name}_transmittance.exr", lut["transmittance"][None],
                pixel_type="float")  # fmt: skip
    write_image(out_dir / f"{name}_inscatter.exr", lut["inscatter"], pixel_type="float")
    write_text(out_dir / f"{name}.glsl", mk.glsl_function(w))
    files = [f"{name}_transmittance.exr", f"{name}_inscatter.exr", f"{name}.glsl"]
    if not o["no_preview"]:
        files.append(_murk_preview(out_dir / f"{name}_preview.png", w, reach, o["max_depth"]))
    doc = {
        "generator": "bakeshop water murk",
        "water": w.name,
        "units": "metres, 1/m; colours linear sRGB; in-scatter per E(0)/pi",
        "chlorophyll_equivalent_mg_m3": w.chlorophyll,
        "visibility_m": mk.visibility(w),
        "beam_attenuation_per_m": beam["rgb"],
        "beam_e_folding_m": beam["e_folding"],
        "diffuse_attenuation_per_m": diffuse["rgb"],
        "diffuse_e_folding_m": diffuse["e_folding"],
        "exponential_fit_max_error": {"beam": beam["max_error"], "diffuse": diffuse["max_error"]},
        "engines": mk.engine_constants(w),
        "lut": {
            "transmittance": files[0],
            "inscatter": files[1],
            "max_distance_m": reach,
            "max_depth_m": o["max_depth"],
            "distances": distances,
            "depths": depths,
            "view": "horizontal at the row's depth, sun overhead",
        },  # fmt: skip
        "files": files,
    }
    write_json(out_dir / f"{name}.json", doc)
    r, g, b = beam["e_folding"]
    click.echo(
        f"{w.name}: line of sight fades to 1/e after {r:.2f} m (red), {g:.2f} m (green), "
        f"{b:.2f} m (blue); ambient light to 1/e at depths {diffuse['e_folding'][0]:.2f}, "
        f"{diffuse['e_folding'][1]:.2f}, {diffuse['e_folding'][2]:.2f} m; black-disk "
        f"visibility {mk.visibility(w):.1f} m"
    )


def _murk_preview(path: Path, w: Water, reach: float, max_depth: float) -> str:
    """White and 18 % grey targets seen through 0..reach metres of water at the surface (top
    half) and at max_depth (bottom half), sRGB."""
    from bakeshop.image import to_srgb8
    from bakeshop.io import write_image
    from bakeshop.water import murk as mk

    d = np.linspace(0, reach, 512)
    rows = []
    for depth in (0.0, max_depth):
        light = mk.depth_transmittance(w, depth)[:3]
        t = mk.transmittance(w, d)[:, :3]
        fog = mk.inscatter(w, d, depth)[:, :3]
        for albedo in (1.0, 0.18):
            rows.append(np.repeat((albedo * light * t + fog)[None], 48, axis=0))
    image = np.concatenate(rows).astype(np.float32)
    write_image(path, to_srgb8(image))
    return path.name
