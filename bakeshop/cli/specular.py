"""``bakeshop prefilter``, ``dfg`` and ``bake-probe``: glossy reflections and the probe bake."""

from __future__ import annotations

import time
from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import (
    ENVIRONMENT,
    OUTPUT,
    convention_option,
    float_format_option,
    out_dir_option,
    refuse_overwriting_inputs,
)
from bakeshop.cli._environment import (
    as_picture,
    describe,
    is_container,
    read_environment,
    write_container,
    write_environment,
)
from bakeshop.cli.compress import bake_compressed, describe_quality, quality_options
from bakeshop.engines import ENGINES
from bakeshop.errors import ArgumentError


def _check_chain_target(target: Path) -> None:
    if not is_container(target) and "{mip}" not in str(target):
        raise ArgumentError(
            "a mip chain is one .dds, .ktx or .ktx2 file, or a name with {mip} (and {face} for six "
            "face files per level, else one vertical cross per level): spec_{mip}_{face}.hdr",
            target,
        )


def write_chain(target: Path, chain, *, convention: str, float32: bool = False) -> list[Path]:
    """Write a cube mip chain: one .dds/.ktx/.ktx2 file, or files per level (``{mip}``) and face.

    Returns the paths written; a container holds float16 unless a value would overflow it.
    """
    from bakeshop import sphere
    from bakeshop.io import write_image

    _check_chain_target(target)
    faces = [sphere.cube_to_faces(level, convention=convention) for level in chain]
    if is_container(target):
        write_container(target, faces, float32=float32)
        return [target]
    paths = []
    for m, level in enumerate(chain):
        name = Path(str(target).replace("{mip}", str(m)))
        if "{face}" in str(name):
            paths += write_environment(name, level, "cube", convention, False)
        else:
            write_image(name, sphere.cube_to_view(level, "cross-vertical"))
            paths.append(name)
    return paths


def write_dfg(target: Path, table, *, float32: bool = False) -> None:
    """Write the DFG table: RG in a .dds/.ktx/.ktx2 2-D texture, else RGB (blue 0) as an image
    (16-bit for PNG: the table is linear data, not a picture)."""
    from bakeshop.io import write_image

    if is_container(target):
        write_container(target, [table], float32=float32)
        return
    rgb = np.concatenate([table, np.zeros_like(table[..., :1])], axis=-1)
    options = {"bits": 16} if target.suffix.lower() == ".png" else {}
    write_image(target, rgb, **options)


def _read_probe(source: Path | None, src_layout: str | None):
    """(image, layout, name) of the input probe; the embedded default when ``source`` is None."""
    from bakeshop import progress

    if source is None:
        from importlib.resources import files

        source = Path(str(files("bakeshop") / "data" / "default_probe.hdr"))
    with progress.step(f"reading {source.name}"):
        image, layout, _ = read_environment(source, src_layout, "opengl", False)
    return image, layout, source


_from = click.option(
    "--from",
    "src_layout",
    metavar="LAYOUT",
    help="Layout of IN (latlong, angular, mirrorball, cross-vertical, ...); guessed from its "
    "shape when only one fits. IN may also be a .dds/.ktx/.ktx2 cube or six files with {face}.",
)
_convention = convention_option(
    "Engine whose cube faces to write (directx: the left-handed, z-forward face set)."
)
_float32 = click.option(
    "--float32", is_flag=True, help="Store 32-bit floats in .dds/.ktx/.ktx2 (default: half floats "
    "unless a value exceeds 65504)."
)  # fmt: skip


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", metavar="IN", type=ENVIRONMENT)
@click.argument("target", metavar="OUT", type=OUTPUT)
@click.option("--brdf", type=click.Choice(("ggx", "phong")), default="ggx", show_default=True)
@click.option(
    "--exponent",
    type=click.FloatRange(min=0, min_open=True),
    help="Phong only: one lobe of this exponent, one level (HDRShop's specular convolution). "
    "Default: a chain with cmft's exponents, 2^(10 (1 - m/(mips-1)) + 1).",
)
@click.option("--size", type=click.IntRange(1, 4096), default=256, show_default=True,
              help="Face size of level 0.")  # fmt: skip
@click.option("--mips", type=click.IntRange(1, 14), help="Levels (default: 9, or down to 1x1).")
@_from
@click.option("--samples", type=click.IntRange(1, 65536), default=256, show_default=True,
              help="Importance samples per texel (narrow lobes; wide ones are exact).")  # fmt: skip
@_convention
@_float32
def prefilter(source, target, brdf, exponent, size, mips, src_layout, samples, convention, float32):
    """Prefilter the environment IN into a glossy-reflection cube mip chain OUT.

    GGX (the split-sum approximation of UE4): level m has roughness m / (mips - 1), so level 0
    is the environment itself and the last level roughness 1; a shader reads it with
    textureLod(env, R, roughness * (mips - 1)) and multiplies by the DFG table (bakeshop dfg).
    Phong: cmft's exponent per level, or one lobe with --exponent. OUT is one .dds, .ktx or
    .ktx2 file holding the whole chain, or a name with {mip} (and {face} for six face files).

    \b
    Example:
      bakeshop prefilter probe.hdr specular.dds
      bakeshop prefilter probe.exr specular.ktx2 --size 128 --mips 8
      bakeshop prefilter probe.hdr "spec_{mip}_{face}.hdr" --convention directx
      bakeshop prefilter probe.hdr glossy.dds --brdf phong --exponent 64 --size 64
    """
    from bakeshop.light import specular

    _check_chain_target(target)
    refuse_overwriting_inputs(target, source)
    if exponent is not None and brdf != "phong":
        raise ArgumentError("--exponent is the exponent of a Phong lobe: add --brdf phong")
    if exponent is not None and mips not in (None, 1):
        raise ArgumentError("--exponent makes one level (one lobe); leave out --mips")
    if mips is None:
        mips = 1 if exponent is not None else min(9, size.bit_length())
    image, layout, _ = _read_probe(source, src_layout)
    started = time.perf_counter()
    if brdf == "ggx":
        chain = specular.prefilter_ggx(image, layout=layout, size=size, mips=mips, samples=samples)
        what = f"GGX, roughness m/{mips - 1} per level" if mips > 1 else "GGX, roughness 0"
    else:
        exponents = None if exponent is None else [exponent]
        chain = specular.prefilter_phong(
            image, layout=layout, size=size, mips=mips, exponents=exponents, samples=samples
        )
        what = f"Phong exponent {exponent:g}" if exponent else "Phong, cmft's exponents"
    elapsed = time.perf_counter() - started
    paths = write_chain(target, chain, convention=convention, float32=float32)
    where = target if len(paths) == 1 else f"{len(paths)} files ({paths[0].name} ...)"
    click.echo(
        f"wrote {where}: {len(chain)} levels of 6x{size} down to 6x{chain[-1].shape[1]} "
        f"({what}; {convention} faces) from {source.name} ({describe(image, layout)}), "
        f"{elapsed:.2f} s"
    )


@click.command(context_settings={"max_content_width": 100})
@click.argument("target", metavar="OUT", type=OUTPUT)
@click.option("--size", type=click.IntRange(1, 4096), default=128, show_default=True,
              help="Side of the square table.")  # fmt: skip
@click.option("--samples", type=click.IntRange(1, 1 << 20), default=4096, show_default=True,
              help="Importance samples per texel.")  # fmt: skip
@click.option(
    "--visibility",
    type=click.Choice(("height-correlated", "schlick")),
    default="height-correlated",
    show_default=True,
    help="Smith GGX visibility: height-correlated (Heitz 2014, exact) or UE4's separable "
    "Schlick-Smith (k = alpha/2).",
)
@_float32
def dfg(target, size, samples, visibility, float32):
    """Write the split-sum DFG lookup table to OUT: scale and bias on F0 per (n.v, roughness).

    Columns are n.v and rows roughness (row 0 smoothest), both at texel centres:
    specular = prefiltered * (F0 * lut.r + lut.g) with lut = texture(dfg, vec2(NdotV,
    roughness)). A .dds/.ktx/.ktx2 file holds an RG float texture; an image file (.exr, .hdr,
    .pfm, 16-bit .png) holds RGB with blue 0.

    \b
    Example:
      bakeshop dfg dfg.dds
      bakeshop dfg dfg_lut.exr --size 256 --visibility schlick
    """
    from bakeshop.light.dfg import dfg_table

    started = time.perf_counter()
    table = dfg_table(size, samples=samples, visibility=visibility)
    elapsed = time.perf_counter() - started
    write_dfg(target, table, float32=float32)
    click.echo(
        f"wrote {target}: {size}x{size} DFG table ({visibility} Smith GGX, {samples} samples), "
        f"{elapsed:.2f} s"
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
@click.option("--cube-size", type=click.IntRange(1, 4096), help="Face size of the environment "
              "cube (default: as many texels as the probe, a power of two).")  # fmt: skip
@click.option("--specular-size", type=click.IntRange(1, 4096), default=256, show_default=True,
              help="Face size of level 0 of the GGX chain.")  # fmt: skip
@click.option("--mips", type=click.IntRange(1, 14), default=9, show_default=True,
              help="Levels of the GGX chain (roughness m / (mips - 1)).")  # fmt: skip
@click.option("--compress", is_flag=True, help="Also write block-compressed (BC6H) files with "
              "their quality sidecars into DIR/ENGINE/ (generic unless --engine).")  # fmt: skip
@click.option("--engine", type=click.Choice(sorted(ENGINES)), help="Write the compressed files "
              "this engine loads (faces, LOD mapping, SH layout; implies --compress).")  # fmt: skip
@quality_options
def bake_probe(
    source, out_dir, src_layout, fmt, container, cube_size, specular_size, mips, compress, engine,
    quality_profile, overflow, min_psnr, zstd,
):  # fmt: skip
    """Bake everything the renderer needs from one probe IN (default: the embedded probe).

    \b
    Writes to DIR:
      env_posx ... env_negz   the environment as OpenGL cube faces
      sun_dim, shadow_dim     the DIM pair (E/pi, latlong 360x180): lit and shadowed surfaces
      shadow_probe            the probe with its sun painted out (input layout; a cube
                              input gives a vertical cross)
      sun.json                the sun's direction, size, colour and irradiance ({"sun": null}
                              when there is none)
      sh.json                 order-2 SH radiance coefficients (9 per channel)
      specular.dds            the GGX mip chain (roughness m/(mips-1)), OpenGL faces
      dfg.dds                 the split-sum DFG table (RG: scale, bias on F0)
      contact_sheet.png       all of it side by side, tone-mapped

    \b
    With --compress or --engine E, also DIR/E/: the environment and the GGX chain in BC6H
    (each with a .json quality sidecar) and E's SH file (docs/engines.md).

    \b
    Example:
      bakeshop bake-probe -o baked/
      bakeshop bake-probe probe.exr -o baked/ --format exr --container ktx
      bakeshop bake-probe -o baked/ --engine unity --compress
    """
    from bakeshop.io import write_image
    from bakeshop.light import probe as probe_module
    from bakeshop.light import sh
    from bakeshop.light import sun as sun_module

    out_dir.mkdir(parents=True, exist_ok=True)
    image, layout, source = _read_probe(source, src_layout)
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
    for path in paths.values():
        refuse_overwriting_inputs(path, source)
    started = time.perf_counter()
    bake = probe_module.bake_probe(
        image, layout, cube_size=cube_size, specular_size=specular_size, mips=mips
    )
    from bakeshop import progress

    with progress.step("writing files"):
        faces = write_environment(paths["cube"], bake.cube, "cube", "opengl", False)
        write_image(paths["sun_dim"], bake.sun_dim)
        write_image(paths["shadow_dim"], bake.shadow_dim)
        # a cube probe (faces or a container) is painted as a cube: one picture, a cross
        write_image(paths["shadow_probe"], as_picture(bake.shadow_probe, layout))
        sun_module.write_json(paths["sun"], bake.sun)
        sh.write_json(paths["sh"], bake.sh)
        write_chain(paths["specular"], bake.specular, convention="opengl")
        write_dfg(paths["dfg"], bake.dfg)
    with progress.step("contact sheet"):
        write_image(paths["sheet"], probe_module.contact_sheet(bake, image))
    elapsed = time.perf_counter() - started
    t = bake.timings
    s = bake.cube.shape[1]
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
        (paths["sun"].name, "the sun" if bake.sun is not None else "no sun found", None),
        (paths["sh"].name, f"SH radiance, {bake.sh.shape[0]} coefficients per channel", t["sh"]),
        (
            paths["specular"].name,
            f"GGX chain, {len(bake.specular)} levels from 6x{bake.specular[0].shape[1]}",
            t["specular"],
        ),
        (paths["dfg"].name, f"DFG table {bake.dfg.shape[1]}x{bake.dfg.shape[0]}", t["dfg"]),
        (paths["sheet"].name, "contact sheet", None),
    ]
    for name, what, seconds in rows:
        took = f"{seconds:6.2f} s" if seconds is not None else ""
        click.echo(f"  {name:<22} {what:<52} {took}".rstrip())
    if bake.sun is not None:
        x, y, z = bake.sun.direction
        click.echo(
            f"  sun: direction [{x:.4f}, {y:.4f}, {z:.4f}], "
            f"radius {bake.sun.angular_radius_deg:.2f} deg"
        )
    if compress or engine:
        written = bake_compressed(
            bake, image, layout, out_dir, engine or "generic", specular_size=specular_size,
            quality_profile=quality_profile, overflow=overflow, min_psnr=min_psnr, zstd=zstd,
        )  # fmt: skip
        click.echo(f"  compressed for {ENGINES[engine or 'generic'].title}:")
        for path, what, report in written:
            q = f": {describe_quality(report['quality'])}" if report else ""
            click.echo(f"    {path.relative_to(out_dir)}  {what}{q}")


def register(group: click.Group) -> None:
    """Add ``prefilter``, ``dfg`` and ``bake-probe`` to the root command group."""
    for command in (prefilter, dfg, bake_probe):
        group.add_command(command)
