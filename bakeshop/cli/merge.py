"""``bakeshop merge``: bracketed exposures merged into one HDR image, with the sun kept."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from bakeshop.cli._common import parse_options
from bakeshop.cli._numbers import Integer, Number, Numbers
from bakeshop.cli._paths import INPUT, OUTPUT, refuse_overwriting_inputs
from bakeshop.cli.convert import codec_options
from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    from bakeshop.photo import CameraResponse, ExposureStack


def _response(
    spec: str,
    stack: ExposureStack,
    *,
    gamma: float,
    smoothness: float,
    samples: int,
    shifts: np.ndarray | None,
    clip_low: float,
    clip_high: float,
) -> CameraResponse:
    from bakeshop.io import read_json
    from bakeshop.photo import known_response, recover_response
    from bakeshop.photo.response import KNOWN_CURVES, RESPONSE_METHODS, CameraResponse

    channels = stack.codes.shape[3]
    if spec in KNOWN_CURVES:
        return known_response(spec, gamma=gamma, channels=channels)
    if spec in RESPONSE_METHODS:
        return recover_response(
            stack.codes, stack.exposures, method=spec, smoothness=smoothness, samples=samples,
            shifts=shifts, clip_low=clip_low, clip_high=clip_high,
        )  # fmt: skip
    path = Path(spec)
    if path.suffix.lower() != ".json":
        choices = ", ".join((*RESPONSE_METHODS, *KNOWN_CURVES))
        raise ArgumentError(f"--response takes {choices} or a saved response .json, not {spec!r}")
    return CameraResponse.from_dict(read_json(path), path)


def _describe_frame(stack: ExposureStack, j: int) -> str:
    s = stack.settings[j] if stack.settings else {}
    t = s.get("exposure_time")
    parts = []
    if t is not None:
        parts.append(f"1/{1 / t:.4g} s" if t < 1 else f"{t:.4g} s")
    if s.get("f_number"):
        parts.append(f"f/{s['f_number']:.3g}")
    if s.get("iso"):
        parts.append(f"ISO {s['iso']:.0f}")
    if s.get("source") == "given":
        parts.append("(given)")
    return " ".join(parts) or f"exposure {stack.exposures[j]:.4g}"


def _layout_for(shape: tuple[int, ...], given: str | None) -> str | None:
    if given is not None:
        return None if given == "photo" else given
    h, w = shape[:2]
    return "latlong" if w == 2 * h else None


@click.command(context_settings={"max_content_width": 100})
@click.argument("images", nargs=-1, required=True, type=INPUT)
@click.option(
    "-o", "--output", required=True, type=OUTPUT, help="The HDR image (.exr, .hdr, .pfm, .tif)."
)
@click.option(
    "--times",
    type=Numbers(0, 3600, count=None, fractions=True, low_open=True),
    metavar="T1,T2,...",
    help="Exposure times in seconds, one per image in the order given (1/1000 or 0.001); "
    "overrides EXIF. Needed when the files carry no EXIF.",
)
@click.option(
    "--f-numbers",
    type=Numbers(0.5, 256, count=None, fractions=True),
    metavar="N1,N2,...",
    help="f-numbers, one per image (overrides EXIF).",
)
@click.option(
    "--isos",
    type=Numbers(1, 1e7, count=None),
    metavar="S1,S2,...",
    help="ISO speeds, one per image (overrides EXIF).",
)
@click.option(
    "--response",
    "response_spec",
    default="debevec",
    show_default=True,
    metavar="debevec|robertson|srgb|gamma|linear|FILE.json",
    help="The camera's curve: recovered from the stack (debevec, robertson), known (srgb for "
    "camera JPEGs, gamma, linear for raw-developed TIFFs), or saved by --save-response.",
)
@click.option(
    "--gamma",
    type=Number(0.2, 5),
    default=2.2,
    show_default=True,
    help="Exponent of --response gamma.",
)
@click.option(
    "--save-response", type=OUTPUT, help="Write the curve used as JSON, to reuse for this camera."
)
@click.option(
    "--smoothness",
    type=Number(1e-3, 1e3),
    default=50.0,
    show_default=True,
    help="Debevec's smoothness weight.",
)
@click.option(
    "--samples",
    type=Integer(16, 100000),
    default=1500,
    show_default=True,
    help="Sample pixels per channel for recovery.",
)
@click.option(
    "--align",
    is_flag=True,
    help="Align hand-held frames (median-threshold bitmaps, then sub-pixel).",
)
@click.option(
    "--max-shift",
    type=Integer(1, 1024),
    default=64,
    show_default=True,
    help="Largest shift --align searches, pixels.",
)
@click.option(
    "--ghost",
    type=Number(0.05, 5),
    help="Suppress ghosts: leave out of each pixel the frames whose value differs from the "
    "best-exposed frame's by more than this natural-log ratio beyond noise (0.25 is "
    "about 28 %). Default off.",
)
@click.option(
    "--sun",
    "sun_mode",
    type=click.Choice(["auto", "model", "off"]),
    default="auto",
    show_default=True,
    help="A sun clipped in every frame: auto models it from its aureole (or --sun-illuminance) "
    "when the output is a panorama; model does the same and fails when it cannot; off leaves "
    "the clipped values (lower bounds).",
)
@click.option(
    "--sun-illuminance",
    type=Number(1e-12, 1e12),
    help="The sun's irradiance at normal incidence in the output's units (lux when the frames' "
    "time, f-number and ISO are known; clear-sky direct sun is about 100000 lux). Default: "
    "from the aureole.",
)
@click.option(
    "--layout",
    type=click.Choice(["latlong", "angular", "mirrorball", "photo"]),
    help="What the frames show, for the sun: a panorama layout, or photo (no sun recovery). "
    "Default: latlong for 2:1 frames, else photo.",
)
@click.option(
    "--confidence",
    type=OUTPUT,
    help="Where to save the confidence map. Default: OUTPUT's name + _confidence.exr.",
)
@click.option(
    "--clip-high",
    type=Number(0.5, 1),
    default=250 / 255,
    show_default="250/255",
    help="Codes at or above this fraction of full scale are clipped.",
)
@click.option(
    "--clip-low",
    type=Number(0, 0.5),
    default=2 / 255,
    show_default="2/255",
    help="Codes at or below this fraction are clipped.",
)
@codec_options
def merge(
    images: tuple[Path, ...], output: Path, times: tuple[float, ...] | None,
    f_numbers: tuple[float, ...] | None, isos: tuple[float, ...] | None, response_spec: str,
    gamma: float, save_response: Path | None, smoothness: float, samples: int, align: bool,
    max_shift: int, ghost: float | None, sun_mode: str, sun_illuminance: float | None,
    layout: str | None, confidence: Path | None, clip_high: float, clip_low: float,
    options: tuple[str, ...],
) -> None:  # fmt: skip
    """Merge bracketed exposures IMAGES (JPEG, PNG or TIFF, 8 or 16 bits) into one HDR image.

    Exposures come from EXIF (time, f-number, ISO) or --times. The camera's response is
    recovered from the stack (Debevec-Malik by default) or given; each pixel is the
    inverse-variance weighted mean of the frames that see it unclipped in every channel. A sun
    that every frame clipped is modelled from its unclipped aureole (Buie's sunshape) when the
    frames are a panorama. Beside the HDR, a confidence map: R the frames that voted, G their
    weight, B the status (0 measured, 1 clipped in every frame, 2 dark in every frame, 3
    modelled). An .exr holds half floats unless a value exceeds 65504 (a sun): then 32-bit
    floats, said in a warning (-O pixel_type=float asks for them). See docs/photographs.md.

    \b
    Example:
      bakeshop merge IMG_01*.jpg -o probe.exr
      bakeshop merge pano_*.tif -o probe.exr --response linear --sun-illuminance 95000
      bakeshop merge a.png b.png c.png --times 1/1000,1/125,1/15 -o sky.hdr --align --ghost 0.25
      bakeshop merge IMG_*.jpg -o hdr.exr --save-response camera.json
      bakeshop merge IMG_*.jpg -o hdr.exr --response camera.json --sun off
      bakeshop merge IMG_*.jpg -o hdr.exr -O pixel_type=float -O compression=piz
    """
    from bakeshop import progress
    from bakeshop.io import check_write_options, write_image, write_json
    from bakeshop.photo import (
        CLIPPED,
        DARK,
        MODELLED,
        confidence_image,
        merge_stack,
        read_stack,
    )
    from bakeshop.photo.align import align_stack
    from bakeshop.photo.sun import recover_sun

    writer_options = parse_options(options)
    check_write_options(output, writer_options)  # before any work
    confidence = confidence or output.with_name(output.stem + "_confidence.exr")
    refuse_overwriting_inputs(output, *images)
    refuse_overwriting_inputs(confidence, *images, output)
    if save_response is not None:
        refuse_overwriting_inputs(save_response, *images, output)
    if clip_high - clip_low < 0.25:
        raise ArgumentError("--clip-high must exceed --clip-low by at least 0.25")
    for option, values in (("--times", times), ("--f-numbers", f_numbers), ("--isos", isos)):
        if values is not None and len(values) != len(images):
            raise ArgumentError(f"{len(images)} images need {len(images)} values for {option}")
    with progress.step(f"reading {len(images)} frames"):
        stack = read_stack(images, exposure_times=times, f_numbers=f_numbers, isos=isos)
    p, h, w, c = stack.codes.shape
    click.echo(
        f"frames: {p} of {w}x{h}, {stack.bits}-bit, exposures spanning {stack.span_stops:.1f} stops"
        + (" (absolute: values in cd/m^2)" if stack.absolute else " (relative values)")
    )
    shifts = None
    if align:
        shifts = align_stack(
            stack.codes, max_shift=max_shift, clip_low=clip_low, clip_high=clip_high
        )
        worst = float(np.abs(shifts).max())
        click.echo(f"aligned to frame {p // 2 + 1}: largest shift {worst:.2f} px")
    with progress.step("recovering the camera response"):
        response = _response(
            response_spec, stack, gamma=gamma, smoothness=smoothness, samples=samples,
            shifts=shifts, clip_low=clip_low, clip_high=clip_high,
        )  # fmt: skip
    if response.samples:
        fit = ", ".join(f"{v:.3f}" for v in response.fit_error_stops)
        click.echo(
            f"response: {response.method} from {response.samples} samples, fit RMS {fit} stops"
        )
    else:
        click.echo(f"response: {response.method}")
    merged = merge_stack(
        stack, response, shifts=shifts, ghost=ghost, clip_low=clip_low, clip_high=clip_high
    )
    for j in range(p):
        line = (
            f"  {Path(stack.names[j]).name}: {_describe_frame(stack, j)}, clipped "
            f"{100 * merged.clipped_high[j]:.2f}% bright, {100 * merged.clipped_low[j]:.2f}% dark"
        )
        if ghost is not None:
            line += f", {100 * merged.ghost_rejected[j]:.2f}% left out as ghosts"
        click.echo(line)
    click.echo(
        f"merged: {100 * (merged.votes > 0).mean():.3f}% of pixels measured, "
        f"{100 * merged.fraction(CLIPPED):.4f}% clipped in every frame, "
        f"{100 * merged.fraction(DARK):.4f}% dark in every frame"
    )
    radiance, status = merged.radiance, merged.status
    where = _layout_for(radiance.shape, layout)
    clipped = merged.fraction(CLIPPED) > 0
    if sun_mode == "off":
        if clipped:
            click.echo("sun: not modelled (--sun off): the clipped pixels hold lower bounds")
    elif not clipped:
        if sun_mode == "model":
            raise ArgumentError("no pixel is clipped in every frame: there is no sun to model")
        click.echo("sun: nothing is clipped in every frame")
    elif where is None:
        message = (
            "the frames are not a panorama (2:1, or --layout), so the clipped sun is not modelled"
        )
        if sun_mode == "model":
            raise ArgumentError(message)
        click.echo(f"sun: {message}")
    else:
        with progress.step("modelling the clipped sun"):
            radiance, status, found = recover_sun(
                radiance, status, where, irradiance=sun_illuminance
            )
        if found is None or found.source == "clipped":
            why = found.reason if found else "the clipped texels hold no measurable aureole"
            if sun_mode == "model":
                raise ArgumentError(f"{why}; give the sun's --sun-illuminance")
            click.echo(
                f"sun: not modelled: {why}; the clipped values are kept as lower bounds "
                "(--sun-illuminance sets the sun's light)"
            )
        else:
            from bakeshop.image import luminance

            gained = luminance(found.irradiance[None])[0] / max(
                luminance(found.merged_irradiance[None])[0], 1e-300
            )
            how = (
                f"aureole slope {found.aureole_slope:.2f}, circumsolar ratio "
                f"{found.circumsolar_ratio:.3f}"
                if found.source == "aureole" else "scaled to --sun-illuminance"
            )  # fmt: skip
            click.echo(
                f"sun: modelled {found.texels} texels within "
                f"{found.clipped_radius_deg:.2f} deg "
                f"({how}); its irradiance {luminance(found.irradiance[None])[0]:.4g} is "
                f"{gained:.1f}x what the clipped frames held; the sun gives "
                f"{100 * found.share:.0f}% of the light on a surface facing it"
            )
    merged.radiance, merged.status = radiance, status
    with progress.step(f"writing {output}"):
        write_image(output, radiance, **writer_options)
        write_image(confidence, confidence_image(merged))
    if save_response is not None:
        write_json(save_response, response.to_dict())
    extra = f" and {save_response}" if save_response else ""
    click.echo(
        f"wrote {output} and {confidence}{extra}"
        + (
            f" ({100 * float((status == MODELLED).mean()):.4f}% modelled)"
            if (status == MODELLED).any()
            else ""
        )
    )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(merge)
