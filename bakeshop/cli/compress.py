"""``bakeshop compress``: engine-ready compressed textures (BC6H, BC7, BC5, ...) with their quality.

Also the pieces ``bake-probe --compress`` and ``normals combine --compress`` reuse: the
``--quality/--overflow/--min-psnr`` options and :func:`write_levels`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click
import numpy as np

from bakeshop.cli._common import is_ldr
from bakeshop.cli._numbers import Integer, Number
from bakeshop.cli._paths import ENVIRONMENT, OUTPUT_CHAIN, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError, BakeshopError

if TYPE_CHECKING:
    from bakeshop.io.compress.texture import Overflow
    from bakeshop.light.probe import ProbeBake

F = TypeVar("F", bound=Callable[..., Any])

CONTEXT = {"max_content_width": 100}


_QUALITY_NAMES = ("ultrafast", "veryfast", "fast", "basic", "slow", "veryslow")


def quality_options(command: F) -> F:
    """The encoder options shared by every command that compresses: --quality, --overflow,
    --min-psnr, --zstd."""
    options = [
        click.option(
            "--quality",
            "quality_profile",
            type=click.Choice(_QUALITY_NAMES),
            default="fast",
            show_default=True,
            help="Encoder profile (ISPC's): BC6H veryfast..veryslow, BC7 ultrafast..slow; "
            "'fast' is within ~0.3 dB of the slowest at a tenth of the time.",
        ),
        click.option(
            "--overflow",
            type=click.Choice(("refuse", "clamp")),
            default="refuse",
            show_default=True,
            help="Values above 65504, which half floats (BC6H) cannot hold: refuse, or clamp "
            "them (a sun) and record it in the sidecar.",
        ),
        click.option(
            "--min-psnr",
            type=Number(0, 200),
            default=None,
            metavar="DB",
            help="Fail (no file written) when the quality of level 0 is below DB: "
            "multi-exposure PSNR for HDR, PSNR for 8-bit colour.",
        ),
        click.option(
            "--zstd",
            is_flag=True,
            help="KTX2 only: Zstandard supercompression of each level.",
        ),
    ]
    for option in reversed(options):
        command = option(command)
    return command


def describe_quality(q: dict) -> str:
    """One line of a quality report: multi-exposure PSNR, log2 RMSE or angular error."""

    def db(value: float) -> str:
        return "lossless" if value == float("inf") else f"{value:.2f} dB"

    if q["kind"] == "hdr":
        return (
            f"{db(q['mpsnr_db'])} multi-exposure PSNR (2^-4..2^4), "
            f"log2 RMSE {q['log2_rmse']:.4f} stops"
        )
    if q["kind"] == "ldr":
        return f"{db(q['psnr_db'])} PSNR"
    return (
        f"normals within {q['angle_mean_deg']:.3f} deg mean, {q['angle_p99_deg']:.2f} deg "
        f"99th percentile, {q['angle_max_deg']:.2f} deg max"
    )


def write_levels(
    target: Path,
    levels: list,
    name: str,
    *,
    cube: bool,
    quality_profile: str = "fast",
    overflow: Overflow = "refuse",
    min_psnr: float | None = None,
    max_angle: float | None = None,
    zstd: bool = False,
    normals: bool = False,
    normal_convention: str = "gl",
    rgbm_range: float = 8.0,
    extra: dict | None = None,
    source: Callable[[list, list], dict] | None = None,
) -> tuple[list[Path], dict]:
    """Compress ``levels`` (already in the engine's orientation) to ``target``, check the
    floors, write the file and its sidecar; returns (paths, report). Nothing is written when a
    floor fails.

    ``source(levels, decoded)`` measures the decoded levels against the source the levels
    were made from (:func:`bakeshop.engines.check_energy`): its figures go to the report's
    ``source``, and it raises when they fail."""
    from bakeshop import progress
    from bakeshop.io.compress.pipeline import compress_levels, write_compressed

    if zstd and target.suffix.lower() != ".ktx2":
        raise ArgumentError("--zstd supercompresses KTX2 files only", target)
    started = time.perf_counter()
    with progress.step(f"compressing {target.name}"):
        try:
            result = compress_levels(
                levels,
                name,
                cube=cube,
                quality_profile=quality_profile,
                overflow=overflow,
                normals=normals,
                normal_convention=normal_convention,
                rgbm_range=rgbm_range,
            )
        except BakeshopError as e:  # refused arguments, and memory that cannot fit
            if e.path is None:
                e.path = str(target)
            raise
    if source is not None:
        try:
            result.report["source"] = source(levels, result.decoded)
        except BakeshopError as e:
            e.path = str(target)
            raise
    q = result.report["quality"]
    if min_psnr is not None:
        if q["kind"] == "normal":
            raise ArgumentError("--min-psnr measures colour; use --max-angle for normal maps")
        value = q["mpsnr_db"] if q["kind"] == "hdr" else q["psnr_db"]
        if value < min_psnr:
            raise ArgumentError(
                f"quality {value:.2f} dB is below --min-psnr {min_psnr:g} dB; nothing written "
                "(try a slower --quality, or check for clamping)",
                target,
            )
    if max_angle is not None and q["kind"] == "normal" and q["angle_mean_deg"] > max_angle:
        raise ArgumentError(
            f"mean normal error {q['angle_mean_deg']:.3f} deg is above --max-angle "
            f"{max_angle:g}; nothing written",
            target,
        )
    result.report["seconds"] = time.perf_counter() - started
    paths = write_compressed(
        target, result, supercompression="zstd" if zstd else "none", extra=extra
    )
    return paths, result.report


def _summary(paths: list[Path], report: dict, levels: list[np.ndarray], cube: bool) -> None:
    level0 = levels[0]
    h, w = level0.shape[-3:-1]
    shape = f"cube 6x{w}x{h}" if cube else f"{w}x{h}"
    size = sum(p.stat().st_size for p in paths[:-1])
    profile = report.get("quality_profile")
    what = report["format"] + (f" ({profile})" if profile else "")
    click.echo(
        f"wrote {paths[0] if len(paths) == 2 else f'{len(paths) - 1} files ({paths[0].name} ...)'}"
        f": {what}, {shape}, {len(levels)} level(s), {size / 1e6:.2f} MB, "
        f"{report['seconds']:.2f} s"
    )
    click.echo(f"  quality (level 0): {describe_quality(report['quality'])}")
    overflow = report.get("overflow")
    if overflow and overflow["clamped_values"]:
        click.echo(
            f"  clamped {overflow['clamped_values']} values above 65504 (peak "
            f"{overflow['peak']:.6g}; {100 * overflow['clamped_energy']:.3g}% of the energy)"
        )
    if "packing" in report:
        p = report["packing"]
        if p["clipped_values"]:
            click.echo(f"  clipped {p['clipped_values']} values above {p['range']:g}")
        click.echo(f"  decode: {p['decode']}")
    click.echo(f"  sidecar: {paths[-1]}")


def _read(
    source: Path, src_layout: str | None, as_cube: bool, normal: bool, convention: str
) -> tuple[list[np.ndarray], bool, bool, str]:
    """(level list, cube?, environment?, what) of the input."""
    from bakeshop.io import check_input, read_container, read_environment
    from bakeshop.io.containers import is_container

    if normal:
        from bakeshop.normals.encoding import read_normal_map

        return [read_normal_map(source, convention=convention)], False, False, "normal map"
    if is_container(source) and source.is_file():
        mips, meta = read_container(source)
        cube = bool(meta.get("cube"))
        if cube and mips[0].shape[-1] == 4 and all(np.all(m[..., 3] == 1) for m in mips):
            mips = [m[..., :3] for m in mips]
        return mips, cube, cube, f"{meta['format']} {meta['stored']}"
    if "{face}" in str(source) or as_cube or src_layout is not None:
        image, layout, how = read_environment(source, src_layout)
        return [image], layout == "cube", True, f"{layout} ({how})"
    check_input(source)
    from bakeshop.io import read_image

    return [read_image(source)], False, False, "image"


def _as_cube(image: np.ndarray, layout: str, size: int | None, source: Path) -> np.ndarray:
    from bakeshop import sphere
    from bakeshop.io.compress.pipeline import compress_levels_cost
    from bakeshop.resources import Cost, require

    if layout == "cube":
        return image
    if size is None:
        texels = image.shape[0] * image.shape[1]
        size = int(min(2048, 2 ** round(np.log2(max(1.0, np.sqrt(texels / 6))))))
    # the whole chain of this cube and its compression, refused before the cube is made
    chain = [(6, max(1, size >> m), max(1, size >> m), 4) for m in range(size.bit_length())]
    cost = compress_levels_cost(chain, "a block format")
    held = sum(int(np.prod(shape)) for shape in chain) * 4
    require(Cost(cost.memory + held, cost.work, f"{cost.what} (a 6x{size}x{size} cube)"), source)
    return sphere.remap(image, layout, "cube", size=size, filter="auto")


@click.command("compress", context_settings=CONTEXT)
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@click.argument("target", metavar="OUT", type=OUTPUT_CHAIN)
@click.option(
    "--format",
    "fmt",
    metavar="FORMAT",
    help="bc6h (HDR), bc6h-signed, bc7 / bc7-srgb (colour), bc5 (normal maps, z rebuilt), bc4, "
    "bc1 / bc1-srgb, bc3 / bc3-srgb, or an 8-bit HDR packing: rgbd / rgbm (PNG) and "
    "rgbd-bc7 / rgbm-bc7. Default: the engine's, else bc6h for HDR input, bc5 with --normal, "
    "bc7-srgb for 8-bit pictures.",
)
@click.option(
    "--engine",
    type=click.Choice(("unity", "unreal", "godot", "three", "filament", "generic")),
    help="Write what this engine samples: its cube orientation or panorama, its normal-map "
    "convention and format (docs/engines.md).",
)
@click.option(
    "--cube",
    "as_cube",
    is_flag=True,
    help="IN is an environment: write it as a cube map (its layout is guessed from the shape, "
    "or given with --from).",
)
@click.option(
    "--from",
    "src_layout",
    metavar="LAYOUT",
    help="Layout of an environment IN (latlong, angular, cross-vertical, ...).",
)
@click.option(
    "--size",
    type=Integer(1, 4096),
    help="Face size of the cube made from a panorama (default: as many texels).",
)
@click.option(
    "--mips",
    type=Integer(1, 21),
    help="Levels to write (default: down to 1x1, or the chain a .dds/.ktx/.ktx2 IN holds).",
)
@click.option(
    "--normal", is_flag=True, help="IN is a tangent-space normal map (8/16-bit or float)."
)
@click.option(
    "--normal-convention",
    type=click.Choice(("gl", "dx")),
    default="gl",
    show_default=True,
    help="Green channel of the IN normal map (OUT uses the engine's, else the same).",
)
@click.option(
    "--max-angle",
    type=Number(0, 180),
    metavar="DEG",
    help="Normal maps: fail when the mean angular error exceeds DEG.",
)
@click.option(
    "--rgbm-range",
    type=Number(1, 65504),
    default=8.0,
    show_default=True,
    help="Largest value RGBM stores.",
)
@quality_options
def compress(
    source: Path,
    target: Path,
    fmt: str | None,
    engine: str | None,
    as_cube: bool,
    src_layout: str | None,
    size: int | None,
    mips: int | None,
    normal: bool,
    normal_convention: str,
    max_angle: float | None,
    rgbm_range: float,
    quality_profile: str,
    overflow: Overflow,
    min_psnr: float | None,
    zstd: bool,
) -> None:
    """Compress IN into the block format an engine samples, and measure what was lost.

    IN is an image (a texture, a normal map with --normal, an environment with --cube or
    --from), six {face} files, or a .dds/.ktx/.ktx2 cube map or chain (float or compressed).
    OUT is .dds (DX10 header), .ktx2 (optionally --zstd) or .ktx; .png for rgbd/rgbm, with
    {face} and {mip} in the name for cubes and chains. Every level is decoded again by
    bakeshop's own decoder and compared with the input: the numbers are printed and written to
    OUT.json beside the file, with the format, the clamping and the decode formula of RGBM/RGBD.

    \b
    Example:
      bakeshop compress probe.hdr probe.dds --cube --overflow clamp
      bakeshop compress specular.dds specular_bc6h.ktx2 --zstd --min-psnr 45
      bakeshop compress rifle_n.png rifle_n.dds --normal --engine unreal
      bakeshop compress probe.exr "env_{mip}_{face}.png" --cube --format rgbd --mips 1
      bakeshop compress probe.hdr sky.dds --from latlong --engine godot --overflow clamp
    """
    from bakeshop import engines
    from bakeshop.io.compress.decode import srgb_to_linear
    from bakeshop.io.compress.pipeline import OUTPUT_FORMATS, box_mips

    refuse_overwriting_inputs(target, source)
    preset = engines.engine(engine) if engine else None
    levels, cube, environment, what = _read(source, src_layout, as_cube, normal, normal_convention)
    if environment and not cube and (as_cube or "{face}" in str(source) or preset is not None):
        layout = src_layout
        if layout is None:
            from bakeshop.io.environment import guess_input_layout

            layout = guess_input_layout(levels[0], source)
        if preset is not None and preset.environment == "panorama":
            from bakeshop import sphere

            if layout != "latlong":
                levels = [sphere.remap(levels[0], layout, "latlong")]
        else:
            levels, cube = [_as_cube(levels[0], layout, size, source)], True
    elif preset is not None and preset.environment == "panorama" and cube:
        from bakeshop import sphere

        levels, cube = [sphere.remap(levels[0], "cube", "latlong")], False
    if fmt is None:
        if normal:
            fmt = preset.normal_format if preset else "bc5"
        elif preset is not None or environment or not is_ldr(source):
            fmt = "bc6h"
        else:
            fmt = "bc7-srgb"
    if fmt not in OUTPUT_FORMATS:
        raise ArgumentError(f"unknown --format {fmt!r}; choose one of: {', '.join(OUTPUT_FORMATS)}")
    out_convention = preset.normal_convention if (preset and normal) else normal_convention
    if preset is not None and environment and not cube:
        # roll level 0 before the chain is made: a half-turn roll of a 1-texel level is not
        # a whole number of texels, and box filtering commutes with the roll
        levels = [engines.panorama(level, preset) for level in levels]
    if mips is not None or len(levels) == 1:
        levels = box_mips(levels[0], cube=cube, levels=mips, normals=normal)
    if not normal and not environment and is_ldr(source) and fmt.endswith("-srgb"):
        # 8-bit pictures hold sRGB-encoded values; the encoder takes linear ones
        levels = [np.concatenate([srgb_to_linear(lv[..., :3]), lv[..., 3:]], -1) for lv in levels]
    extra = {"source": str(source), "input": what, "engine": engine}
    if preset is not None:
        if cube:
            levels = [engines.cube_faces(level, preset) for level in levels]
            extra["faces"] = f"{preset.title}: lookup {preset.lookup}"
        elif environment:
            extra["faces"] = (
                f"{preset.title} panorama (bakeshop latlong rolled by "
                f"{preset.panorama_shift:g} turn)"
            )
        wanted = "." + preset.container
        if target.suffix.lower() not in (wanted, ".png"):
            click.echo(
                f"warning: {preset.title} loads {wanted} files; writing {target.suffix} anyway",
                err=True,
            )
    elif cube:
        extra["faces"] = "OpenGL order and orientation"
    if normal:
        extra["normal_convention"] = out_convention
    paths, report = write_levels(
        target,
        levels,
        fmt,
        cube=cube,
        quality_profile=quality_profile,
        overflow=overflow,
        min_psnr=min_psnr,
        max_angle=max_angle,
        zstd=zstd,
        normals=normal,
        normal_convention=out_convention,
        rgbm_range=rgbm_range,
        extra=extra,
    )
    _summary(paths, report, levels, cube)


def bake_compressed(
    bake: ProbeBake,
    image: np.ndarray,
    layout: str,
    out_dir: Path,
    engine_name: str,
    *,
    specular_size: int,
    quality_profile: str = "fast",
    overflow: Overflow = "refuse",
    min_psnr: float | None = None,
    zstd: bool = False,
) -> list[tuple[Path, str, dict | None]]:
    """Write an engine's compressed files from a probe bake into ``out_dir / engine``: the
    environment (cube with box mips, or Godot's panorama), the GGX chain re-baked from
    ``image`` (the source probe, its sun included) with the roughness per level the engine's
    shader assumes, and its SH layout. Returns ``(path, what, report)`` rows; reports are None
    for JSON files.

    Every texture is decoded and measured against the source probe before it is written
    (:func:`bakeshop.engines.check_energy`): the environment's level 0 (box filtering does not
    keep a cube's energy below it) and every level of the chain; a file that misses the
    source's energy (a chain made from the probe without its sun) is refused."""
    from bakeshop import engines
    from bakeshop.io.compress.pipeline import box_mips, write_json
    from bakeshop.light import specular

    preset = engines.engine(engine_name)
    folder = out_dir / preset.name
    folder.mkdir(parents=True, exist_ok=True)

    reference = engines.SourceEnergy.of_bake(
        bake.sh, None if bake.sun is None else bake.sun.irradiance
    )

    def write(
        path: Path, levels: list, *, cube: bool, extra: dict, every_level: bool
    ) -> tuple[list[Path], dict]:
        def source(levels: list, decoded: list) -> dict:
            n = len(decoded) if every_level else 1
            return engines.check_energy(decoded[:n], reference, cube=cube, encoded=levels[:n])

        return write_levels(
            path,
            levels,
            "bc6h",
            cube=cube,
            extra=extra,
            quality_profile=quality_profile,
            overflow=overflow,
            min_psnr=min_psnr,
            zstd=zstd and preset.container == "ktx2",
            source=source,
        )

    rows: list[tuple[Path, str, dict | None]] = []
    extra = {"engine": preset.name, "engine_checked": preset.checked}
    env_path = folder / preset.files["environment"]
    if preset.environment == "panorama":
        from bakeshop import sphere

        pano = sphere.remap(bake.cube, "cube", "latlong", filter="area")
        levels = box_mips(engines.panorama(pano, preset), cube=False)
        paths, report = write(env_path, levels, cube=False, extra=extra, every_level=False)
        rows.append((paths[0], f"panorama {pano.shape[1]}x{pano.shape[0]}, BC6H", report))
    else:
        levels = [engines.cube_faces(m, preset) for m in box_mips(bake.cube, cube=True)]
        paths, report = write(env_path, levels, cube=True, extra=extra, every_level=False)
        rows.append((paths[0], f"environment 6x{bake.cube.shape[1]}, BC6H", report))
    if "specular" in preset.files:
        count = preset.specular_levels or len(bake.specular)
        count = min(count, specular_size.bit_length())
        rough = engines.mip_roughness(preset, count)
        assert rough is not None, "an engine that takes a GGX chain states its LOD mapping"
        if count == len(bake.specular) and np.allclose(rough, np.linspace(0, 1, count)):
            chain = bake.specular  # bakeshop's own chain already has this roughness per level
        else:
            chain = specular.prefilter_ggx(
                image, layout=layout, size=specular_size, mips=count, roughness=rough
            )
        chain = [engines.cube_faces(level, preset) for level in chain]
        spec_extra = {**extra, "roughness_per_level": [float(r) for r in rough]}
        paths, report = write(
            folder / preset.files["specular"], chain, cube=True, extra=spec_extra, every_level=True
        )
        rows.append((paths[0], f"GGX chain, {count} levels for the engine's LOD mapping", report))
    if preset.sh is not None:
        sh_path = folder / preset.files["sh"]
        write_json(sh_path, {"engine": preset.name, **engines.sh_export(bake.sh, preset)})
        rows.append((sh_path, f"SH, {preset.title} layout", None))
    return rows


def register(group: click.Group) -> None:
    """Add ``compress`` to the root command group."""
    group.add_command(compress)
