"""``bakeshop water ocean``: tileable, time-looping ocean textures."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from bakeshop import progress
from bakeshop.cli._budget import check
from bakeshop.cli._numbers import Integer, Number
from bakeshop.cli._paths import OUT_DIR
from bakeshop.cli.water._group import CONTEXT, GATHER_LIMIT, water
from bakeshop.cli.water._sets import (
    TextureSet,
    _parse_outputs,
    _preview_indices,
    _write_previews,
)
from bakeshop.errors import ArgumentError, with_article
from bakeshop.resources import Cost, require, seconds_of

#: output texels per second per core of a whole run (synthesis, encoding, writing), per output:
#: measured at 4e5 (512^2 normal maps, a loaded machine), docs/hostile-input.md.
TEXELS_PER_SECOND = 5e5

if TYPE_CHECKING:
    from bakeshop.water.ocean import FieldName, Ocean
    from bakeshop.water.spectra import Spectrum

_OCEAN_OUTPUTS = ("normal", "height", "derivatives", "displacement", "foam")


@water.command(context_settings=CONTEXT)
@click.argument("out_dir", type=OUT_DIR)
@click.option("--spectrum", type=click.Choice(("jonswap", "pierson-moskowitz", "phillips",
              "tma")), default="jonswap", show_default=True,  # fmt: skip
              help="Sea state model: JONSWAP (fetch-limited, Hasselmann 1973), Pierson-Moskowitz "
              "(fully developed, 1964), TMA (JONSWAP in finite depth, Bouws 1985), Phillips "
              "(Tessendorf 2001).")  # fmt: skip
@click.option(
    "--wind",
    type=Number(0.1, 60),  # bakeshop.water.spectra.MIN_WIND_SPEED (not imported: start-up)
    default=10.0,
    show_default=True,
    metavar="M/S",
    help="Wind speed 10 m above the sea, m/s (the spectra's fetch and peak divide by it).",
)
@click.option("--direction", type=Number(-360, 360), default=0.0, show_default=True,
              metavar="DEG", help="Wind direction in the texture, degrees from +u towards +v "
              "(up the picture), in [-360, 360].")  # fmt: skip
@click.option("--fetch", type=Number(1, 1e7), default=100e3, show_default=True, metavar="M",
              help="Open water upwind, m, in [1, 1e7] (JONSWAP, TMA); long fetches are capped "
              "where the sea is fully developed.")  # fmt: skip
@click.option("--depth", type=Number(0.01, None, allow_inf=True), default=math.inf,
              metavar="M", help="Water depth, m, >= 0.01 (default: deep water). Changes the "
              "dispersion, and the spectrum for --spectrum tma.")  # fmt: skip
@click.option("--spreading", type=click.Choice(("mitsuyasu", "cos2s", "cos2")),
              default="mitsuyasu", show_default=True,
              help="Directional spreading: mitsuyasu (cos^2s with s from the frequency), "
              "cos2s (fixed --spread), cos2 (only with the wind).")  # fmt: skip
@click.option(
    "--spread",
    type=Number(0.1, 1000),
    default=10.0,
    show_default=True,
    metavar="S",
    help="s of cos2s spreading, in [0.1, 1000] (larger is narrower).",
)
@click.option("--cutoff", type=Number(0, 100), default=0.0, show_default=True, metavar="M",
              help="Small-wave cut-off length, m, in [0, 100]: damps waves shorter than about "
              "2 pi times this.")  # fmt: skip
@click.option(
    "--phillips-amplitude",
    type=Number(0, 1, low_open=True),
    default=1e-3,
    show_default=True,
    metavar="A",
    help="A of the Phillips spectrum, in (0, 1].",
)
@click.option(
    "--size",
    type=Number(0.01, 1e5),
    default=64.0,
    show_default=True,
    metavar="M",
    help="Patch (tile) side, m, in [0.01, 1e5]; with --cascades the largest one.",
)
@click.option(
    "--resolution",
    type=click.Choice(("32", "64", "128", "256", "512", "1024", "2048", "4096")),
    default="256",
    show_default=True,  # fmt: skip
    help="Texels per side (a power of two).",
)
@click.option("--period", type=Number(0.1, 3600), default=8.0, show_default=True, metavar="S",
              help="Loop period, s, in [0.1, 3600]: frequencies are rounded to whole turns per "
              "loop so the animation repeats exactly.")  # fmt: skip
@click.option("--frames", type=Integer(1, 4096), default=None, metavar="N",
              help="Frames per loop, 1 to 4096 (default: the fewest that do not alias the "
              "fastest wave, rounded up to a multiple of 8). Too few are refused with the "
              "reason unless --alias drop.")  # fmt: skip
@click.option("--alias", type=click.Choice(("refuse", "drop")), default="refuse",
              show_default=True, help="When --frames is too few: refuse, or drop the waves "
              "that would alias (the sidecar says how much variance they carried).")  # fmt: skip
@click.option("--choppiness", type=Number(0, 4), default=0.0, show_default=True, metavar="L",
              help="Horizontal displacement scale lambda, in [0, 4] (about 1 sharpens crests; "
              "the surface folds and foams where the Jacobian < 0).")  # fmt: skip
@click.option(
    "--seed",
    type=Integer(0, 2**63 - 1),
    default=0,
    show_default=True,
    help="Random waves; the same seed gives the same waves at any resolution.",
)
@click.option("--outputs", default="normal", show_default=True, metavar="LIST",
              help="Comma-separated: normal, height (m), derivatives (dh/dx, dh/dy in m/m), "
              "displacement (x, y, height in m), foam (coverage 0-1).")  # fmt: skip
@click.option("--normal-format", type=click.Choice(("png16", "png8", "xy8", "exr")),
              default="png16", show_default=True,
              help="png16/png8: RGB packed (n + 1) / 2; xy8: BC5-ready 8-bit x, y only (z "
              "rebuilt by the shader; as PNG the blue channel is 0.5); exr: float "
              "packed.")  # fmt: skip
@click.option("--height-format", type=click.Choice(("exr", "png16")), default="exr",
              show_default=True, help="exr: metres; png16: (h - low) / (high - low) with the "
              "range in the sidecar.")  # fmt: skip
@click.option("--layout", type=click.Choice(("frames", "atlas", "array")), default="frames",
              show_default=True, help="Numbered frames, one flipbook atlas per output "
              "(row-major from the top left), or one texture array per output (KTX2/DDS "
              "layers with mips).")  # fmt: skip
@click.option(
    "--container",
    type=click.Choice(("ktx2", "dds")),
    default="ktx2",
    show_default=True,
    help="Texture array container (--layout array).",
)
@click.option(
    "--columns",
    type=Integer(1, 256),
    default=None,
    help="Atlas frames per row, 1 to 256 (default: most square).",
)
@click.option(
    "--gutter",
    type=Integer(0, 64),
    default=0,
    show_default=True,
    help="Atlas: texels of wrapped border around each frame, 0 to 64.",
)
@click.option("--no-mips", is_flag=True, help="Texture arrays without mip levels.")
@click.option(
    "--foam-start",
    type=Number(-4, 4),
    default=0.5,
    show_default=True,
    metavar="J",
    help="Jacobian below which foam starts, in [-4, 4].",
)
@click.option(
    "--foam-full",
    type=Number(-4, 4),
    default=0.0,
    show_default=True,
    metavar="J",
    help="Jacobian at which foam covers the texel, below --foam-start.",
)
@click.option("--foam-decay", type=Number(0, 3600), default=0.0, show_default=True,
              metavar="S", help="Seconds for foam to fade to 1/e after the crest passes, in "
              "[0, 3600] (0: no lingering). Lingering foam loops too.")  # fmt: skip
@click.option("--cascades", type=Integer(1, 4), default=1, show_default=True,
              help="Patches of decreasing size (by --ratio) sharing the spectrum, written as "
              "separate sets NAME_c0, NAME_c1 ...; 1 to 4.")  # fmt: skip
@click.option(
    "--ratio",
    type=Number(1.5, 16),
    default=math.e,
    show_default=True,
    help="Size ratio between cascades, in [1.5, 16] (e avoids realigning).",
)
@click.option("--method", type=click.Choice(("fft", "gerstner")), default="fft",
              show_default=True, help="fft: every lattice wave; gerstner: the --waves strongest "
              "lattice waves summed directly (what a vertex shader can sum).")  # fmt: skip
@click.option(
    "--waves",
    type=Integer(1, 4096),
    default=64,
    show_default=True,
    help="Gerstner waves, 1 to 4096.",
)
@click.option("--name", default="ocean", show_default=True, help="Prefix of the file names.")
@click.option("--no-preview", is_flag=True, help="Skip the preview PNGs.")
def ocean(out_dir: Path, **o: Any) -> None:
    """Tileable, time-looping ocean textures from a wind-wave spectrum (FFT synthesis,
    Tessendorf 2001): normal-map sequences, heights, slopes, displacement and foam, as numbered
    frames, a flipbook atlas or a texture array, with a JSON sidecar (tile size in metres, loop
    period, frame rate, spectrum parameters, what the loop quantisation froze) and previews
    (a frame grid and a 2x2 tiling that shows there are no seams).

    Normal maps: tangent space, +X along u, +Y along v up (OpenGL; flip green for DirectX),
    packed (n + 1) / 2; the world patch is X along u, -Z along v.

    \b
    Example:
      bakeshop water ocean ocean/ --wind 8 --fetch 50000 --size 64 --resolution 256 \\
          --period 8 --choppiness 0.8 --outputs normal,height,foam
      bakeshop water ocean arrays/ --normal-format xy8 --layout array --container dds
      bakeshop water ocean sheet/ --resolution 128 --layout atlas --gutter 2 --frames 32 \\
          --alias drop
    """
    from bakeshop.io import write_json
    from bakeshop.water.cascades import cascade_sizes, cascades
    from bakeshop.water.ocean import ocean as make_ocean
    from bakeshop.water.spectra import Spectrum

    outputs = _parse_outputs(o["outputs"], _OCEAN_OUTPUTS)
    if o["foam_full"] >= o["foam_start"]:
        raise ArgumentError("--foam-full must be below --foam-start")
    if "foam" in outputs and o["choppiness"] == 0:
        raise ArgumentError("foam comes from folding crests: give --choppiness > 0")
    resolution = int(o["resolution"])
    spectrum = Spectrum(
        o["spectrum"],
        wind_speed=o["wind"],
        wind_direction=o["direction"],
        fetch=o["fetch"],
        depth=o["depth"],
        spreading=o["spreading"],
        spread=o["spread"],
        cutoff=o["cutoff"],
        amplitude=o["phillips_amplitude"],
    )
    if o["frames"]:
        _check_time(o["frames"], resolution, o["cascades"], outputs, out_dir)
    with progress.step("seeding the wave lattice"):
        if o["cascades"] > 1:
            sizes = cascade_sizes(o["size"], o["cascades"], ratio=o["ratio"])
            oceans = cascades(spectrum, sizes, resolution=resolution, seed=o["seed"],
                              loop_period=o["period"])  # fmt: skip
            names = [f"{o['name']}_c{c}" for c in range(len(oceans))]
        else:
            oceans = [make_ocean(spectrum, size=o["size"], resolution=resolution, seed=o["seed"],
                                 loop_period=o["period"])]  # fmt: skip
            names = [o["name"]]
    if not any(x.report["spectrum_variance"] > 0 for x in oceans):
        raise ArgumentError(
            f"no wave of this sea fits the tile: the lattice holds wavelengths from "
            f"{o['size']:g} m down to {2 * o['size'] / resolution:.3g} m and "
            f"{with_article(format(o['wind'], 'g'))} m/s "
            "wind puts no energy there; raise --wind, or lower --size or raise --resolution"
        )
    frames = o["frames"] or 8 * math.ceil(max(x.minimum_frames() for x in oceans) / 8)
    if not o["frames"]:  # the default: known once the lattice is seeded
        _check_time(frames, resolution, o["cascades"], outputs, out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    documents = []
    for oc, name in zip(oceans, names, strict=True):
        documents.append(_ocean_set(oc, name, out_dir, outputs, frames, spectrum, o))
    for doc, name in zip(documents, names, strict=True):
        write_json(out_dir / f"{name}.json", doc)
        click.echo(_ocean_summary(doc, name))


def _check_time(
    frames: int, resolution: int, cascades: int, outputs: Sequence[str], out_dir: Path
) -> None:
    """Refuse a run estimated to take longer than bakeshop --max-time, before it starts."""
    texels = cascades * frames * resolution**2
    what = f"{cascades * frames} ocean frames of {resolution}x{resolution}"
    work = Cost(0, texels, what, seconds_of(texels * len(outputs), TEXELS_PER_SECOND))
    check(work, out_dir, "--resolution", "--frames or --resolution")


def _ocean_set(
    oc: Ocean,
    name: str,
    out_dir: Path,
    outputs: Sequence[str],
    frames: int,
    spectrum: Spectrum,
    o: dict[str, Any],
) -> dict:
    from bakeshop.water.gerstner import gerstner_frames, gerstner_waves
    from bakeshop.water.ocean import fit_to_frames, ocean_frames
    from bakeshop.water.textures import (
        encode_heights,
        foam,
        pack_normals,
        persistent_foam,
        sidecar,
    )

    n = oc.resolution
    lam = o["choppiness"]
    fields: list[FieldName] = []
    if "normal" in outputs or not o["no_preview"]:
        fields.append("normal")
    if "height" in outputs or "displacement" in outputs:
        fields.append("height")
    if "derivatives" in outputs:
        fields.append("slope")
    if "displacement" in outputs:
        fields.append("displacement")
    if "foam" in outputs:
        fields.append("jacobian")
    channels = {"normal": 2 if o["normal_format"] == "xy8" else 3, "height": 1,
                "derivatives": 3, "displacement": 3, "foam": 1}  # fmt: skip
    if o["layout"] != "frames" or "foam" in outputs and o["foam_decay"] > 0:
        gathered = frames * n * n * 4 * sum(channels[x] for x in outputs)
        if gathered > GATHER_LIMIT:
            raise ArgumentError(
                f"{o['layout']} output of {frames} frames at {n}x{n} gathers "
                f"{gathered / 2**30:.1f} GiB in memory (limit {GATHER_LIMIT / 2**30:.0f} GiB); "
                "use --layout frames, fewer frames or a lower resolution"
            )
        what = f"gathering {frames} frames of {n}x{n} for the {o['layout']} output"
        require(Cost(gathered, frames, what))
    sink = TextureSet(out_dir, name, o["layout"], container=o["container"], columns=o["columns"],
                      gutter=o["gutter"], mips=not o["no_mips"], frames=frames)  # fmt: skip
    report = dict(oc.report)
    if o["method"] == "gerstner":
        waves = gerstner_waves(oc, o["waves"])
        report["gerstner_waves"] = waves.count
        report["gerstner_variance"] = float((waves.amplitude**2).sum() / 2)
        stream = gerstner_frames(waves, resolution=n, frames=frames, fields=fields,
                                 choppiness=lam)  # fmt: skip
    else:
        oc = fit_to_frames(oc, frames, alias=o["alias"])
        report = dict(oc.report)
        stream = ocean_frames(oc, frames=frames, fields=fields, choppiness=lam)
    preview_at = set(_preview_indices(frames).tolist())
    previews: dict[int, np.ndarray] = {}
    heights = []
    jacobians = []
    if o["method"] == "gerstner":
        batches = frames
    else:
        batches = math.ceil(frames / _batch_guess(n, fields, lam))
    for indices, batch in progress.track(stream, f"synthesising {name}", total=batches):
        if "normal" in batch:
            for i, f in enumerate(indices):
                if int(f) in preview_at:
                    previews[int(f)] = batch["normal"][i]
        if "normal" in outputs:
            fmt = o["normal_format"]
            packed = pack_normals(batch["normal"], channels="xy" if fmt == "xy8" else "xyz")
            if fmt == "xy8" and o["layout"] != "array":
                packed = np.concatenate([packed, np.full(packed.shape[:-1] + (1,), 0.5,
                                                         np.float32)], -1)  # fmt: skip
            sink.add("normal", packed, "png8" if fmt in ("png8", "xy8") else fmt, indices)
        if "height" in outputs:
            if o["height_format"] == "png16":
                heights.append(batch["height"].copy())
            else:
                sink.add("height", batch["height"][..., None], "exr", indices)
        if "derivatives" in outputs:
            s = batch["slope"]
            sink.add("derivatives", np.concatenate([s, np.zeros_like(s[..., :1])], -1), "exr",
                     indices)  # fmt: skip
        if "displacement" in outputs:
            d = batch["displacement"]
            sink.add("displacement", np.concatenate([d, batch["height"][..., None]], -1), "exr",
                     indices)  # fmt: skip
        if "foam" in outputs:
            cover = foam(batch["jacobian"], start=o["foam_start"], full=o["foam_full"])
            if o["foam_decay"] > 0:
                jacobians.append(cover)
            else:
                sink.add("foam", cover[..., None], "png8", indices)
    extra = {}
    if heights:
        h = np.concatenate(heights)
        low, high = float(h.min()), float(h.max())
        if high <= low:
            high = low + 1e-6
        sink.add("height", encode_heights(h, low, high)[..., None], "png16", np.arange(frames))
        extra["height_range_m"] = [low, high]
    if jacobians:
        lingering = persistent_foam(np.concatenate(jacobians), frame_time=o["period"] / frames,
                                    decay=o["foam_decay"])  # fmt: skip
        sink.add("foam", lingering[..., None], "png8", np.arange(frames))
    sink.finish()
    files = sink.files
    if not o["no_preview"] and previews:
        ordered = np.stack([previews[i] for i in sorted(previews)])
        files.append({"output": "preview", "files": _write_previews(out_dir, name, ordered,
                                                                    previews[0])})  # fmt: skip
    parameters = {
        "spectrum": spectrum.to_dict(),
        "seed": oc.seed,
        "choppiness": lam,
        "method": o["method"],
        "foam": {"start": o["foam_start"], "full": o["foam_full"], "decay_s": o["foam_decay"]}
        if "foam" in outputs else None,
        **extra,
    }  # fmt: skip
    return sidecar(kind="ocean", size=oc.size, resolution=n, loop_period=oc.loop_period,
                   frames=frames, files=files, parameters=parameters, report=report)  # fmt: skip


def _batch_guess(n: int, fields: Sequence[str], lam: float) -> int:
    from bakeshop.water.ocean import BATCH_BYTES, frame_bytes

    return max(1, BATCH_BYTES // frame_bytes(n, fields, lam, "float32"))


def _ocean_summary(doc: dict, name: str) -> str:
    r = doc["report"]
    share = (
        f"{100 * r['captured']:.1f}% of the spectrum's {r['spectrum_hs']:.3g} m in its band"
        if r["spectrum_variance"] > 0
        else "the spectrum holds nothing in its band"
    )
    lines = [
        f"{name}: {doc['resolution']}x{doc['resolution']} texels over {doc['tile_size_m']:g} m, "
        f"{doc['frames']} frames per {doc['loop_period_s']:g} s loop "
        f"({doc['frame_rate_hz']:.3g} frames/s)",
        f"  Hs {r['hs']:.3g} m on the lattice ({share}), {r['modes']} waves",
        f"  loop: {r['frozen_modes']} waves frozen ({100 * r['frozen_fraction']:.3f}% of the "
        f"variance), frequencies moved by up to {100 * r['max_frequency_shift']:.2f}%, "
        f"fastest wave {r['max_cycles']} turns per loop (>= {r['minimum_frames']} frames)",
    ]
    if "aliased_modes" in r:
        lines.append(
            f"  dropped {r['aliased_modes']} waves that {doc['frames']} frames would alias "
            f"({r['aliased_variance']:.3g} m^2 of variance)"
        )
    return "\n".join(lines)
