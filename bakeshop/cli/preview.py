"""``bakeshop preview``: render a bake offscreen (sky, material balls, golf course) to PNGs."""

from __future__ import annotations

import time
from pathlib import Path

import click

from bakeshop.cli._common import parse_exposure_mode
from bakeshop.cli._numbers import Exposure, Fields, Number, Size
from bakeshop.cli._paths import check_output_name, parse_size, refuse_overwriting_inputs
from bakeshop.errors import ArgumentError

#: what ``--scene all`` renders.
ALL_SCENES = ("sky", "balls", "golf")
#: the largest picture side.
MAX_SIDE = 8192


#: ``--camera YAW,PITCH,DISTANCE[,FOV]``: degrees, degrees (open), metres, degrees (open).
CAMERA = Fields(
    {
        "yaw": Number(-360, 360),
        "pitch": Number(-90, 90, low_open=True, high_open=True),
        "distance": Number(0, 1e6, low_open=True),
        "fov": Number(0, 180, low_open=True, high_open=True),
    },
    sep=",",
    required=3,
)


@click.command(context_settings={"max_content_width": 100})
@click.argument("bake_dir", metavar="BAKE_DIR", type=click.Path(file_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    "target",
    metavar="OUT",
    help="The PNG to write; {scene} in it is replaced by the scene's name (needed with several "
    "scenes). Default: BAKE_DIR/preview_{scene}.png.",
)
@click.option(
    "--scene",
    "scenes",
    multiple=True,
    type=click.Choice(("sky", "balls", "golf", "water", "all")),
    help="What to render (repeat for several): sky (the baked cube), balls (Lambertian balls "
    "by the sun DIM, the shadow DIM and the SH; a roughness x metalness grid of GGX balls), "
    "golf (the course with DIM shadows), water (the course's pond up close), all (sky, balls, "
    "golf). Default: balls.",
)
@click.option(
    "--size", type=Size(MAX_SIDE), default="1280x720", show_default=True, metavar="WxH",
    help="Picture size in pixels.",
)  # fmt: skip
@click.option(
    "--camera",
    type=CAMERA,
    metavar="YAW,PITCH,DISTANCE[,FOV]",
    help="Orbit the scene's target: yaw from +Z towards +X and pitch in degrees, distance in "
    "metres, vertical field of view in degrees. Default: each scene's own view (the sky looks "
    f"forward, -Z, with a 90 degree field of view). [{CAMERA.describe_range()}]",
)
@click.option(
    "--exposure",
    "exposure_text",
    type=Exposure(("auto",)),
    default="auto",
    show_default=True,
    metavar="EV|auto",
    help="Exposure in stops, or auto: the bake's log-average radiance over the "
    "sphere to middle grey (the contact sheet's exposure, the same for every scene).",
)
@click.option(
    "--tonemap",
    "operator",
    type=click.Choice(("none", "reinhard", "aces")),
    default="aces",
    show_default=True,
    help="Tone curve after exposure (none clamps at 1).",
)
@click.option(
    "--sky-level",
    type=Number(-1, 64),
    default=-1.0,
    show_default=True,
    help="Background: -1 the environment cube; m >= 0 that level of detail of the specular "
    "chain (fractions blend two levels).",
)
@click.option(
    "--sun-light",
    is_flag=True,
    help="Balls: add sun.json's sun as a GGX light on top of the chain (the chain already "
    "holds the sun; this shows a sharp highlight the mips blur).",
)
@click.option(
    "--diffuse",
    type=click.Choice(("pair", "sun", "shadow", "sh")),
    default="pair",
    show_default=True,
    help="Golf: the DIM pair by the sun's shadow map, or one source everywhere (sun DIM, "
    "shadow DIM, SH).",
)
@click.option("--no-water", is_flag=True, help="Golf: leave the pond and the sea out.")
def preview(
    bake_dir: Path,
    target: str | None,
    scenes: tuple[str, ...],
    size: str | int | tuple[int, int],
    camera: tuple[float, ...] | None,
    exposure_text: str | float,
    operator: str,
    sky_level: float,
    sun_light: bool,
    diffuse: str,
    no_water: bool,
) -> None:
    """Render what `bake-probe` wrote into BAKE_DIR offscreen (OpenGL through moderngl over EGL;
    Mesa's llvmpipe without a GPU) and write PNGs.

    The shaders read exactly the baked files: the environment cube, the GGX chain (roughness
    m / (levels - 1) at mip m), the DFG table, the sun and shadow DIMs, sh.json and sun.json;
    nothing is re-filtered. GGX balls are the glTF metallic-roughness material: diffuse (1 -
    metalness) base * sun DIM(n), specular prefiltered(r, roughness) * (F0 A + B) with F0 =
    mix(0.04, base, metalness) (Karis 2013's split sum). On the golf course a fragment that the
    sun's shadow map sees takes the sun DIM, a shadowed one the shadow DIM. The pictures go
    through bakeshop's display rule (exposure, tone curve, sRGB, 8 bits) and record it; a numpy
    reference of the same equations checks the renders (docs/preview.md). Needs
    `pip install 'bakeshop[preview]'` and libEGL with Mesa (Debian: libegl1 libgl1-mesa-dri).

    \b
    Example:
      bakeshop bake-probe -o demo
      bakeshop preview demo                      # demo/preview_balls.png
      bakeshop preview demo --scene all --size 960x540
      bakeshop preview demo --scene balls -o balls.png --exposure 0 --sun-light
      bakeshop preview demo --scene golf --camera 20,35,110 --diffuse shadow -o shadowed.png
    """
    from bakeshop import progress
    from bakeshop.image import to_picture
    from bakeshop.io import write_image
    from bakeshop.preview import Camera, Renderer, View, bake_exposure, default_camera, read_bake

    chosen = []
    for s in scenes or ("balls",):
        for name in ALL_SCENES if s == "all" else (s,):
            if name not in chosen:
                chosen.append(name)
    parsed = parse_size(size)
    if isinstance(parsed, int):
        raise ArgumentError(f"invalid size {size!r}: expected WxH, each 1..{MAX_SIDE}")
    width, height = parsed
    ev = parse_exposure_mode(exposure_text)
    orbit = camera
    if target is None:
        target = str(bake_dir / "preview_{scene}.png")
    check_output_name(target, ("scene",))
    if len(chosen) > 1 and "{scene}" not in target:
        raise ArgumentError("several scenes need {scene} in the output name", target)
    outputs = {name: Path(target.replace("{scene}", name)) for name in chosen}
    for out in outputs.values():
        if out.suffix.lower() != ".png":
            raise ArgumentError("preview writes PNG pictures: name the output .png", out)

    started = time.perf_counter()
    bake = read_bake(bake_dir)
    for out in outputs.values():
        refuse_overwriting_inputs(out, *(bake_dir / name for name in (bake.files or {}).values()))
    if ev == "auto":
        ev = bake_exposure(bake)
    with Renderer(bake) as renderer:
        for name in progress.track(chosen, "rendering the preview", total=len(chosen)):
            eye = None
            if orbit is not None:
                base = default_camera(name)
                fov = orbit[3] if len(orbit) == 4 else base.fov
                eye = Camera(base.target, orbit[0], orbit[1], orbit[2], fov, base.near, base.far)
            view = View(
                name,
                width,
                height,
                camera=eye,
                diffuse=diffuse,
                sky_level=sky_level,
                sun_light=sun_light,
                water=not no_water,
            )
            linear = renderer.render(view)[..., :3]
            picture = to_picture(linear, ev=ev, operator=operator)
            write_image(outputs[name], picture.pixels, description=picture.metadata())
            click.echo(f"wrote {outputs[name]}: {name}, {width}x{height}, {picture.describe()}")
    click.echo(f"rendered {len(chosen)} view(s) in {time.perf_counter() - started:.2f} s")


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(preview)
