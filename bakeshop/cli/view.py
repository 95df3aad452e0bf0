"""``bakeshop view``: the bake in the browser (WebGL2, the preview's shaders), served locally."""

from __future__ import annotations

import time
import webbrowser
from pathlib import Path

import click

from bakeshop.cli._numbers import Integer


@click.command(context_settings={"max_content_width": 100})
@click.argument("bake_dir", metavar="BAKE_DIR", type=click.Path(path_type=Path))
@click.option(
    "--port",
    type=Integer(0, 65535),
    default=0,
    show_default=True,
    help="Port on 127.0.0.1 (0: a free one).",
)
@click.option("--no-browser", is_flag=True, help="Print the address; do not open a browser.")
def view(bake_dir: Path, port: int, no_browser: bool) -> None:
    """Show what `bake-probe` wrote into BAKE_DIR in the browser, until Ctrl-C.

    A local page (served by the standard library on 127.0.0.1 only, answering a fixed set of
    routes: never a file path from a request) draws the sky and the material balls with WebGL2
    and the same GLSL as `bakeshop preview`, from the bake's own texels (the cube, every level
    of the GGX chain, the DFG table, the DIM pair; nothing re-filtered). Drag to orbit, scroll
    to zoom; the panel sets the exposure (or auto), the tone curve, the sky (the environment or
    a level of the chain) and the sun as a GGX light. The page's URL holds the view, so it can
    be shared or screenshot; `bakeshop preview` with the same view gives the same picture
    (docs/preview.md). Opens the system's browser when there is one.

    \b
    Example:
      bakeshop bake-probe -o demo
      bakeshop view demo
      bakeshop view demo --port 8765 --no-browser   # then open http://127.0.0.1:8765/
    """
    from bakeshop.preview import read_bake
    from bakeshop.preview.server import serve

    bake = read_bake(bake_dir)
    viewer = serve(bake, port=port)
    click.echo(f"bakeshop view: {bake_dir} at {viewer.url} (Ctrl-C stops)")
    if not no_browser:
        try:
            webbrowser.open(viewer.url)
        except webbrowser.Error:
            pass
    try:
        while True:
            time.sleep(3600)
    finally:
        viewer.close()


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(view)
