"""``bakeshop bake``: run a recipe, rebuilding only what changed, and say why."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click

from bakeshop.cli._numbers import Integer

if TYPE_CHECKING:
    from bakeshop.bake import Decision


def _operations_text() -> str:
    from bakeshop.bake import OPERATIONS

    lines = []
    for op in OPERATIONS.values():
        lines.append(f"[{op.name}.NAME]  {op.summary}")
        for key, kind in op.paths.items():
            lines.append(
                f"  {key:<14} {kind} path" + (" (file or folder)" if kind == "output" else "")
            )
        for key, spec in op.options.items():
            if spec.choices:
                domain = " | ".join(map(str, spec.choices))
            elif spec.kind in ("int", "float", "pair"):
                domain = f"{spec.kind} in [{spec.low:g}, {spec.high:g}]"
            else:
                domain = spec.kind
            default = "unset" if spec.default is None else json.dumps(spec.default)
            help = f"; {spec.help}" if spec.help else ""
            lines.append(f"  {key:<14} {domain} (default {default}){help}")
        lines.append("")
    return "\n".join(lines)


@click.command(context_settings={"max_content_width": 100})
@click.argument("recipe", type=click.Path(dir_okay=False, path_type=Path), required=False)
@click.option(
    "--explain",
    is_flag=True,
    help="Say why each step that runs is rebuilt (which input, option, output or version changed).",
)
@click.option(
    "--dry-run",
    "-n",
    is_flag=True,
    help="Say what would be rebuilt and why; run nothing, write nothing.",
)
@click.option(
    "--force",
    "force",
    multiple=True,
    metavar="STEP",
    help="Rebuild STEP (e.g. probe.atrium) whatever its state; repeatable.",
)
@click.option(
    "--jobs",
    "-j",
    type=Integer(1, 256),
    default=1,
    show_default=True,
    metavar="N",
    help="Steps run at once, 1 to 256 (threads; each step after the ones it reads). The "
    "outputs are the same as one at a time.",
)
@click.option(
    "--allow-folder",
    type=click.Path(file_okay=False, path_type=Path),
    metavar="DIR",
    help="Let the bake write and delete in DIR, the [bake] folder of a recipe that names one "
    "outside its own folder (by default a bake touches only its recipe's folder).",
)
@click.option(
    "--init",
    is_flag=True,
    help="Write a commented starter RECIPE for the files in its folder (a probe step per "
    ".hdr/.exr/.pfm, normal-map and compress templates) and exit; never replaces a file.",
)
@click.option(
    "--operations",
    is_flag=True,
    help="List the operations a recipe can use, with every key, its range and default, and exit.",
)
def bake(
    recipe: Path | None,
    explain: bool,
    dry_run: bool,
    force: tuple[str, ...],
    jobs: int,
    allow_folder: Path | None,
    init: bool,
    operations: bool,
) -> None:
    """Bake a level from RECIPE (TOML): probes, panoramas, normal maps, compressed textures and
    water, rebuilding only the steps whose inputs, options or bakeshop version changed, or
    whose outputs were deleted or altered. Every file written is read back through bakeshop and
    compared with what was meant (bit-exact for lossless formats, within the stated error for
    RGBE and JPEG, byte-exact blocks) before it takes its name; RECIPE.bake.json beside it
    records each output's inputs, options, key, size and reload check. Docs: docs/recipes.md.

    \b
    A recipe (paths relative to it; [defaults.OP] is shared, a step's keys override it):
      [defaults.probe]
      specular_size = 128
      [probe.atrium]
      input = "probes/atrium.hdr"
      output = "baked/atrium"
      [compress.atrium_specular]
      input = "baked/atrium/specular.dds"     # made by probe.atrium: runs after it
      output = "baked/atrium/specular_bc6h.dds"
      [normals.crate]
      macro = "textures/crate_n.png"
      layers = [{ detail = "textures/grain_n.png", tile = 8, strength = 0.5 }]
      output = "baked/crate_n.png"
      [water.harbour]
      output = "baked/harbour"
      wind = 8.0

    \b
    Example:
      bakeshop bake --init level.toml
      bakeshop bake level.toml
      bakeshop bake level.toml --dry-run
      bakeshop bake level.toml --explain --force probe.atrium
      bakeshop bake level.toml --jobs 4
      bakeshop bake --operations
    """
    from bakeshop.bake import load_recipe, plan, run, starter_recipe

    if operations:
        click.echo(_operations_text().rstrip())
        return
    if recipe is None:
        raise click.UsageError("give a RECIPE (or --operations)")
    if init:
        _init(recipe, starter_recipe(recipe.parent if str(recipe.parent) else Path(".")))
        return
    loaded = load_recipe(recipe, allow_folder=allow_folder)
    manifest = loaded.relative(loaded.manifest)
    if dry_run:
        decisions = plan(loaded, force=force)
        for d in decisions:
            click.echo(d.describe())
        todo = sum(d.action == "build" for d in decisions)
        maybe = sum(d.action == "wait" for d in decisions)
        if todo or maybe:
            more = f", and {maybe} more if what they read changes" if maybe else ""
            click.echo(
                f"would rebuild {todo} of {len(decisions)} steps{more} (dry run: nothing written)"
            )
        else:
            click.echo(f"nothing to do: all {len(decisions)} steps are up to date")
        return

    def report(decision: Decision, record: dict | None) -> None:
        if record is not None:
            outs = record["outputs"]
            checked = sum(bool(o["reload"].get("ok")) for o in outs)
            click.echo(
                f"built      {decision.step} in {record['seconds']:.2f} s: {len(outs)} "
                f"file(s), {checked} re-read and checked"
            )
            for name in record["left"]:
                click.echo(
                    f"left in place: {name} (no step of the recipe makes it any more; "
                    "delete it yourself)"
                )
        elif decision.action == "blocked" or (explain and decision.action == "build"):
            click.echo(decision.describe())

    result = run(loaded, force=force, jobs=jobs, on_decision=report)
    n = len(result.decisions)
    if not result.built and not result.failed:
        click.echo(
            f"nothing to do: all {n} steps are up to date (checked in "
            f"{result.seconds:.2f} s, {result.hashed} file(s) hashed)"
        )
        return
    click.echo(
        f"baked {len(result.built)} of {n} steps in {result.seconds:.1f} s "
        f"({len(result.up_to_date)} up to date); manifest {manifest}"
    )
    if result.failed:
        errors = list(result.failed.values())
        for e in errors[1:]:
            click.echo(f"failed     {e}")
        raise errors[0]


def _init(recipe: Path, text: str) -> None:
    from bakeshop.errors import ArgumentError
    from bakeshop.io import write_text

    if recipe.exists():
        raise ArgumentError("already exists; --init never replaces a recipe", recipe)
    write_text(recipe, text)
    steps = sum(line.startswith("[probe.") for line in text.splitlines())
    click.echo(
        f"wrote {recipe}: {steps} probe step(s) for the files beside it; try: bakeshop bake "
        f"{recipe} --dry-run"
    )


def register(group: click.Group) -> None:
    """Add the command to the root group."""
    group.add_command(bake)
