"""``bakeshop bake-probe``: everything the renderer needs from one probe."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING

import click

from bakeshop.cli._budget import check
from bakeshop.cli._common import (
    alpha_option,
    fit_alpha,
    float_format_option,
    linearise,
    out_dir_option,
    srgb_decode_option,
)
from bakeshop.cli._numbers import Integer
from bakeshop.cli._paths import ENVIRONMENT, refuse_overwriting_inputs
from bakeshop.cli._probe import chain_mips, check_picture_format, picture_layout, read_probe
from bakeshop.cli.compress import bake_compressed, describe_quality, quality_options
from bakeshop.engines import ENGINES
from bakeshop.io.environment import (
    as_picture,
    describe,
    write_chain,
    write_environment,
    write_table,
)

if TYPE_CHECKING:
    from bakeshop.io.compress.texture import Overflow

_from = click.option(
    "--from",
    "src_layout",
    metavar="LAYOUT",
    help="Layout of IN (latlong, angular, mirrorball, cross-vertical, ...); an EXR's envmap "
    "attribute (openexr-latlong, openexr-cube), else guessed from its shape when only one "
    "fits. IN may also be a .dds/.ktx/.ktx2 cube or six files with {face}.",
)


@click.command("bake-probe", context_settings={"max_content_width": 100})
@click.argument("source", metavar="[IN]", required=False, type=ENVIRONMENT)
@out_dir_option("Directory for everything (created if missing).")
@_from
@float_format_option("File format of the cube faces, DIMs and shadow probe.")
@click.option(
    "--container",
    type=click.Choice(("dds", "ktx", "ktx2")),
    default="dds",
    show_default=True,
    help="Container of the specular mip chain and the DFG table.",
)
@click.option("--cube-size", type=Integer(1, 4096), help="Face size of the environment "
              "cube (default: as many texels as the probe, a power of two).")  # fmt: skip
@click.option("--specular-size", type=Integer(1, 4096), default=256, show_default=True,
              help="Face size of level 0 of the GGX chain.")  # fmt: skip
@click.option("--mips", type=Integer(1, 14), help="Levels of the GGX chain (roughness "
              "m / (mips - 1); default: 9, or down to 1x1; at most log2(--specular-size) "
              "+ 1).")  # fmt: skip
@srgb_decode_option
@alpha_option
@click.option("--compress", is_flag=True, help="Also write block-compressed (BC6H) files with "
              "their quality sidecars into DIR/ENGINE/ (generic unless --engine).")  # fmt: skip
@click.option("--engine", type=click.Choice(sorted(ENGINES)), help="Write the compressed files "
              "this engine loads (faces, LOD mapping, SH layout; implies --compress).")  # fmt: skip
@quality_options
def bake_probe(
    source: Path | None,
    out_dir: Path,
    src_layout: str | None,
    fmt: str,
    container: str,
    cube_size: int | None,
    specular_size: int,
    mips: int | None,
    srgb_decode: bool,
    alpha: str | None,
    compress: bool,
    engine: str | None,
    quality_profile: str,
    overflow: Overflow,
    min_psnr: float | None,
    zstd: bool,
) -> None:
    """Bake everything the renderer needs from one probe IN (default: the embedded probe).

    \b
    Writes to DIR:
      env_posx ... env_negz   the environment as OpenGL cube faces
      sun_dim, shadow_dim     the DIM pair (E/pi, latlong 360x180): lit and shadowed surfaces
      shadow_probe            the probe with its sun painted out (input layout; a cube
                              input gives a vertical cross)
      sun.json                the sun's direction, size, colour and irradiance ({"sun": null}
                              when there is none)
      sh.json                 order-2 SH radiance coefficients (9 per channel), and the
                              irradiance's, windowed to be nowhere negative
      specular.dds            the GGX mip chain (roughness m/(mips-1)), OpenGL faces
      dfg.dds                 the split-sum DFG table (RG: scale, bias on F0)
      contact_sheet.png       all of it side by side, tone-mapped (exposure recorded in it)

    \b
    With --compress or --engine E, also DIR/E/: the environment and the GGX chain in BC6H
    (each with a .json quality sidecar) and E's SH file (docs/engines.md).

    \b
    Example:
      bakeshop bake-probe -o baked/
      bakeshop bake-probe probe.exr -o baked/ --format exr --container ktx
      bakeshop bake-probe -o baked/ --engine unity --compress
    """
    from bakeshop.io import write_image, write_json
    from bakeshop.light import bake_probe as bake
    from bakeshop.light import bake_probe_cost, contact_sheet, sh, sheet_exposure, sun_document
    from bakeshop.sphere import check_environment

    paths = {
        "cube": out_dir / f"env_{{face}}.{fmt}",
        "sun_dim": out_dir / f"sun_dim.{fmt}",
        "shadow_dim": out_dir / f"shadow_dim.{fmt}",
        "shadow_probe": out_dir / f"shadow_probe.{fmt}",
        "sun": out_dir / "sun.json",
        "sh": out_dir / "sh.json",
        "specular": out_dir / f"specular.{container}",
        "dfg": out_dir / f"dfg.{container}",
        "sheet": out_dir / "contact_sheet.png",
    }
    outputs = list(paths.values())
    if compress or engine:  # and the engine's files in DIR/ENGINE/
        from bakeshop.engines import engine as engine_preset
        from bakeshop.io.compress.pipeline import sidecar_path

        preset = engine_preset(engine or "generic")
        for name in preset.files.values():
            outputs.append(out_dir / preset.name / name)
            if not name.endswith(".json"):
                outputs.append(sidecar_path(outputs[-1]))
    for path in outputs:  # before any work
        refuse_overwriting_inputs(path, source)
    mips = chain_mips(mips, specular_size, "--specular-size", out_dir)
    _require_compressing(preset.container if compress or engine else None, zstd, out_dir)
    if compress or engine:
        _require_extras(out_dir / preset.name / preset.files["environment"], zstd)
    for folder in dict.fromkeys(path.parent for path in outputs):
        _require_writable(folder)
    image, layout, source, meta = read_probe(source, src_layout, with_metadata=True)
    check_picture_format(layout, fmt, source)
    image, _ = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, *outputs)  # alpha is carried by every step
    cost = bake_probe_cost(
        image.shape, layout, cube_size=cube_size, specular_size=specular_size, mips=mips,
        itemsize=image.itemsize, shadow_probe=False,
    )  # fmt: skip
    check(cost, source, "--cube-size or --specular-size", "--specular-size")
    _require_space(
        out_dir, image.shape, layout, cube_size, specular_size, mips, bool(compress or engine)
    )
    out_dir.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    # the shadow probe is painted into the probe itself once nothing else reads it (the
    # contact sheet and the engine chains read it first, sun included): a 16k probe is never
    # held twice
    baked = bake(image, layout, cube_size=cube_size, specular_size=specular_size, mips=mips,
                 shadow_probe=False)  # fmt: skip
    from bakeshop import progress

    with progress.step("contact sheet"):
        ev = sheet_exposure(image, layout)
        sheet = contact_sheet(baked, image, ev=ev)
    with progress.step("writing files"):
        faces = write_environment(paths["cube"], baked.cube, "cube")
        write_image(paths["sun_dim"], baked.sun_dim)
        write_image(paths["shadow_dim"], baked.shadow_dim)
        write_json(paths["sun"], sun_document(baked.sun))
        write_json(paths["sh"], sh.to_document(baked.sh, irradiance=baked.sh_irradiance))
        write_chain(paths["specular"], baked.specular, convention="opengl")
        write_table(paths["dfg"], baked.dfg)
        write_image(
            paths["sheet"],
            sheet,
            description=f"bakeshop display: exposure {ev:+.4f} EV; exposure {ev:+.2f} EV (auto "
            "over the probe's sphere), ACES, clamped, sRGB, 8-bit",
        )
    written = []
    if compress or engine:
        written = bake_compressed(
            baked, image, layout, out_dir, engine or "generic", specular_size=specular_size,
            quality_profile=quality_profile, overflow=overflow, min_psnr=min_psnr, zstd=zstd,
        )  # fmt: skip
    with progress.step("writing the shadow probe"):
        env = check_environment(image, layout)  # the probe itself, with a channel axis
        if baked.fill is not None:
            baked.fill.paint(env.image)
        # a cube probe (faces or a container) is painted as a cube: one picture, a cross
        write_environment(
            paths["shadow_probe"], as_picture(env.shaped(env.image), layout), picture_layout(layout)
        )
    elapsed = time.perf_counter() - started
    t = baked.timings
    s = baked.cube.shape[1]
    click.echo(
        f"baked {source.name} ({describe(image, layout)}) into {out_dir}/ in {elapsed:.1f} s"
    )
    rows = [
        (f"{faces[0].name} ...", f"environment, 6 OpenGL faces of {s}x{s}", t["cube"]),
        (paths["sun_dim"].name, "DIM of the probe (E/pi), latlong 360x180", t["dims"]),
        (paths["shadow_dim"].name, "DIM without the sun", None),
        (
            paths["shadow_probe"].name,
            "probe without the sun "
            + ("(vertical cross)" if layout == "cube" else f"({describe(image, layout)})"),
            None,
        ),
        (paths["sun"].name, "the sun" if baked.sun is not None else "no sun found", None),
        (paths["sh"].name, f"SH radiance, {baked.sh.shape[0]} coefficients per channel", t["sh"]),
        ("", f"SH irradiance: {baked.sh_irradiance.describe()}", None),
        (
            paths["specular"].name,
            f"GGX chain, {len(baked.specular)} levels from 6x{baked.specular[0].shape[1]}",
            t["specular"],
        ),
        (paths["dfg"].name, f"DFG table {baked.dfg.shape[1]}x{baked.dfg.shape[0]}", t["dfg"]),
        (paths["sheet"].name, f"contact sheet, exposure {ev:+.2f} EV (auto), ACES", None),
    ]
    for name, what, seconds in rows:
        took = f"{seconds:6.2f} s" if seconds is not None else ""
        click.echo(f"  {name:<22} {what:<52} {took}".rstrip())
    if baked.sun is not None:
        x, y, z = baked.sun.direction
        click.echo(
            f"  sun: direction [{x:.4f}, {y:.4f}, {z:.4f}], "
            f"radius {baked.sun.angular_radius_deg:.2f} deg"
        )
    if compress or engine:
        click.echo(f"  compressed for {ENGINES[engine or 'generic'].title}:")
        for path, what, report in written:
            q = ""
            if report:
                ratios = [row["energy_ratio"] for row in report["source"]["levels"]]
                worst = max(ratios, key=lambda r: abs(r - 1))
                q = f": {describe_quality(report['quality'])}; energy {worst:.1%} of the probe's"
            click.echo(f"    {path.relative_to(out_dir)}  {what}{q}")


def _require_compressing(container: str | None, zstd: bool, out_dir: Path) -> None:
    """Refuse an encoder option that would do nothing: given without --compress or --engine
    (``container`` None), or --zstd for an engine whose container is not KTX2."""
    from bakeshop.errors import ArgumentError

    if container is not None:
        if zstd and container != "ktx2":
            reason = f"--zstd supercompresses KTX2 files only; this engine loads .{container}"
            raise ArgumentError(reason, out_dir)
        return
    context = click.get_current_context()
    for name in ("quality_profile", "overflow", "min_psnr", "zstd"):
        if context.get_parameter_source(name) is not click.core.ParameterSource.DEFAULT:
            option = "--quality" if name == "quality_profile" else "--" + name.replace("_", "-")
            raise ArgumentError(
                f"{option} is an option of the compressed files: add --compress or --engine",
                out_dir,
            )


def _require_extras(target: Path, zstd: bool) -> None:
    """Refuse before any work when the compress extra that ``target`` needs is missing."""
    from bakeshop.errors import BakeshopError
    from bakeshop.io.compress.encode import ispc
    from bakeshop.io.ktx2 import zstandard

    try:
        ispc()
        if zstd:
            zstandard()
    except BakeshopError as e:
        e.path = str(target)
        raise


def _nearest_existing(path: Path) -> Path:
    """``path``, or the nearest of its parents that exists."""
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def _require_writable(folder: Path) -> None:
    """Refuse when ``folder`` cannot be written in or created: a temporary file is written (and
    removed at once) in it, or in the nearest existing folder above it; nothing is created."""
    import tempfile

    from bakeshop.errors import ArgumentError
    from bakeshop.io import describe_os_error

    existing = _nearest_existing(folder)
    what = "write in" if existing == folder else "create"
    if not existing.is_dir():
        raise ArgumentError(f"cannot {what} this folder: {existing} is a file", folder)
    try:
        with tempfile.TemporaryFile(dir=existing):
            pass
    except OSError as e:
        raise ArgumentError(f"cannot {what} this folder: {describe_os_error(e)}", folder) from None


def _require_space(
    out_dir: Path,
    shape: tuple[int, ...],
    layout: str,
    cube_size: int | None,
    specular_size: int,
    mips: int,
    compress: bool,
) -> None:
    """Refuse before the bake when ``out_dir``'s file system has less room than the bake writes:
    an upper bound at 4 bytes a sample (float32; half floats and RGBE take less), one byte a
    texel for BC6H, and a megabyte for the JSON files and the contact sheet."""
    import math
    import shutil

    from bakeshop.errors import ArgumentError
    from bakeshop.light.probe import default_cube_size

    channels = min(4, shape[-1])  # of the outputs; the shadow probe has the probe's samples
    size = cube_size or default_cube_size(shape, layout)
    chain = sum(6 * max(1, specular_size >> m) ** 2 for m in range(mips))
    samples = channels * (6 * size**2 + 2 * 360 * 180 + chain) + math.prod(shape)
    need = 4 * samples + 4 * 2 * 128**2 + 2**20
    if compress:  # the environment's box mips (4/3 of level 0) and a chain of at most as many
        need += 6 * size**2 * 4 // 3 + chain
    free = shutil.disk_usage(_nearest_existing(out_dir)).free
    if need > free:
        raise ArgumentError(
            f"the bake writes up to {need / 1e6:.1f} MB and this file system has "
            f"{free / 1e6:.1f} MB free: free some space, or lower --cube-size, --specular-size "
            "or the probe's size",
            out_dir,
        )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(bake_probe)
