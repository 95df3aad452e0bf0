"""``bakeshop unwrap``: photographs of a mirror ball unwrapped into one probe."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click
import numpy as np

from bakeshop.cli._numbers import Integer, Number, Numbers
from bakeshop.cli._paths import INPUT, OUTPUT, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    from bakeshop.photo.mirrorball import BallConvention, UnwrapLayout

#: Largest pixel coordinate or box side the options take (a photo 2^20 pixels across).
PIXELS = 1 << 20


@click.command(context_settings={"max_content_width": 100})
@click.argument("balls", nargs=-1, required=True, type=INPUT)
@click.option(
    "-o", "--output", required=True, type=OUTPUT, help="The probe (.exr, .hdr, .pfm, .png ...)."
)
@click.option(
    "--to",
    type=click.Choice(["latlong", "angular", "mirrorball"]),
    default="latlong",
    show_default=True,
    help="Output layout (DESIGN's: latlong centre -Z; angular and mirrorball HDRShop's).",
)
@click.option(
    "--size",
    type=Integer(8, 32768),
    help="Output height (latlong) or edge. Default: the ball's diameter in pixels "
    "across (a latlong that wide).",
)
@click.option(
    "--convention",
    type=click.Choice(["hdrshop", "physical"]),
    default="hdrshop",
    show_default=True,
    help="hdrshop: what HDRShop makes (the ball's centre looks forward, -Z); physical: the world "
    "as it was (the ball's centre shows what is behind the camera, +Z), for matching a set.",
)
@click.option(
    "--circle",
    "circles",
    multiple=True,
    type=Numbers(0, PIXELS, count=3),
    metavar="X,Y,R",
    help="The ball in each photo (pixels: centre and radius, refined to sub-pixel); repeat once "
    "per photo. Default: found automatically.",
)
@click.option(
    "--angle",
    type=Number(1, 179),
    default=90.0,
    show_default=True,
    help="Degrees between two views around the vertical; the sign is found from the photos.",
)
@click.option(
    "--exclude",
    type=Number(0, 60),
    default=25.0,
    show_default=True,
    help="Cone around each view's camera (the photographer) that view leaves to the other, "
    "degrees.",
)
@click.option(
    "--reflectance",
    type=Numbers(0.05, 1, count=(1, 3)),
    metavar="R|R,G,B",
    help="The ball's reflectance, divided out: chrome is about 0.6-0.8.",
)
@click.option(
    "--card",
    type=Numbers(0, PIXELS, count=4),
    metavar="X,Y,W,H",
    help="A grey card seen directly in the first photo (pixel box); with --card-reflection, "
    "measures the reflectance.",
)
@click.option(
    "--card-reflection",
    type=Numbers(0, PIXELS, count=4),
    metavar="X,Y,W,H",
    help="The same card's reflection in the ball (pixel box).",
)
def unwrap(
    balls: tuple[Path, ...],
    output: Path,
    to: UnwrapLayout,
    size: int | None,
    convention: BallConvention,
    circles: tuple[tuple[float, ...], ...],
    angle: float,
    exclude: float,
    reflectance: tuple[float, ...] | None,
    card: tuple[float, ...] | None,
    card_reflection: tuple[float, ...] | None,
) -> None:
    """Unwrap photographs of a mirror ball (BALLS: one, or two taken about 90 degrees apart
    around the vertical) into one probe.

    The ball is found in each photo (a circle fitted to its rim, to a fraction of a pixel);
    with two photos, each direction is taken from the view that sees it better, which removes
    the photographer and the camera (at each view's centre) and the stretched rim. Use merged
    HDR photos (bakeshop merge) for a light probe; 8-bit photos are unwrapped as they are. See
    docs/photographs.md.

    \b
    Example:
      bakeshop unwrap ball.exr -o probe.exr --to latlong --size 1024
      bakeshop unwrap ball_front.exr ball_side.exr -o probe.exr --reflectance 0.7
      bakeshop unwrap ball.exr -o probe.hdr --circle 1520.5,1010,640 --to angular
      bakeshop unwrap ball.exr -o probe.exr --card 100,80,40,40 --card-reflection 1400,900,12,12
    """
    from bakeshop import progress
    from bakeshop.io import HDR_CODECS, codec_for, read_image, write_image
    from bakeshop.photo import mirrorball as mb

    codec_for(output)
    refuse_overwriting_inputs(output, *balls)
    if len(balls) > 2:
        raise ArgumentError(f"unwrap takes one or two photos of the ball, not {len(balls)}")
    if circles and len(circles) != len(balls):
        raise ArgumentError(
            f"give --circle once per photo ({len(balls)}), not {len(circles)} times"
        )
    if (card is None) != (card_reflection is None):
        raise ArgumentError("--card and --card-reflection go together")
    if reflectance is not None and card is not None:
        raise ArgumentError("give --reflectance or --card, not both")
    linear = all(codec_for(p) in HDR_CODECS for p in balls)
    if not linear and (reflectance is not None or card is not None):
        raise ArgumentError("reflectance correction needs linear HDR photos (.exr, .hdr, .pfm)")
    photos, found = [], []
    for i, path in enumerate(balls):
        with progress.step(f"reading {path}"):
            photo = read_image(path)
        guess = None
        if circles:
            x, y, r = circles[i]
            guess = mb.Circle(x, y, r)
        with progress.step(f"finding the ball in {path}"):
            try:
                circle = mb.find_ball(photo, guess=guess)
            except ArgumentError as e:
                raise ArgumentError(f"{e.reason}; give it with --circle X,Y,R", path) from None
        click.echo(
            f"{Path(path).name}: ball at ({circle.x:.2f}, {circle.y:.2f}), radius "
            f"{circle.radius:.2f} px (rim fit RMS {circle.residual:.2f} px over {circle.points} "
            "points)"
        )
        photos.append(photo)
        found.append(circle)
    if size is None:  # the ball's diameter across: the latlong's width, a square's edge
        size = int(np.ceil(2 * max(c.radius for c in found)))
        size = max(8, size // 2) if to == "latlong" else size
    with progress.step("unwrapping"):
        if len(photos) == 1:
            out = mb.unwrap(photos[0], found[0], to=to, size=size, convention=convention)
            note = ""
        else:
            yaw, plus, minus = mb.best_yaw(photos, found, angle_deg=angle, convention=convention)
            out, weight = mb.merge_views(
                photos, found, yaws_deg=[0.0, yaw], to=to, size=size, convention=convention,
                exclude_deg=exclude,
            )  # fmt: skip
            unseen = float(((weight == 0) & (out.sum(-1) != 0)).mean())
            note = (
                f"; second view turned {yaw:+.0f} deg (log disagreement {min(plus, minus):.3f} "
                f"against {max(plus, minus):.3f} the other way), {100 * unseen:.2f}% seen by "
                "neither"
            )
    if card is not None and card_reflection is not None:  # both or neither (checked above)
        factor = mb.card_reflectance(
            photos[0],
            list(card),
            list(card_reflection),
        )
        if not np.all((factor >= 0.05) & (factor <= 1.2)):
            raise ArgumentError(
                f"the grey card gives an implausible reflectance {np.round(factor, 3).tolist()}"
            )
    elif reflectance is not None:
        factor = np.asarray(reflectance)
    else:
        factor = None
    if factor is not None:
        out = out / np.broadcast_to(factor, (out.shape[-1],)).astype(np.float32)
        note += f"; divided by the ball's reflectance {np.round(factor, 3).tolist()}"
    with progress.step(f"writing {output}"):
        write_image(output, out)
    h, w = out.shape[:2]
    click.echo(
        f"wrote {output}: {to} {w}x{h} in the {convention} convention from {len(photos)} "
        f"view{'s' if len(photos) > 1 else ''}{note}"
        + ("" if linear else " (8-bit photos: display-encoded values unwrapped as they are)")
    )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(unwrap)
