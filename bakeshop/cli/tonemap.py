"""``bakeshop tonemap``: exposure, tone mapping and adaptation of HDR frames to 8-bit pictures."""

from __future__ import annotations

import glob
import os
import re
import string
from collections.abc import Iterable
from pathlib import Path

import click

from bakeshop.cli._common import (
    alpha_option,
    environment_weights,
    fit_alpha,
    is_picture,
    linearise,
    output_bits,
    parse_exposure_mode,
    srgb_decode_option,
    warn,
)
from bakeshop.cli._numbers import Exposure, Number
from bakeshop.cli._paths import FRAMES, OUTPUT_FRAMES, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError
from bakeshop.io import check_input, stored_bits
from bakeshop.sphere import FILE_LAYOUTS


def _natural_key(path: str) -> list[tuple[int, int, str]]:
    """Sort key that orders frame_2 before frame_10."""
    return [(0, int(t), "") if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", path)]


def expand_inputs(patterns: Iterable[str | os.PathLike]) -> list[Path]:
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
    """Output names: ``target`` for one frame; ``target.format(frame=i)`` for a sequence (its
    braces were checked when parsed: :data:`bakeshop.cli._paths.OUTPUT_FRAMES`)."""
    fields = {f for _, f, _, _ in string.Formatter().parse(target) if f is not None}
    if count > 1 and "frame" not in fields:
        raise ArgumentError(
            "several input frames need a {frame} pattern in the output name "
            "(for example out_{frame:04d}.png)",
            target,
        )
    try:
        return [Path(target.format(frame=i)) for i in range(count)]
    except (ValueError, IndexError) as e:
        raise ArgumentError(f"bad output pattern: {e}", target) from None


@click.command(context_settings={"max_content_width": 100})
@click.argument("inputs", nargs=-1, required=True, metavar="IN...", type=FRAMES)
@click.argument("target", metavar="OUT", type=OUTPUT_FRAMES)
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
    type=Exposure(("auto", "fit")),
    default="auto",
    show_default=True,
    metavar="EV|auto|fit",
    help="Exposure in stops, auto (centre-weighted log-average luminance of the "
    "texels that hold light mapped to --key, adapting over a sequence) or fit (only the "
    "brightest 0.1% clip).",
)
@click.option(
    "--from",
    "layout",
    type=click.Choice(FILE_LAYOUTS),
    help="Meter IN as an environment in this layout: texels weighted by solid angle, only the "
    "layout's valid ones (not a disk's outside or a cross's empty cells).",
)
@click.option(
    "--center-weight",
    type=Number(0, 1),
    default=0.75,
    show_default=True,
    help="Auto exposure: fraction of the metering weight in the centre spot (0 is "
    "the plain frame average).",
)
@click.option(
    "--key",
    type=Number(0, 1000, low_open=True),
    default=0.18,
    show_default=True,
    help="Auto exposure: target log-average (middle grey).",
)
@click.option(
    "--white",
    type=Number(0, 1e6, low_open=True),
    help="Reinhard: luminance (after exposure) that maps to white; default infinite.",
)
@click.option(
    "--fps",
    type=Number(0, 1000, low_open=True),
    default=30.0,
    show_default=True,
    help="Sequence: frames per second (for the adaptation).",
)
@click.option(
    "--tau-brighter",
    type=Number(0, 3600, low_open=True),
    default=0.5,
    show_default=True,
    help="Sequence: adaptation time constant (s) when the scene gets brighter.",
)
@click.option(
    "--tau-darker",
    type=Number(0, 3600, low_open=True),
    default=2.0,
    show_default=True,
    help="Sequence: adaptation time constant (s) when the scene gets darker.",
)
@click.option("--dither", is_flag=True, help="Triangular dither of +-1 code value (seeded).")
@click.option(
    "--bits",
    type=click.Choice(("8", "16")),
    help="Bits per sample of OUT (16: PNG only). Default 8, or 16 for 16-bit inputs.",
)
@srgb_decode_option
@alpha_option
def tonemap(
    inputs: tuple[Path, ...],
    target: Path,
    operator: str,
    exposure_text: float | str,
    center_weight: float,
    key: float,
    white: float | None,
    fps: float,
    tau_brighter: float,
    tau_darker: float,
    dither: bool,
    layout: str | None,
    bits: str | None,
    srgb_decode: bool,
    alpha: str | None,
) -> None:
    """Tone-map HDR images (one or a sequence of frames) to 8-bit sRGB pictures.

    Each frame: exposure (a fixed EV, or auto), the tone operator, clamp to [0, 1], sRGB
    encoding (IEC 61966-2-1) and rounding to 8 bits: the display rule of every command
    (docs/tonemap.md); OUT is .png, .tga or .jpg and records the exposure. Auto exposure
    meters the centre-weighted log-average luminance (Reinhard 2002 eq. 1, weights favouring
    the centre of the frame; with --from, solid angles over the layout's valid texels) and
    maps it to --key, leaving out texels that are black in every channel (no light: a cross's
    empty cells, a fresnel bake's lower half); over a sequence the exposure adapts
    exponentially, with time constant --tau-brighter when the scene gets brighter and
    --tau-darker when it gets darker (63% of a step after one time constant). IN may be
    several files or a quoted glob (matches in name order, numbers numerically); a sequence
    needs {frame} in OUT (frame 0, 1, ...).

    \b
    Example:
      bakeshop tonemap probe.hdr preview.png --operator reinhard --white 8
      bakeshop tonemap 'shots/frame_*.exr' out/frame_{frame:04d}.png --operator aces
      bakeshop tonemap probe.hdr dark.png --operator none --exposure -3
      bakeshop tonemap cross.exr cross.png --from cross-vertical
    """
    from bakeshop import progress
    from bakeshop.image import adapt_exposure, choose_exposure, to_picture
    from bakeshop.io import read_image, write_image

    frames = expand_inputs(inputs)
    outputs = frame_paths(str(target), len(frames))
    for out in outputs:
        if not is_picture(out):
            raise ArgumentError("tonemap writes pictures: use .png, .tga or .jpg", out)
        refuse_overwriting_inputs(out, *frames)
    if len(set(outputs)) != len(outputs):
        raise ArgumentError("the output pattern gives several frames the same name", target)
    ev_fixed = parse_exposure_mode(exposure_text)
    adapted = None
    evs = []
    for path, out in progress.track(
        list(zip(frames, outputs, strict=True)), "tone mapping", total=len(frames)
    ):
        image, meta = read_image(path, with_metadata=True)
        image, _ = linearise(image, path, meta, srgb_decode)
        image = fit_alpha(image, alpha, path, out)
        weights = None if layout is None else environment_weights(layout, image.shape[:2])
        if isinstance(ev_fixed, str):
            target_ev = choose_exposure(
                image, ev_fixed, weights=weights, key=key, center_weight=center_weight
            ).ev
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
        depth, note = output_bits(
            out,
            requested=None if bits is None else int(bits),
            inputs=[stored_bits(meta)],
            display=True,
        )
        shown = to_picture(
            image,
            ev=ev,
            operator=operator,
            white=white,
            bits=depth,
            dither="triangular" if dither else "none",
            weights=weights,
        )
        how = "" if not isinstance(ev_fixed, str) else f" ({ev_fixed}, adapted)"
        write_image(out, shown.pixels, description=shown.metadata() + how)
        rule = shown.describe().split(", ", 1)[1]  # the rule after the exposure, as for the others
        if note:
            warn(note, out)
        evs.append(ev)
    how = ev_fixed if isinstance(ev_fixed, str) else "fixed"
    span = f"{evs[0]:+.2f} EV" if len(evs) == 1 else f"{min(evs):+.2f} to {max(evs):+.2f} EV"
    dest = outputs[0] if len(outputs) == 1 else f"{len(outputs)} frames ({target})"
    click.echo(f"wrote {dest}: {operator}, {how} exposure {span}; {rule}")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(tonemap)
