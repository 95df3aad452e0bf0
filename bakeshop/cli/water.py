"""``bakeshop water``: looping ocean textures, impact ripples and underwater murk constants."""

from __future__ import annotations

import math
from pathlib import Path

import click
import numpy as np

from bakeshop import progress
from bakeshop.cli._common import OUT_DIR, Integer, Number, Numbers, Size
from bakeshop.errors import ArgumentError
from bakeshop.resources import Cost, require

CONTEXT = {"max_content_width": 100}

#: Largest amount of frame data an atlas or array output may gather in memory, bytes.
GATHER_LIMIT = 4 << 30
#: Bytes per texel and frame that a ripple flipbook holds: the normals and their packed copy.
RIPPLE_TEXEL_BYTES = 24


@click.group(context_settings=CONTEXT)
def water():
    """Water textures an engine loads: tileable, time-looping ocean normal maps (with heights,
    slopes, displacement and foam), impact ripples, and underwater murk constants.

    Every command writes a JSON sidecar (units SI: metres, seconds) and preview PNGs.

    \b
    Example:
      bakeshop water ocean ocean/ --wind 8 --size 64 --resolution 256 --period 8
      bakeshop water ripples ripples/ --drop-diameter 0.004 --drop-speed 6
      bakeshop water murk murk/ --water-type IB
    """


def register(group: click.Group) -> None:
    """Add the ``water`` command group to the ``bakeshop`` command."""
    group.add_command(water)


# --- writing texture sets -------------------------------------------------------------------


def _write_png(path: Path, values, bits: int) -> None:
    from bakeshop.io import write_image

    write_image(path, values, bits=bits)


def _write_exr(path: Path, values) -> None:
    from bakeshop.io import write_image

    write_image(path, np.asarray(values, np.float32), pixel_type="float")


def _write_container(path: Path, layers: np.ndarray, dtype: str, kind: str, mips: bool) -> None:
    from bakeshop.io.dds import write_dds
    from bakeshop.io.ktx2 import write_ktx2
    from bakeshop.water.textures import box_mips, normal_mips

    side = layers.shape[1]
    if mips and side & (side - 1) == 0:
        if kind == "normal":
            # renormalised 2x2 means of the unit vectors, re-packed
            from bakeshop.water.textures import pack_normals

            chain = [pack_normals(m) for m in normal_mips(layers * 2 - 1)]
        elif kind == "normal_xy":
            from bakeshop.water.textures import pack_normals, unpack_normals

            chain = [pack_normals(m, channels="xy") for m in normal_mips(unpack_normals(
                layers, channels="xy").astype(np.float32))]  # fmt: skip
        else:
            chain = box_mips(layers)
    else:
        chain = [layers]
    writer = write_ktx2 if path.suffix == ".ktx2" else write_dds
    writer(path, chain, dtype=dtype, array=True)


class TextureSet:
    """Receives frames of named outputs in batches and writes them as numbered frames, a
    flipbook atlas or a texture array. Each output is (kind, channels, encoding)."""

    def __init__(self, out_dir: Path, name: str, layout: str, *, container: str, columns,
                 gutter: int, mips: bool, frames: int):  # fmt: skip
        self.out_dir, self.name, self.layout = out_dir, name, layout
        self.container, self.columns, self.gutter, self.mips = container, columns, gutter, mips
        self.frames = frames
        self.gathered: dict[str, list] = {}
        self.files: list[dict] = []
        self.formats: dict[str, str] = {}

    def frame_path(self, output: str, index: int, ext: str) -> Path:
        """The file of one frame of one output: ``NAME_OUTPUT_0001.EXT``."""
        digits = max(4, len(str(self.frames - 1)))
        return self.out_dir / f"{self.name}_{output}_{index:0{digits}d}{ext}"

    def add(self, output: str, values: np.ndarray, fmt: str, indices) -> None:
        """``values`` (B, N, N, C) float32 texel values ready to store (packed normals in
        [0, 1], metres for heights ...) for frames ``indices``; ``fmt`` is png8, png16, exr."""
        self.formats[output] = fmt
        if self.layout == "frames":
            ext = ".exr" if fmt == "exr" else ".png"
            for value, f in zip(values, indices, strict=True):
                path = self.frame_path(output, int(f), ext)
                if fmt == "exr":
                    _write_exr(path, value)
                else:
                    _write_png(path, value, 16 if fmt == "png16" else 8)
            return
        self.gathered.setdefault(output, []).append(values.astype(np.float32))

    def finish(self) -> None:
        """Write the gathered frames as flipbooks or arrays, and the sidecar."""
        from bakeshop.water.textures import flipbook

        if self.layout == "frames":
            digits = max(4, len(str(self.frames - 1)))
            for output, fmt in self.formats.items():
                ext = ".exr" if fmt == "exr" else ".png"
                pattern = f"{self.name}_{output}_{'#' * digits}{ext}"
                self.files.append({"output": output, "layout": "frames", "pattern": pattern,
                                   "format": fmt})  # fmt: skip
            return
        for output, parts in self.gathered.items():
            fmt = self.formats[output]
            stack = np.concatenate(parts).astype(np.float32)
            if self.layout == "atlas":
                atlas, layout = flipbook(stack, columns=self.columns, gutter=self.gutter)
                ext = ".exr" if fmt == "exr" else ".png"
                path = self.out_dir / f"{self.name}_{output}_atlas{ext}"
                if fmt == "exr":
                    _write_exr(path, atlas)
                else:
                    _write_png(path, atlas, 16 if fmt == "png16" else 8)
                self.files.append({"output": output, "layout": "atlas", "file": path.name,
                                   "format": fmt, "atlas": layout})  # fmt: skip
            else:
                path = self.out_dir / f"{self.name}_{output}.{self.container}"
                dtype = {"png8": "unorm8", "png16": "float16", "exr": "float32"}[fmt]
                if output == "normal" and fmt == "png8" and stack.shape[-1] == 2:
                    kind = "normal_xy"
                else:
                    kind = "normal" if output == "normal" else output
                if fmt == "png16" and output == "normal":
                    dtype = "float16"
                _write_container(path, stack, dtype, kind, self.mips)
                self.files.append({"output": output, "layout": "array", "file": path.name,
                                   "format": dtype, "layers": int(stack.shape[0]),
                                   "mips": bool(self.mips)})  # fmt: skip


def _write_previews(out_dir: Path, name: str, frames: np.ndarray, tiled: np.ndarray) -> list:
    """Shaded frame grid and the 2x2 tiling of frame 0, sRGB PNGs."""
    from bakeshop.image import to_srgb8
    from bakeshop.io import write_image
    from bakeshop.water.textures import grid, shade, tile

    shaded = np.stack([shade(f) for f in frames])
    grid_path = out_dir / f"{name}_preview_frames.png"
    tiled_path = out_dir / f"{name}_preview_tiled.png"
    write_image(grid_path, to_srgb8(grid(shaded, border=2)))
    write_image(tiled_path, to_srgb8(tile(shade(tiled), 2)))
    return [grid_path.name, tiled_path.name]


def _preview_indices(frames: int, count: int = 16) -> np.ndarray:
    return np.unique(np.linspace(0, frames - 1, min(count, frames)).round().astype(int))


# --- ocean ----------------------------------------------------------------------------------

_OCEAN_OUTPUTS = ("normal", "height", "derivatives", "displacement", "foam")


def _parse_outputs(text: str, allowed) -> list[str]:
    names = [t.strip() for t in text.split(",") if t.strip()]
    bad = [n for n in names if n not in allowed]
    if not names or bad:
        raise ArgumentError(
            f"unknown output {', '.join(map(repr, bad)) or repr(text)}; choose from: "
            + ", ".join(allowed)
        )
    return list(dict.fromkeys(names))


@water.command(context_settings=CONTEXT)
@click.argument("out_dir", type=OUT_DIR)
@click.option("--spectrum", type=click.Choice(("jonswap", "pierson-moskowitz", "phillips",
              "tma")), default="jonswap", show_default=True,  # fmt: skip
              help="Sea state model: JONSWAP (fetch-limited, Hasselmann 1973), Pierson-Moskowitz "
              "(fully developed, 1964), TMA (JONSWAP in finite depth, Bouws 1985), Phillips "
              "(Tessendorf 2001).")  # fmt: skip
@click.option(
    "--wind",
    type=Number(0.1, 60),
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
def ocean(out_dir: Path, **o):
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
    out_dir.mkdir(parents=True, exist_ok=True)
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
    needed = max(x.minimum_frames() for x in oceans)
    frames = o["frames"] or 8 * math.ceil(needed / 8)
    documents = []
    for oc, name in zip(oceans, names, strict=True):
        documents.append(_ocean_set(oc, name, out_dir, outputs, frames, spectrum, o))
    for doc, name in zip(documents, names, strict=True):
        write_json(out_dir / f"{name}.json", doc)
        click.echo(_ocean_summary(doc, name))


def _ocean_set(oc, name, out_dir, outputs, frames, spectrum, o) -> dict:
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
    fields = []
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


def _batch_guess(n, fields, lam) -> int:
    from bakeshop.water.ocean import BATCH_BYTES, frame_bytes

    return max(1, BATCH_BYTES // frame_bytes(n, fields, lam, "float32"))


def _ocean_summary(doc: dict, name: str) -> str:
    r = doc["report"]
    lines = [
        f"{name}: {doc['resolution']}x{doc['resolution']} texels over {doc['tile_size_m']:g} m, "
        f"{doc['frames']} frames per {doc['loop_period_s']:g} s loop "
        f"({doc['frame_rate_hz']:.3g} frames/s)",
        f"  Hs {r['hs']:.3f} m on the lattice ({100 * r['captured']:.1f}% of the spectrum's "
        f"{r['spectrum_hs']:.3f} m in its band), {r['modes']} waves",
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


# --- ripples --------------------------------------------------------------------------------

_RIPPLE_OUTPUTS = ("flipbook", "ring", "ring-texture", "rain")


def _parse_impacts(impacts) -> list[tuple[float, float, float]]:
    for x, y, t in impacts:
        if t < 0:
            raise ArgumentError(f"invalid impact {x:g},{y:g},{t:g}: its time T must be >= 0")
    return [tuple(impact) for impact in impacts]


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
@click.option("--container", type=click.Choice(("ktx2", "dds")), default="ktx2", show_default=True)
@click.option("--seed", type=Integer(0, 2**63 - 1), default=0, show_default=True)
@click.option("--name", default="ripples", show_default=True)
@click.option("--no-preview", is_flag=True)
def ripples(out_dir: Path, **o):
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
            f"the crater ({crater.width * 1000:.3g} mm wide) does not fit a {o['size']:g} m "
            "texture: use a larger --size or a smaller drop"
        )
    out_dir.mkdir(parents=True, exist_ok=True)
    frames = o["frames"]
    times = np.linspace(0, o["duration"], frames, endpoint=frames == 1)
    files: list = []
    previews = []
    fmt = o["normal_format"]
    params: dict = {"model": o["model"], "crater": crater.to_dict()}
    if o["model"] == "wave" and set(outputs) - {"flipbook"}:
        outputs = [x for x in outputs if x == "flipbook"] or ["flipbook"]
    if "flipbook" in outputs:
        # every frame's normals (float32) and their packed texels (at most float32 too) are held
        gathered = frames * n * n * RIPPLE_TEXEL_BYTES
        require(Cost(gathered, frames, f"a flipbook of {frames} frames of {n}x{n} normals"))
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


# --- murk -----------------------------------------------------------------------------------


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
@click.option("--name", default="murk", show_default=True)
@click.option("--no-preview", is_flag=True)
def murk(out_dir: Path, **o):
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


def _murk_preview(path: Path, w, reach: float, max_depth: float) -> str:
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
