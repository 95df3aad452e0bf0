"""Entry point of the ``bakeshop`` command (click for parsing, rich for progress).

Each command group lives in its own module of this package, which exposes ``register(group)``;
:data:`COMMANDS` lists them in the order ``--help`` shows them, and a command's module is
imported only when it runs (start-up pays for what the command uses). How a run behaves as a
process (signals, the one error line, warnings) is :mod:`bakeshop.cli._process`.
"""

from __future__ import annotations

import importlib
import sys
from typing import NoReturn

import click

from bakeshop import __version__, progress
from bakeshop.cli._budget import max_time_option
from bakeshop.cli._numbers import Integer
from bakeshop.cli._process import ByteSize, record_command_writes, run

#: command name -> (its module, the start of its help as ``--help`` lists it), in the order
#: ``--help`` shows them. A command's module is imported only when that command runs or shows
#: its own help (``bakeshop --version`` loads none); tests/cli/test_main.py checks the table
#: against the commands themselves.
COMMANDS: dict[str, tuple[str, str]] = {
    "info": (
        "info",
        (
            "Describe image files: format, size, channels, stored type, per-channel min/max/mean, "
            "NaN/Inf counts, dynamic range in..."
        ),
    ),
    "convert": (
        "convert",
        (
            "Convert SOURCE to TARGET, any supported format to any other (by extension: .hdr .pfm "
            ".exr .tga .png .jpg)."
        ),
    ),
    "resize": (
        "resize",
        "Resize SOURCE to TARGET with energy-preserving area resampling.",
    ),
    "remap": (
        "remap",
        "Convert the panorama SOURCE from one layout to another and write TARGET.",
    ),
    "merge": (
        "merge",
        "Merge bracketed exposures IMAGES (JPEG, PNG or TIFF, 8 or 16 bits) into one HDR image.",
    ),
    "unwrap": (
        "unwrap",
        (
            "Unwrap photographs of a mirror ball (BALLS: one, or two taken about 90 degrees apart "
            "around the vertical) into one..."
        ),
    ),
    "irradiance": (
        "irradiance",
        "Compute the diffuse irradiance map (DIM) of the probe IN and write it to OUT.",
    ),
    "sun": (
        "sun",
        "Find the sun of the probe IN and print its direction, size, colour and irradiance.",
    ),
    "dims": (
        "dims",
        "Make the DIM pair of the probe IN: sun_dim, shadow_dim, shadow_probe and sun.json.",
    ),
    "prefilter": (
        "prefilter",
        "Prefilter the environment IN into a glossy-reflection cube mip chain OUT.",
    ),
    "dfg": (
        "dfg",
        "Write the split-sum DFG lookup table to OUT: scale and bias on F0 per (n.v, roughness).",
    ),
    "bake-probe": (
        "bake_probe",
        "Bake everything the renderer needs from one probe IN (default: the embedded probe).",
    ),
    "fresnel": (
        "fresnel",
        "Bake the fresnel reflectance of flat water into an environment map.",
    ),
    "water": (
        "water",
        (
            "Water textures an engine loads: tileable, time-looping ocean normal maps (with "
            "heights, slopes, displacement and..."
        ),
    ),
    "tonemap": (
        "tonemap",
        "Tone-map HDR images (one or a sequence of frames) to 8-bit sRGB pictures.",
    ),
    "compress": (
        "compress",
        "Compress IN into the block format an engine samples, and measure what was lost.",
    ),
    "normals": (
        "normals",
        (
            "Tangent-space normal maps: combine macro and micro detail correctly, transfer a "
            "tileable detail into a mesh's UV..."
        ),
    ),
    "float": (
        "float",
        (
            "Float a mesh or a built-in shape in water and measure it: volume, mass, sample points,"
            " the exact Archimedes draft,..."
        ),
    ),
    "preview": (
        "preview",
        (
            "Render what `bake-probe` wrote into BAKE_DIR offscreen (OpenGL through moderngl over "
            "EGL; Mesa's llvmpipe without a..."
        ),
    ),
    "view": (
        "view",
        "Show what `bake-probe` wrote into BAKE_DIR in the browser, until Ctrl-C.",
    ),
    "bake": (
        "bake",
        (
            "Bake a level from RECIPE (TOML): probes, panoramas, normal maps, compressed textures "
            "and water, rebuilding only the..."
        ),
    ),
}

COMMAND_MODULES = list(dict.fromkeys(module for module, _ in COMMANDS.values()))

CONTEXT = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


class _Lazy(click.Group):
    """The root group: commands listed from :data:`COMMANDS`, each module imported on use."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in self.commands and name in COMMANDS:
            from bakeshop.cli._paths import guard_outputs

            importlib.import_module(f"bakeshop.cli.{COMMANDS[name][0]}").register(self)
            # before the command runs, none of its outputs may be one of its inputs
            guard_outputs(self)
        return self.commands.get(name)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        # the listing needs each command's first words only: no module is imported for it
        placeholders = {
            name: click.Command(name, help=text) for name, (_, text) in COMMANDS.items()
        }
        limit = formatter.width - 6 - max(len(name) for name in COMMANDS)
        rows = [(name, cmd.get_short_help_str(limit)) for name, cmd in placeholders.items()]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


@click.group(cls=_Lazy, context_settings=CONTEXT)
@click.version_option(__version__, "--version", prog_name="bakeshop")
@max_time_option
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
@click.option(
    "--threads",
    type=Integer(1, 4096),
    metavar="N",
    help="Threads of the compiled kernels (default: OMP_NUM_THREADS when set, else every "
    "processor this process may use).",
)
def cli(quiet: bool, max_decoded: int | None, threads: int | None) -> None:
    """The content pipeline of a real-time renderer: HDR light probes, panoramas and cube maps,
    diffuse irradiance, fresnel bakes, normal maps and buoyancy.

    Run 'bakeshop COMMAND --help' for what each command does, with an example. Errors are one
    line on stderr (exit status 2); SIGINT and SIGTERM clean up and exit 130 and 143.

    \b
    Example:
      bakeshop info probe.hdr
      bakeshop --max-decoded 8G convert flat_16k_mask.png mask.exr
      bakeshop --threads 1 irradiance probe.hdr irr.hdr
    """
    record_command_writes(click.get_current_context())
    if threads is not None:
        from bakeshop import threads as kernel_threads

        kernel_threads.use(threads)
    if not quiet:
        # bars on a terminal; elsewhere (a log) plain lines from steps longer than the log
        # interval only, so that a quick command's stderr is its error line alone
        progress.enable()
    if max_decoded is not None:
        from bakeshop.io import decode_budget

        click.get_current_context().with_resource(decode_budget(max_decoded))


def main(argv: list[str] | None = None) -> int:
    """Run the command line. Bad input and bad arguments exit 2 with one line on stderr and no
    traceback; SIGINT, SIGTERM and SIGHUP clean up and exit 128 + the signal number."""
    try:
        return run(cli, argv)
    finally:
        progress.disable()


def command() -> NoReturn:
    """The ``bakeshop`` executable: :func:`main`, then exit with its status."""
    sys.exit(main())


if __name__ == "__main__":
    command()
