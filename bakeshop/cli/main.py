"""Entry point of the ``bakeshop`` command (click for parsing, rich for progress).

Each command group lives in its own module of this package, which exposes ``register(group)``;
:data:`COMMAND_MODULES` lists them in the order ``--help`` shows them. How a run behaves as a
process (signals, the one error line, warnings) is :mod:`bakeshop.cli._process`.
"""

from __future__ import annotations

import importlib
import sys

import click

from bakeshop import __version__, progress
from bakeshop.cli._paths import guard_outputs
from bakeshop.cli._process import ByteSize, run

COMMAND_MODULES = [
    "info",
    "convert",
    "resize",
    "remap",
    "merge",
    "unwrap",
    "irradiance",
    "sun",
    "dims",
    "prefilter",
    "dfg",
    "bake_probe",
    "fresnel",
    "water",
    "tonemap",
    "compress",
    "normals",
    "float",
    "preview",
    "view",
    "bake",
]

CONTEXT = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


class _Ordered(click.Group):
    def list_commands(self, ctx):
        return list(self.commands)


@click.group(cls=_Ordered, context_settings=CONTEXT)
@click.version_option(__version__, "--version", prog_name="bakeshop")
@click.option(
    "--quiet",
    "-q",
    is_flag=True,
    help="No progress (bars on a terminal; in a log, a line every 5 s from long steps).",
)
@click.option(
    "--max-decoded",
    type=ByteSize(),
    metavar="SIZE",
    help="Largest image one input file may decode to, e.g. 8G (default: 1 GiB, or 256 bytes "
    "per byte of the file when that is more; a larger result is refused as a possible "
    "decompression bomb); 1 byte to 1 EiB.",
)
def cli(quiet: bool, max_decoded: int | None):
    """The content pipeline of a real-time renderer: HDR light probes, panoramas and cube maps,
    diffuse irradiance, fresnel bakes, normal maps and buoyancy.

    Run 'bakeshop COMMAND --help' for what each command does, with an example. Errors are one
    line on stderr (exit status 2); SIGINT and SIGTERM clean up and exit 130 and 143.

    \b
    Example:
      bakeshop info probe.hdr
      bakeshop --max-decoded 8G convert flat_16k_mask.png mask.exr
    """
    if not quiet:
        # bars on a terminal; elsewhere (a log) plain lines from steps longer than the log
        # interval only, so that a quick command's stderr is its error line alone
        progress.enable()
    if max_decoded is not None:
        from bakeshop.io import decode_budget

        click.get_current_context().with_resource(decode_budget(max_decoded))


for _name in COMMAND_MODULES:
    importlib.import_module(f"bakeshop.cli.{_name}").register(cli)
# before any command runs, none of its outputs may be one of its inputs (bakeshop.cli._common)
guard_outputs(cli)


def main(argv: list[str] | None = None) -> int:
    """Run the command line. Bad input and bad arguments exit 2 with one line on stderr and no
    traceback; SIGINT, SIGTERM and SIGHUP clean up and exit 128 + the signal number."""
    try:
        return run(cli, argv)
    finally:
        progress.disable()


if __name__ == "__main__":
    sys.exit(main())
