"""``bakeshop fresnel``: fresnel-baked reflections for flat water."""

from __future__ import annotations

from pathlib import Path

import click

from bakeshop.cli._budget import check
from bakeshop.cli._common import (
    alpha_option,
    convention_option,
    environment_weights,
    fit_alpha,
    is_ldr,
    linearise,
    parse_exposure_mode,
    srgb_decode_option,
)
from bakeshop.cli._numbers import Direction, Exposure, Integer, Number, Size
from bakeshop.cli._paths import ENVIRONMENT, OUTPUT_FACES, parse_size, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError
from bakeshop.io.environment import (
    describe,
    is_container,
    read_environment,
    write_environment,
)


def _check_output(target: Path, layout: str, ldr: bool) -> None:
    """Refuse an output whose format does not fit the layout or the sample type."""
    if is_container(target):
        if layout != "cube" or ldr:
            raise ArgumentError(
                "a .dds, .ktx or .ktx2 output is a float cube map: use --layout cube, without "
                "--ldr",
                target,
            )
        return
    if is_ldr(target) != ldr:
        raise ArgumentError(
            "--ldr writes 8-bit sRGB: give a .png or .tga output"
            if ldr
            else "this output format is 8-bit: add --ldr (exposure, sRGB encoding) or write "
            ".exr/.hdr/.pfm",
            target,
        )
    if layout == "cube" and "{face}" not in str(target):
        raise ArgumentError(
            "a cube is written as six faces: put {face} in the output name (for example "
            "sky_{face}.png), write one .dds, .ktx or .ktx2 file, or choose --layout "
            "cross-vertical",
            target,
        )


def _report_lines(schlick: dict, flat: dict, rough: list[dict]) -> list[str]:
    lines = [
        f"Schlick's approximation vs the exact reflectance: {schlick['max']:+.4f} at "
        f"{schlick['max_angle_deg']:.1f} deg, {schlick['min']:+.4f} at "
        f"{schlick['min_angle_deg']:.1f} deg, mean {schlick['mean']:+.4f} over cos(theta)",
        f"flat water, baked 8-bit lookup vs runtime (HDR x fresnel x exposure -> 8-bit sRGB), "
        f"{flat['samples']} reflected directions over the upper hemisphere, {flat['filter']} "
        f"lookups, below horizon: {flat['below']}, dither: {flat['dither']}:",
        f"  error in 8-bit steps: max {flat['max']}, mean {flat['mean']:.3f} over all lookups",
        f"  where the runtime value is not clipped: max {flat['max_unclipped']}, "
        f"mean {flat['mean_unclipped']:.3f}",
        f"  and away from the horizon band and clipped footprints: max {flat['max_clean']}, "
        f"mean {flat['mean_clean']:.3f}, more than one step: {100 * flat['over_one_clean']:.4f}% "
        f"(worst at {flat['worst_elevation_deg']:.2f} deg elevation)",
        f"  left out: runtime clipped {100 * flat['clipped']:.3f}%, footprint touches a clipped "
        f"texel {100 * flat['footprint_clipped']:.3f}%, horizon band {100 * flat['horizon']:.3f}%",
        "normal-mapped water, reflectance error of the baked (flat) fresnel vs the true one "
        "(R(r.up) vs R(e.n)), eye directions over the hemisphere:",
        "  RMS slope   mean |dR|   p99 |dR|   mean |dR/R|   p99 |dR/R|   left out",
    ]
    for r in rough:
        lines.append(
            f"  {r['rms_slope']:9.2f}   {r['mean_abs']:9.4f}   {r['p99_abs']:8.4f}   "
            f"{100 * r['mean_rel']:10.1f}%   {100 * r['p99_rel']:9.1f}%   "
            f"{100 * (r['back_facing'] + r['below_horizon']):7.1f}%"
        )
    return lines


@click.command(context_settings={"max_content_width": 100})
@click.argument("source", type=ENVIRONMENT)
@click.argument("target", type=OUTPUT_FACES)
@click.option(
    "--from",
    "src_layout",
    metavar="LAYOUT",
    help="Layout of SOURCE (default: guessed from its shape when unambiguous, e.g. 2:1 is "
    "latlong). SOURCE may also be a .dds/.ktx/.ktx2 cube or six files with {face}.",
)
@click.option(
    "--layout",
    "dst_layout",
    metavar="LAYOUT",
    help="Layout of the output (default: that of SOURCE); 'cube' writes six faces "
    "to a TARGET containing {face}, or one float cube map to a .dds, .ktx or .ktx2 TARGET.",
)
@click.option(
    "--size",
    type=Size(),
    metavar="N|WxH",
    help="Output size: N (latlong height, face edge, disk edge) or WxH. Remapping uses the "
    "area filter when the output has at most half the input's texels, bilinear otherwise.",
)
@click.option(
    "--ior",
    type=Number(1, 4, low_open=True),
    default=1.333,
    show_default=True,
    help="Index of refraction of the water.",
)
@click.option(
    "--up",
    type=Direction(),
    default="+Y",
    show_default=True,
    help="Normal of the water plane in the world frame: +Y, -Z, ... or x,y,z.",
)
@click.option(
    "--below",
    type=click.Choice(["zero", "mirror"]),
    default="zero",
    show_default=True,
    help="Directions below the plane (never seen by a flat reflector): black, or the "
    "mirror image of the upper half (no dark seam when filtering at the horizon).",
)
@click.option(
    "--exposure",
    "exposure_text",
    type=Exposure(("auto", "fit")),
    metavar="EV|auto|fit",
    help="Exposure applied to the bake: stops, fit (only the brightest 0.1% of "
    "the hemisphere, by solid angle: the sun, clips at 1) or auto (log-average luminance "
    "above the horizon to middle grey). Default: 0, or fit with --ldr.",
)
@click.option(
    "--ldr", is_flag=True, help="Write 8-bit sRGB (PNG, TGA): exposure, clamp, sRGB encode, round."
)
@click.option(
    "--dither",
    is_flag=True,
    help="With --ldr: triangular dither of +-1 code value (seeded) against banding.",
)
@click.option(
    "--seed", type=Integer(0, 2**32 - 1), default=0, show_default=True, help="Seed of the dither."
)
@convention_option(
    "Face set of cube files, read (a {face} or .dds/.ktx/.ktx2 SOURCE) and written (--layout cube)."
)
@click.option(
    "--report",
    is_flag=True,
    help="Also measure the bake: 8-bit baked vs runtime path on flat water, and the "
    "fresnel error on normal-mapped water for RMS slopes 0.02 to 0.3.",
)
@srgb_decode_option
@alpha_option
def fresnel(
    source: Path,
    target: Path,
    src_layout: str | None,
    dst_layout: str | None,
    size: int | tuple[int, int] | None,
    ior: float,
    up: tuple[float, float, float],
    below: str,
    exposure_text: float | str | None,
    ldr: bool,
    dither: bool,
    seed: int,
    convention: str,
    report: bool,
    srgb_decode: bool,
    alpha: str | None,
) -> None:
    """Bake the fresnel reflectance of flat water into an environment map.

    For a flat reflector every direction d of a distant environment is seen under one angle
    of incidence, cos(theta) = d . up, so each texel is multiplied by the exact unpolarised
    reflectance R(d . up) of water (air -> n = --ior) and the shader does a plain lookup at the
    reflected vector. After exposure the bake fits in 8 bits: fresnel dims the bright zenith
    (R = 0.02 looking straight down) and only the sun clips. Directions below the plane are
    written as --below says.

    --ldr writes 8-bit sRGB (IEC 61966-2-1) after --exposure (fit by default), optionally
    dithered, by the display rule of every command (docs/tonemap.md) with the exposure metered
    above the horizon only, and recorded in the file; otherwise the bake is written as float
    (.exr, .hdr, .pfm). --layout cube writes
    the six faces an engine loads (OpenGL order and orientation, or --convention directx), as
    six pictures or one float .dds/.ktx/.ktx2 cube map.

    \b
    Example:
      bakeshop fresnel sky.hdr water_env.exr
      bakeshop fresnel sky.hdr water_env.png --ldr --dither --report
      bakeshop fresnel sky.exr water_{face}.png --layout cube --size 512 --ldr
      bakeshop fresnel sky.exr water.dds --layout cube --size 512 --below mirror
    """
    from bakeshop import progress, sphere
    from bakeshop.image import choose_exposure, to_picture
    from bakeshop.image import exposure as apply_exposure
    from bakeshop.light.fresnel import (
        RMS_SLOPES,
        bake_fresnel,
        flat_water_error,
        normal_mapped_error,
        schlick_error,
    )

    refuse_overwriting_inputs(target, source)
    if exposure_text is None:
        ev = "fit" if ldr else 0.0
    else:
        ev = parse_exposure_mode(exposure_text)
    if dither and not ldr:
        raise ArgumentError("--dither applies to --ldr output only")

    (image, src, _), meta = read_environment(
        source, src_layout, convention=convention, with_metadata=True
    )
    image, _ = linearise(image, source, meta, srgb_decode)
    image = fit_alpha(image, alpha, source, target)
    dst = dst_layout or src
    _check_output(target, dst, ldr)
    if dst != src or size is not None:
        wanted = parse_size(size) if size else None
        shape = image.shape[: 3 if src == "cube" else 2]
        cost = sphere.remap_cost(src, shape, dst, wanted, filter="auto",
                                 channels=image.shape[-1], itemsize=image.itemsize)  # fmt: skip
        check(cost, source, "--size", "--size")
        image = sphere.remap(image, src, dst, wanted, filter="auto")
    baked = bake_fresnel(image, dst, ior=ior, up=up, below=below)
    # metered over the texels above the water plane: the lower half holds no reflection
    weights = environment_weights(dst, baked.shape[:-1], up=up)
    description = None
    if ldr:
        shown = to_picture(
            baked,
            ev=ev,
            dither="triangular" if dither else "none",
            seed=seed,
            weights=weights,
        )
        out, ev, description = shown.pixels, shown.ev, shown.metadata()
        encoding = shown.describe()
    else:
        ev = choose_exposure(baked, ev, weights=weights).ev
        out = apply_exposure(baked, ev)
        encoding = f"exposure {ev:+.2f} EV, float"
    written = write_environment(target, out, dst, convention=convention, description=description)

    where = str(written[0]) if len(written) == 1 else f"{len(written)} faces ({target})"
    click.echo(
        f"wrote {where}: {describe(out, dst)}, fresnel ior {ior:g} "
        f"up [{', '.join(f'{c:g}' for c in up)}], below horizon {below}, {encoding}"
    )
    if report:
        flat = flat_water_error(
            image,
            dst,
            ev=ev,
            ior=ior,
            up=up,
            below=below,
            dither="triangular" if dither else "none",
            seed=seed,
        )
        slopes = progress.track(RMS_SLOPES, "normal-mapped water")
        rough = [normal_mapped_error(s, ior=ior, samples=1 << 18) for s in slopes]
        for line in _report_lines(schlick_error(ior), flat, rough):
            click.echo(line)


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(fresnel)
