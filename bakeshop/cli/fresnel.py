"""``bakeshop fresnel`` (fresnel-baked reflections for flat water) and ``bakeshop tonemap``."""

from __future__ import annotations

import glob
import re
import string
from pathlib import Path

import click
import numpy as np

from bakeshop.cli._common import (
    ENVIRONMENT,
    FRAMES,
    OUTPUT,
    convention_option,
    is_ldr,
    parse_size,
    refuse_overwriting_inputs,
    require_hdr,
)
from bakeshop.cli._environment import (
    auto_filter,
    describe,
    is_container,
    read_environment,
    write_environment,
)
from bakeshop.errors import ArgumentError
from bakeshop.io import check_input

_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def parse_axis(text: str) -> tuple[float, float, float]:
    """``'+Y'``, ``'-z'``, ``'Y'`` or ``'x,y,z'`` -> a 3-vector (normalised later)."""
    t = text.strip().lower()
    m = re.fullmatch(r"([+-]?)([xyz])", t)
    if m:
        sign = -1.0 if m.group(1) == "-" else 1.0
        return tuple(sign * v for v in _AXES[m.group(2)])
    try:
        v = tuple(float(p) for p in t.split(","))
    except ValueError:
        v = ()
    if len(v) != 3 or not np.all(np.isfinite(v)) or not any(v):
        raise ArgumentError(f"invalid axis {text!r}: use +X, -X, +Y, -Y, +Z, -Z or x,y,z")
    return v


def parse_exposure(text: str | None) -> float | str | None:
    """``None``, ``'auto'`` or a number of stops."""
    if text is None or text.strip().lower() == "auto":
        return None if text is None else "auto"
    try:
        ev = float(text)
    except ValueError:
        ev = float("nan")
    if not np.isfinite(ev):
        raise ArgumentError(f"invalid exposure {text!r}: a number of stops (EV) or 'auto'")
    return ev


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
@click.argument("target", type=OUTPUT)
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
    help="Output size: N (latlong height, face edge, disk edge) or WxH. Remapping uses the "
    "area filter when the output has at most half the input's texels, bilinear otherwise.",
)
@click.option(
    "--ior", type=float, default=1.333, show_default=True, help="Index of refraction of the water."
)
@click.option(
    "--up",
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
    metavar="EV|auto",
    help="Exposure in stops applied to the bake; 'auto' lets only the brightest 0.1% "
    "of the hemisphere (by solid angle: the sun) clip at 1. Default: 0, or auto "
    "with --ldr.",
)
@click.option(
    "--ldr", is_flag=True, help="Write 8-bit sRGB (PNG, TGA): exposure, clamp, sRGB encode, round."
)
@click.option(
    "--dither",
    is_flag=True,
    help="With --ldr: triangular dither of +-1 code value (seeded) against banding.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the dither.")
@convention_option(
    "Face set of cube files, read (a {face} or .dds/.ktx/.ktx2 SOURCE) and written (--layout cube)."
)
@click.option(
    "--report",
    is_flag=True,
    help="Also measure the bake: 8-bit baked vs runtime path on flat water, and the "
    "fresnel error on normal-mapped water for RMS slopes 0.02 to 0.3.",
)
def fresnel(
    source,
    target,
    src_layout,
    dst_layout,
    size,
    ior,
    up,
    below,
    exposure_text,
    ldr,
    dither,
    seed,
    convention,
    report,
):
    """Bake the fresnel reflectance of flat water into an environment map.

    For a flat reflector every direction d of a distant environment is seen under one angle
    of incidence, cos(theta) = d . up, so each texel is multiplied by the exact unpolarised
    reflectance R(d . up) of water (air -> n = --ior) and the shader does a plain lookup at the
    reflected vector. After exposure the bake fits in 8 bits: fresnel dims the bright zenith
    (R = 0.02 looking straight down) and only the sun clips. Directions below the plane are
    written as --below says.

    --ldr writes 8-bit sRGB (IEC 61966-2-1) after --exposure (auto by default), optionally
    dithered; otherwise the bake is written as float (.exr, .hdr, .pfm). --layout cube writes
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
    from bakeshop.light.fresnel import (
        RMS_SLOPES,
        bake_fresnel,
        flat_water_error,
        ldr_exposure,
        normal_mapped_error,
        schlick_error,
    )
    from bakeshop.light.tonemap import exposure as apply_exposure
    from bakeshop.light.tonemap import to_srgb8

    refuse_overwriting_inputs(target, source)
    if not is_container(source):  # a container holds floats
        require_hdr(source)
    up_axis = parse_axis(up)
    ev = parse_exposure(exposure_text)
    if dither and not ldr:
        raise ArgumentError("--dither applies to --ldr output only")

    image, src, _ = read_environment(source, src_layout, convention)
    dst = dst_layout or src
    _check_output(target, dst, ldr)
    if dst != src or size is not None:
        wanted = parse_size(size) if size else None
        image = sphere.remap(image, src, dst, wanted, filter=auto_filter(image, src, dst, wanted))
    baked = bake_fresnel(image, dst, ior=ior, up=up_axis, below=below)
    if ev == "auto" or (ev is None and ldr):
        ev = ldr_exposure(baked, dst, up=up_axis)
    ev = ev or 0.0
    out = apply_exposure(baked, ev)
    if ldr:
        out = to_srgb8(out, dither="triangular" if dither else "none", seed=seed)
    written = write_environment(target, out, dst, convention)

    encoding = "8-bit sRGB" + (", dithered" if dither else "") if ldr else "float"
    where = str(written[0]) if len(written) == 1 else f"{len(written)} faces ({target})"
    click.echo(
        f"wrote {where}: {describe(out, dst)}, fresnel ior {ior:g} "
        f"up {up}, below horizon {below}, exposure {ev:+.2f} EV, {encoding}"
    )
    if report:
        flat = flat_water_error(
            image,
            dst,
            ev=ev,
            ior=ior,
            up=up_axis,
            below=below,
            dither="triangular" if dither else "none",
            seed=seed,
        )
        slopes = progress.track(RMS_SLOPES, "normal-mapped water")
        rough = [normal_mapped_error(s, ior=ior, samples=1 << 18) for s in slopes]
        for line in _report_lines(schlick_error(ior), flat, rough):
            click.echo(line)


def _natural_key(path: str):
    """Sort key that orders frame_2 before frame_10."""
    return [(0, int(t), "") if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", path)]


def expand_inputs(patterns) -> list[Path]:
    """Input frames in order: each argument is a file or a glob pattern, whose matches are
    sorted by name with numbers in numeric order (frame_2 before frame_10)."""
    frames: list[Path] = []
    for p in map(str, patterns):
        if glob.has_magic(p):
            matches = sorted(glob.glob(p), key=_natural_key)
            if not matches:
                raise ArgumentError("no file matches this pattern", p)
            frames.extend(Path(m) for m in matches)
        else:
            check_input(p)
            frames.append(Path(p))
    return frames


def frame_paths(target: str, count: int) -> list[Path]:
    """Output names: ``target`` for one frame; ``target.format(frame=i)`` for a sequence."""
    fields = {f for _, f, _, _ in string.Formatter().parse(target) if f is not None}
    if count > 1 and "frame" not in fields:
        raise ArgumentError(
            "several input frames need a {frame} pattern in the output name "
            "(for example out_{frame:04d}.png)",
            target,
        )
    if fields - {"frame"}:
        raise ArgumentError("only {frame} may appear in braces in the output name", target)
    try:
        return [Path(target.format(frame=i)) for i in range(count)]
    except (ValueError, IndexError) as e:
        raise ArgumentError(f"bad output pattern: {e}", target) from None


@click.command(context_settings={"max_content_width": 100})
@click.argument("inputs", nargs=-1, required=True, metavar="IN...", type=FRAMES)
@click.argument("target", metavar="OUT")
@click.option(
    "--operator",
    type=click.Choice(["none", "reinhard", "aces"]),
    default="aces",
    show_default=True,
    help="Tone curve after exposure: none (clamp), reinhard (Reinhard 2002 eq. 4 on "
    "luminance, hue kept), aces (Hill's fit of the ACES RRT+ODT).",
)
@click.option(
    "--exposure",
    "exposure_text",
    default="auto",
    show_default=True,
    metavar="EV|auto",
    help="Exposure in stops, or auto: centre-weighted log-average luminance mapped "
    "to --key, adapting over a sequence.",
)
@click.option(
    "--center-weight",
    type=click.FloatRange(0, 1),
    default=0.75,
    show_default=True,
    help="Auto exposure: fraction of the metering weight in the centre spot (0 is "
    "the plain frame average).",
)
@click.option(
    "--key",
    type=click.FloatRange(min=0, min_open=True),
    default=0.18,
    show_default=True,
    help="Auto exposure: target log-average (middle grey).",
)
@click.option(
    "--white",
    type=click.FloatRange(min=0, min_open=True),
    help="Reinhard: luminance (after exposure) that maps to white; default infinite.",
)
@click.option(
    "--fps",
    type=click.FloatRange(min=0, min_open=True),
    default=30.0,
    show_default=True,
    help="Sequence: frames per second (for the adaptation).",
)
@click.option(
    "--tau-brighter",
    type=click.FloatRange(min=0, min_open=True),
    default=0.5,
    show_default=True,
    help="Sequence: adaptation time constant (s) when the scene gets brighter.",
)
@click.option(
    "--tau-darker",
    type=click.FloatRange(min=0, min_open=True),
    default=2.0,
    show_default=True,
    help="Sequence: adaptation time constant (s) when the scene gets darker.",
)
@click.option("--dither", is_flag=True, help="Triangular dither of +-1 code value (seeded).")
def tonemap(
    inputs,
    target,
    operator,
    exposure_text,
    center_weight,
    key,
    white,
    fps,
    tau_brighter,
    tau_darker,
    dither,
):
    """Tone-map HDR images (one or a sequence of frames) to 8-bit sRGB pictures.

    Each frame: exposure (a fixed EV, or auto), the tone operator, clamp to [0, 1], sRGB
    encoding (IEC 61966-2-1) and rounding to 8 bits; OUT is .png, .tga or .jpg. Auto exposure
    meters the centre-weighted log-average luminance (Reinhard 2002 eq. 1, weights favouring
    the centre of the frame) and maps it to --key; over a sequence the exposure adapts
    exponentially, with time constant --tau-brighter when the scene gets brighter and
    --tau-darker when it gets darker (63% of a step after one time constant). IN may be
    several files or a quoted glob (matches in name order, numbers numerically); a sequence
    needs {frame} in OUT (frame 0, 1, ...).

    \b
    Example:
      bakeshop tonemap probe.hdr preview.png --operator reinhard --white 8
      bakeshop tonemap 'shots/frame_*.exr' out/frame_{frame:04d}.png --operator aces
      bakeshop tonemap probe.hdr dark.png --operator none --exposure -3
    """
    from bakeshop import progress
    from bakeshop.io import read_image, write_image
    from bakeshop.light.tonemap import (
        adapt_exposure,
        auto_exposure,
        to_srgb8,
    )
    from bakeshop.light.tonemap import tonemap as apply_tonemap

    frames = expand_inputs(inputs)
    for frame in frames:
        require_hdr(frame)
    outputs = frame_paths(target, len(frames))
    for out in outputs:
        if not is_ldr(out):
            raise ArgumentError("tonemap writes 8-bit sRGB pictures: use .png, .tga or .jpg", out)
        refuse_overwriting_inputs(out, *frames)
    if len(set(outputs)) != len(outputs):
        raise ArgumentError("the output pattern gives several frames the same name", target)
    ev_fixed = parse_exposure(exposure_text)
    adapted = None
    evs = []
    for path, out in progress.track(
        list(zip(frames, outputs, strict=True)), "tone mapping", total=len(frames)
    ):
        image = read_image(path)
        if ev_fixed == "auto":
            target_ev = auto_exposure(image, center_weight=center_weight, key=key)
            adapted = adapt_exposure(
                [target_ev],
                frame_time=1.0 / fps,
                tau_brighter=tau_brighter,
                tau_darker=tau_darker,
                start=adapted,
            )[0]
            ev = float(adapted)
        else:
            ev = ev_fixed
        display = apply_tonemap(image, ev=ev, operator=operator, white=white)
        write_image(out, to_srgb8(display, dither="triangular" if dither else "none"))
        evs.append(ev)
    how = "auto" if ev_fixed == "auto" else "fixed"
    span = f"{evs[0]:+.2f} EV" if len(evs) == 1 else f"{min(evs):+.2f} to {max(evs):+.2f} EV"
    dest = outputs[0] if len(outputs) == 1 else f"{len(outputs)} frames ({target})"
    click.echo(f"wrote {dest}: {operator}, {how} exposure {span}, 8-bit sRGB")


def register(group: click.Group) -> None:
    """Add ``fresnel`` and ``tonemap`` to the ``bakeshop`` command."""
    group.add_command(fresnel)
    group.add_command(tonemap)
