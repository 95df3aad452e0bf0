"""The operations a recipe step can run: bakeshop's own library functions, with the options
of the commands they mirror (same names, with ``_`` for ``-``, same defaults and ranges).

Each :class:`Operation` says which keys are paths (inputs, the output), which are options
(:class:`Option`: default, type, range or choices), which files a step reads, and how it runs
(``run(options) -> dict`` of facts for the manifest; every file is written through
:mod:`bakeshop.io`). ``version`` is the operation's algorithm version: raise it when the same
inputs and options would give different outputs, and every step of the operation is rebuilt.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import NoReturn

import numpy as np

from bakeshop.errors import ArgumentError, with_article
from bakeshop.sphere import FILE_LAYOUTS

__all__ = ["OPERATIONS", "Operation", "Option"]

_PROBE_LAYOUTS = ("auto", *FILE_LAYOUTS)

#: how a recipe reports a bad value: ``fail(reason)`` raises (naming the file and the table).
Fail = Callable[[str], NoReturn]
#: how a recipe resolves a path option: ``resolve(value, what)`` (relative to the recipe).
Resolve = Callable[[object, str], Path]


@dataclass(frozen=True)
class Option:
    """One option of an operation: ``kind`` is ``"int"``, ``"float"``, ``"str"``, ``"bool"``,
    ``"pair"`` (a number or two), or ``"tables"`` (a list of tables, checked by the
    operation); ``None`` as default means unset (TOML has no null: leave the key out)."""

    default: object
    kind: str
    low: float = -math.inf
    high: float = math.inf
    choices: tuple = ()
    help: str = ""

    def check(self, value: object, what: str, fail: Fail) -> object:
        """``value`` checked (``fail(reason)`` when it is out of its domain) and normalised."""
        if value is None and self.default is None:
            return None
        if self.kind == "bool":
            if not isinstance(value, bool):
                fail(f"{what} must be true or false, got {value!r}")
            return value
        if self.kind == "str":
            if not isinstance(value, str):
                fail(f"{what} must be a string, got {value!r}")
            if self.choices and value not in self.choices:
                fail(f"{what}: unknown value {value!r}; choose one of: {', '.join(self.choices)}")
            return value
        if self.kind == "tables":
            if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
                fail(f'{what} must be a list of tables, e.g. [{{ detail = "d.png" }}]')
            return value
        if self.kind == "pair":
            values = value if isinstance(value, list) else [value]
            if len(values) not in (1, 2):
                fail(f"{what} must be a number or two, got {value!r}")
            pair = [number(v, what, fail, self.low, self.high) for v in values]
            return [pair[0], pair[-1]]
        if self.kind == "int":
            if isinstance(value, bool) or not isinstance(value, int):
                fail(f"{what} must be an integer, got {value!r}")
            if self.choices and value not in self.choices:
                choices = ", ".join(map(str, self.choices))
                fail(f"{what} must be one of {choices}, got {_shown(value)}")
            if not self.low <= value <= self.high:  # exact, however long the integer
                fail(f"{what} must be in [{self.low}, {self.high}], got {_shown(value)}")
            return value
        return number(value, what, fail, self.low, self.high)


def _shown(value: object) -> str:
    """``value`` as an error message shows it: an integer too long to read by its length."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**20:
        digits = int(value.bit_length() * math.log10(2))  # the count, or one less
        return f"an integer of {digits + (abs(value) >= 10**digits)} digits"
    return repr(value)


def number(
    value: object, what: str, fail: Fail, low: float = -math.inf, high: float = math.inf
) -> float:
    """``value`` as a float in [low, high], or fail naming ``what`` and the range."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        fail(f"{what} must be a finite number, got {value!r}")
    if isinstance(value, float) and not math.isfinite(value):  # an int is finite, however long
        fail(f"{what} must be a finite number, got {value!r}")
    if not low <= value <= high:  # exact for an integer of any length
        fail(f"{what} must be in [{low:g}, {high:g}], got {_shown(value)}")
    if abs(value) > sys.float_info.max:
        biggest = sys.float_info.max
        fail(f"{what} must be a finite number (at most {biggest:g} in size), got {_shown(value)}")
    return float(value)


@dataclass(frozen=True)
class Operation:
    """A step kind. ``paths``: key -> ``"input"``, ``"input?"`` (optional) or ``"output"``;
    ``inputs(options)`` lists every file read (nested ones too); ``check(options, resolve,
    fail)`` applies the rules between options (``fail(reason)`` raises, naming the step;
    ``resolve(value, what)`` makes a recipe path absolute) and returns the values it
    normalised."""

    name: str
    version: int
    summary: str
    paths: dict
    options: dict
    run: Callable[[dict], dict]
    inputs: Callable[[dict], list] = field(default=None)  # type: ignore[assignment]
    check: Callable[..., dict] = field(default=lambda options, resolve, fail: {})

    def __post_init__(self) -> None:
        if self.inputs is None:
            keys = [k for k, v in self.paths.items() if v.startswith("input")]
            object.__setattr__(self, "inputs", lambda o: [o[k] for k in keys if o[k] is not None])

    @property
    def output_key(self) -> str:
        """The key of the path the step writes."""
        return next(k for k, v in self.paths.items() if v == "output")


# --- probe ---------------------------------------------------------------------------------------


def _probe_check(o: dict, resolve: Resolve, fail: Fail) -> dict:
    top = o["specular_size"].bit_length()
    if o["mips"] > top:
        size = with_article(o["specular_size"])
        fail(f"mips = {o['mips']}: {size}-texel cube has 1..{top} mip levels")
    return {}


def _probe(o: dict) -> dict:
    from bakeshop.image import srgb_decode
    from bakeshop.io import read_environment, stored_bits, write_image, write_json
    from bakeshop.io.environment import (
        LAYOUT_ENVMAPS,
        as_picture,
        is_cube,
        write_chain,
        write_environment,
        write_table,
    )
    from bakeshop.light import bake_probe, sh, sun_document

    out: Path = o["output"]
    fmt, container = o["format"], o["container"]
    (image, layout, _), meta = read_environment(
        o["input"], None if o["layout"] == "auto" else o["layout"], with_metadata=True
    )
    if layout in LAYOUT_ENVMAPS and fmt != "exr":
        raise ArgumentError(
            f'the probe is {layout}, which only an .exr can say: format = "exr"', o["input"]
        )
    notes = []
    if stored_bits(meta) is not None:
        if o["srgb_decode"]:
            image = np.array(image, np.float32)
            image[..., :3] = srgb_decode(image[..., :3])
        else:
            notes.append("integer input used as stored (display-encoded, not radiance)")
    if image.shape[-1] == 4 and fmt != "exr":
        if not np.all(image[..., 3] == 1):  # never a silent loss
            raise ArgumentError(
                f'the probe\'s alpha is not 1 everywhere and .{fmt} stores none: format = "exr" '
                "keeps it (or drop it with bakeshop convert --alpha drop)",
                o["input"],
            )
        image = image[..., :3]
        notes.append(f"alpha dropped: .{fmt} stores none (it was 1 everywhere)")
    baked = bake_probe(
        image, layout, cube_size=o["cube_size"], specular_size=o["specular_size"], mips=o["mips"]
    )
    out.mkdir(parents=True, exist_ok=True)
    write_environment(out / f"env_{{face}}.{fmt}", baked.cube, "cube")
    write_image(out / f"sun_dim.{fmt}", baked.sun_dim)
    write_image(out / f"shadow_dim.{fmt}", baked.shadow_dim)
    picture = "cross-vertical" if is_cube(layout) else layout
    assert baked.shadow_probe is not None  # bake_probe paints it unless told not to

    write_environment(out / f"shadow_probe.{fmt}", as_picture(baked.shadow_probe, layout), picture)
    write_json(out / "sun.json", sun_document(baked.sun))
    write_json(out / "sh.json", sh.to_document(baked.sh, irradiance=baked.sh_irradiance))
    write_chain(out / f"specular.{container}", baked.specular, convention="opengl")
    write_table(out / f"dfg.{container}", baked.dfg)
    return {
        "input_layout": layout,
        "cube": {
            "size": int(baked.cube.shape[1]),
            "faces": "OpenGL order +X -X +Y -Y +Z -Z",
            "convention": "opengl",
        },
        "dims": "latlong 360x180, E/pi (the radiance an albedo-1 Lambertian surface reflects)",
        "specular": {
            "levels": len(baked.specular),
            "size": int(baked.specular[0].shape[1]),
            "roughness": f"m / {len(baked.specular) - 1}",
        },
        "units": "radiance in the input's units",
        "sun": None if baked.sun is None else [float(v) for v in baked.sun.direction],
        "notes": notes,
    }


PROBE = Operation(
    name="probe",
    version=1,
    summary="everything the renderer needs from one probe, as 'bakeshop bake-probe' writes it "
    "(cube faces, DIM pair, shadow probe, sun.json, sh.json, GGX chain, DFG table)",
    paths={"input": "input", "output": "output"},
    options={
        "layout": Option(
            "auto",
            "str",
            choices=_PROBE_LAYOUTS,
            help="layout of the input (auto: an EXR's envmap, else its shape)",
        ),
        "cube_size": Option(None, "int", 1, 4096, help="face size of the environment cube"),
        "specular_size": Option(256, "int", 1, 4096, help="face size of the GGX chain"),
        "mips": Option(9, "int", 1, 14, help="levels of the GGX chain"),
        "format": Option("hdr", "str", choices=("hdr", "exr", "pfm", "tif")),
        "container": Option("dds", "str", choices=("dds", "ktx", "ktx2")),
        "srgb_decode": Option(False, "bool", help="linearise an 8/16-bit input"),
    },
    run=_probe,
    check=_probe_check,
)


# --- remap ---------------------------------------------------------------------------------------

_REMAP_TARGETS = tuple(n for n in _PROBE_LAYOUTS if n != "auto") + ("faces",)


def _remap_check(o: dict, resolve: Resolve, fail: Fail) -> dict:
    from bakeshop.io.containers import is_container

    target, to = o["output"], o["to"]
    if to is None:
        fail(f"needs to (the output layout): {', '.join(_REMAP_TARGETS)}")
    if to == "faces":
        if "{face}" not in target.name and not is_container(target):
            fail(
                "a cube is written as six files: put {face} in the output name "
                "(sky_{face}.exr), or write one .dds, .ktx or .ktx2 file"
            )
    elif "{face}" in target.name:
        fail(f'{{face}} in the output name needs to = "faces", not {to!r}')
    if to.startswith("openexr-") and target.suffix.lower() != ".exr":
        fail(f"{to} is OpenEXR's environment mapping: write it to an .exr file")
    return {}


def _remap(o: dict) -> dict:
    from bakeshop.io import read_environment
    from bakeshop.io.environment import write_environment
    from bakeshop.sphere import remap

    image, layout, _ = read_environment(o["input"], None if o["layout"] == "auto" else o["layout"])
    cube = o["to"] == "faces"
    out = remap(image, layout, "cube" if cube else o["to"], o["size"], filter=o["filter"])
    write_environment(o["output"], out, o["to"], convention=o["convention"])
    return {
        "from": layout,
        "to": o["to"],
        "shape": list(out.shape),
        "cube_convention": o["convention"] if cube else None,
    }


REMAP = Operation(
    name="remap",
    version=1,
    summary="a panorama converted between layouts (latlong, light probes, crosses, strips, "
    "octahedral, cube faces or a cube container), as 'bakeshop remap' does",
    paths={"input": "input", "output": "output"},
    options={
        "to": Option(None, "str", choices=_REMAP_TARGETS, help="the output layout (required)"),
        "layout": Option("auto", "str", choices=_PROBE_LAYOUTS, help="layout of the input"),
        "size": Option(
            None,
            "int",
            1,
            16384,
            help="latlong height, square edge or cube face "
            "edge (default: about as many texels as the input)",
        ),
        "filter": Option("auto", "str", choices=("auto", "area", "bilinear", "nearest")),
        "convention": Option(
            "opengl",
            "str",
            choices=("opengl", "vulkan", "directx"),
            help="cube faces as this engine loads them",
        ),
    },
    run=_remap,
    check=_remap_check,
)


# --- compress ------------------------------------------------------------------------------------


def _compress_check(o: dict, resolve: Resolve, fail: Fail) -> dict:
    from bakeshop.io.compress import QUALITIES

    base = o["format"].removesuffix("-srgb")
    if o["quality"] not in QUALITIES[base]:
        fail(
            f"{o['format']} has the quality profiles {', '.join(QUALITIES[base])}, not "
            f"{o['quality']!r}"
        )
    suffix = o["output"].suffix.lower()
    if suffix not in (".dds", ".ktx2", ".ktx"):
        fail(f"a compressed texture is written to .dds, .ktx2 or .ktx, not {o['output'].name}")
    if o["zstd"] and suffix != ".ktx2":
        fail("zstd supercompresses .ktx2 files only")
    return {}


def _compress(o: dict) -> dict:
    from bakeshop.io import read_container, read_image
    from bakeshop.io.compress.pipeline import box_mips, compress_levels, write_compressed
    from bakeshop.io.containers import is_container

    source = o["input"]
    if is_container(source):
        mips, meta = read_container(source)
        cube = bool(meta.get("cube"))
        if mips[0].shape[-1] == 4 and all(np.all(m[..., 3] == 1) for m in mips):
            mips = [m[..., :3] for m in mips]
    elif o["normals"]:
        from bakeshop.normals.encoding import read_normal_map

        cube = False
        mips = [read_normal_map(source, convention=o["convention"])]
    else:
        cube = False
        mips = [read_image(source)]
    if not cube and len(mips) == 1 and o["mips"]:
        mips = box_mips(mips[0], cube=False, normals=o["normals"])
    result = compress_levels(
        mips,
        o["format"],
        cube=cube,
        quality_profile=o["quality"],
        overflow=o["overflow"],
        normals=o["normals"],
        normal_convention=o["convention"],
    )
    write_compressed(o["output"], result, supercompression="zstd" if o["zstd"] else "none")
    return {
        "format": o["format"],
        "cube": cube,
        "levels": len(mips),
        "quality": result.report["quality"],
    }


def _block_formats() -> tuple:
    from bakeshop.io.compress import FORMATS

    return tuple(FORMATS)


COMPRESS = Operation(
    name="compress",
    version=1,
    summary="a texture or a mip chain block-compressed (BC6H, BC7, BC5, ...) with its quality "
    "sidecar, as 'bakeshop compress' writes it",
    paths={"input": "input", "output": "output"},
    options={
        "format": Option("bc6h", "str", choices=_block_formats()),
        "quality": Option(
            "fast",
            "str",
            choices=("ultrafast", "veryfast", "fast", "basic", "slow", "veryslow"),
            help="encoder profile (the ones the format has)",
        ),
        "overflow": Option("refuse", "str", choices=("refuse", "clamp")),
        "normals": Option(False, "bool", help="the input is a normal map"),
        "convention": Option("gl", "str", choices=("gl", "dx")),
        "mips": Option(True, "bool", help="give a single 2-D image its box-filtered mip chain"),
        "zstd": Option(False, "bool", help="Zstandard supercompression (.ktx2)"),
    },
    run=_compress,
    check=_compress_check,
)


# --- normals -------------------------------------------------------------------------------------

_LAYER = {
    "tile": Option(1.0, "pair", help="repetitions across the macro map (negative mirrors)"),
    "offset": Option(0.0, "pair", help="shift of the pattern, in tiles"),
    "rotate": Option(0.0, "float", -360, 360, help="degrees, counter-clockwise"),
    "strength": Option(1.0, "float", -16, 16, help="height scale of the detail"),
    "convention": Option(None, "str", choices=("gl", "dx")),
}


def _normals_check(o: dict, resolve: Resolve, fail: Fail) -> dict:
    if not o["layers"]:
        fail('normals needs layers = [{ detail = "FILE", ... }, ...]')
    layers = []
    for i, table in enumerate(o["layers"]):
        what = f"layers[{i}]"
        valid = ["detail", "mask", *_LAYER]
        for key in table:
            if key not in valid:
                fail(f"unknown key {key!r} in {what}; a layer takes: {', '.join(valid)}")
        if "detail" not in table:
            fail(f"{what} needs detail (a normal map)")
        layer = {
            k: spec.check(table.get(k, spec.default), f"{what} {k}", fail)
            for k, spec in _LAYER.items()
        }
        layer["detail"] = resolve(table["detail"], f"{what} detail")
        layer["mask"] = resolve(table["mask"], f"{what} mask") if "mask" in table else None
        layers.append(layer)
    return {"layers": layers}


def _normals_inputs(o: dict) -> list:
    found = [o["macro"]]
    for layer in o["layers"]:
        found += [p for p in (layer["detail"], layer["mask"]) if p is not None]
    return found


def _normals(o: dict) -> dict:
    from bakeshop.io import read_image, write_image
    from bakeshop.normals import DetailLayer, apply_layers, encode_normals, mask_weights
    from bakeshop.normals.encoding import read_normal_map

    base = read_normal_map(o["macro"], convention=o["convention"], encoding=o["encoding"])
    layers = []
    for s in o["layers"]:
        detail = read_normal_map(
            s["detail"], convention=s["convention"] or o["convention"], encoding=o["encoding"]
        )
        mask = None if s["mask"] is None else mask_weights(read_image(s["mask"]), base.shape[:2])
        layers.append(
            DetailLayer(
                detail,
                tile=tuple(s["tile"]),
                offset=tuple(s["offset"]),
                rotation=s["rotate"],
                strength=s["strength"],
                mask=mask,
            )
        )
    result = apply_layers(base, layers, method=o["method"])
    values = encode_normals(result, convention=o["convention"], encoding=o["encoding"])
    options = {"bits": o["bits"]} if o["output"].suffix.lower() == ".png" else {}
    write_image(o["output"], values.astype(np.float32, copy=False), **options)
    return {
        "size": list(result.shape[1::-1]),
        "method": o["method"],
        "convention": o["convention"],
        "encoding": o["encoding"],
        "layers": len(layers),
    }


def _methods() -> tuple:
    from bakeshop.normals.blend import METHODS

    return tuple(METHODS)


NORMALS = Operation(
    name="normals",
    version=1,
    summary="detail normal maps blended onto a macro normal map, as 'bakeshop normals combine' "
    "does (layers in order, each tiled, rotated, masked)",
    paths={"macro": "input", "output": "output"},
    options={
        "layers": Option(
            [],
            "tables",
            help="detail layers: detail, tile, offset, rotate, strength, mask, convention",
        ),
        "method": Option("exact", "str", choices=_methods()),
        "convention": Option("gl", "str", choices=("gl", "dx")),
        "encoding": Option("packed", "str", choices=("packed", "signed")),
        "bits": Option(16, "int", choices=(8, 16), help="PNG sample depth"),
    },
    run=_normals,
    inputs=_normals_inputs,
    check=_normals_check,
)


# --- water ---------------------------------------------------------------------------------------


def _water_check(o: dict, resolve: Resolve, fail: Fail) -> dict:
    if o["resolution"] & (o["resolution"] - 1):
        fail(f"resolution must be a power of two, got {o['resolution']}")
    name = o["name"]
    if not name or name in (".", "..") or any(c in name for c in "/\\\0"):
        fail(f"name must be a file name prefix (no folders, no NUL), got {name!r}")
    return {}


def _water(o: dict) -> dict:
    from bakeshop.io import write_image, write_json
    from bakeshop.water.ocean import fit_to_frames, ocean, ocean_frames
    from bakeshop.water.spectra import Spectrum
    from bakeshop.water.textures import pack_normals, sidecar

    spectrum = Spectrum(
        o["spectrum"],
        wind_speed=o["wind"],
        wind_direction=o["direction"],
        fetch=o["fetch"],
        depth=math.inf,
    )
    oc = ocean(
        spectrum,
        size=o["size"],
        resolution=o["resolution"],
        seed=o["seed"],
        loop_period=o["period"],
    )
    frames = o["frames"] or 8 * math.ceil(oc.minimum_frames() / 8)
    oc = fit_to_frames(oc, frames, alias="refuse")
    out: Path = o["output"]
    out.mkdir(parents=True, exist_ok=True)
    digits = max(4, len(str(frames - 1)))
    for indices, batch in ocean_frames(
        oc, frames=frames, fields=("normal",), choppiness=o["choppiness"]
    ):
        for i, f in enumerate(indices):
            path = out / f"{o['name']}_normal_{int(f):0{digits}d}.png"
            write_image(path, pack_normals(batch["normal"][i]), bits=16)
    files = [
        {
            "output": "normal",
            "layout": "frames",
            "format": "png16",
            "pattern": f"{o['name']}_normal_{'#' * digits}.png",
        }
    ]
    parameters = {
        "spectrum": spectrum.to_dict(),
        "seed": oc.seed,
        "choppiness": o["choppiness"],
        "method": "fft",
    }
    doc = sidecar(
        kind="ocean",
        size=oc.size,
        resolution=oc.resolution,
        loop_period=oc.loop_period,
        frames=frames,
        files=files,
        parameters=parameters,
        report=dict(oc.report),
    )
    write_json(out / f"{o['name']}.json", doc)
    return {
        "frames": frames,
        "tile_size_m": oc.size,
        "loop_period_s": oc.loop_period,
        "units": "SI; normals tangent space OpenGL, packed (n + 1) / 2",
    }


WATER = Operation(
    name="water",
    version=1,
    summary="a tileable, looping ocean normal-map sequence (16-bit PNG frames) and its JSON "
    "sidecar, as 'bakeshop water ocean' writes them",
    paths={"output": "output"},
    options={
        "spectrum": Option("jonswap", "str", choices=("jonswap", "pierson-moskowitz", "phillips")),
        "wind": Option(10.0, "float", 1e-3, 60, help="m/s at 10 m"),
        "direction": Option(0.0, "float", -360, 360, help="degrees from +u towards +v"),
        "fetch": Option(100e3, "float", 1, 1e7, help="m of open water upwind"),
        "size": Option(64.0, "float", 0.01, 1e5, help="patch side, m"),
        "resolution": Option(256, "int", 32, 4096, help="texels per side, a power of two"),
        "period": Option(8.0, "float", 0.1, 3600, help="loop period, s"),
        "frames": Option(
            None,
            "int",
            1,
            4096,
            help="frames per loop (default: the fewest "
            "that do not alias, rounded up to a multiple of 8)",
        ),
        "choppiness": Option(0.0, "float", 0, 4),
        "seed": Option(0, "int", 0, 2**63 - 1),
        "name": Option("ocean", "str", help="prefix of the file names"),
    },
    run=_water,
    check=_water_check,
)


#: operation name -> :class:`Operation`, in the order ``--help`` lists them.
OPERATIONS: dict[str, Operation] = {op.name: op for op in (PROBE, REMAP, COMPRESS, NORMALS, WATER)}
