"""Entry point of the ``bakeshop`` command (click for parsing, rich for progress).

Each command group lives in its own module of this package, which exposes ``register(group)``;
:data:`COMMAND_MODULES` lists them in the order ``--help`` shows them.
"""

from __future__ import annotations

import importlib
import sys

import click

from bakeshop import __version__, progress
from bakeshop.errors import BakeshopError

COMMAND_MODULES = [
    "images",
    "panorama",
    "fresnel",
    "normals",
    "light",
    "specular",
    "buoyancy",
    "water",
]

CONTEXT = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


class _Ordered(click.Group):
    def list_commands(self, ctx):
        return list(self.commands)


@click.group(cls=_Ordered, context_settings=CONTEXT)
@click.version_option(__version__, "--version", prog_name="bakeshop")
@click.option("--quiet", "-q", is_flag=True, help="No progress bars.")
def cli(quiet: bool):
    """The content pipeline of a real-time renderer: HDR light probes, panoramas and cube maps,
    diffuse irradiance, fresnel bakes, normal maps and buoyancy.

    Run 'bakeshop COMMAND --help' for what each command does, with an example.
    """
    if not quiet:
        progress.enable()


for _name in COMMAND_MODULES:
    importlib.import_module(f"bakeshop.cli.{_name}").register(cli)


def error(message: str) -> int:
    """Print ``bakeshop: error: message`` on stderr and return the exit status 2."""
    click.echo(f"bakeshop: error: {message}", err=True)
    return 2


def main(argv: list[str] | None = None) -> int:
    """Run the command line; bad input and bad arguments exit 2 with one line, no traceback."""
    try:
        return cli.main(args=argv, prog_name="bakeshop", standalone_mode=False) or 0
    except BakeshopError as e:
        return error(str(e))
    except click.UsageError as e:
        where = e.ctx.command_path if e.ctx is not None else "bakeshop"
        return error(f"{e.format_message()} (see '{where} --help')")
    except click.ClickException as e:
        return error(e.format_message())
    except (click.Abort, KeyboardInterrupt):
        click.echo("bakeshop: interrupted", err=True)
        return 130
    except OSError as e:
        return error(f"{e.filename}: {e.strerror}" if e.filename else str(e))
    finally:
        progress.disable()


if __name__ == "__main__":
    sys.exit(main())
