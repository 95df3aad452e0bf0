"""Recipe files: a level's bake described in TOML, validated completely before any work starts.

A recipe is a table per operation holding one named step per sub-table, with shared settings in
``[defaults.OPERATION]`` that a step's own keys override::

    [defaults.probe]
    specular_size = 128

    [probe.atrium]
    input = "probes/atrium.hdr"
    output = "baked/atrium"
    mips = 6                      # this probe differs

Paths are relative to the recipe's folder. Steps run in the file's order, except that a step
whose input is another step's output (that file, or a file in that output folder) runs after
it. Unknown tables, keys and operations are
errors that name the valid ones; so is a bad value (with its range), a missing input file that
no step makes, a circle of steps, and two steps writing the same path.

A bake writes and deletes only inside the folder the recipe governs: its own folder, or the
folder ``[bake] folder`` names (one outside the recipe's folder must be confirmed by the caller,
``--allow-folder`` on the command line). Every output, the manifest and the digest cache lie
there; no output is or holds the recipe, the manifest or the cache, and the manifest and the
cache are never an input.
"""

from __future__ import annotations

import functools
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

from bakeshop.bake.operations import OPERATIONS, Fail, Operation
from bakeshop.errors import ArgumentError, BakeshopError, FormatError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["Recipe", "Step", "load_recipe", "parse_recipe", "starter_recipe"]

#: keys of the ``[bake]`` table and their defaults (``{stem}``: the recipe's name without
#: ``.toml``, so that two recipes in one folder keep apart manifests; ``folder``: the one the
#: bake writes and deletes in).
BAKE_KEYS = {"manifest": "{stem}.bake.json", "cache": ".bakeshop", "folder": "."}
#: a recipe larger than this is not a level's (a 3000-step recipe is about 200 KiB).
MAX_RECIPE_BYTES = 4 << 20


@dataclass(frozen=True)
class Step:
    """One step of a recipe.

    Attributes
    ----------
    name : str
        ``OPERATION.NAME``, as in the recipe (``probe.atrium``).
    operation : str
    options : dict
        Every option of the operation, defaults filled in (inputs and outputs as absolute
        paths).
    inputs : tuple of Path
        The files the step reads (absolute).
    output : Path
        The file or folder it writes (absolute).
    after : tuple of str
        The steps whose outputs it reads.
    """

    name: str
    operation: str
    options: dict
    inputs: tuple[Path, ...]
    output: Path
    after: tuple[str, ...] = ()


@dataclass(frozen=True)
class Recipe:
    """A validated recipe: its steps in an order where every step follows those it reads;
    ``root`` is its folder (paths are relative to it), ``folder`` the one its bake may write
    and delete in."""

    path: Path
    root: Path
    steps: tuple[Step, ...]
    manifest: Path
    cache: Path
    folder: Path
    settings: dict = field(default_factory=dict)

    @functools.cached_property
    def _by_name(self) -> dict[str, Step]:
        return {s.name: s for s in self.steps}

    def step(self, name: str) -> Step:
        """The step called ``name`` (an error lists the steps when there is none)."""
        if name in self._by_name:
            return self._by_name[name]
        raise ArgumentError(
            f"no step {name!r} in the recipe; its steps are: "
            + ", ".join(s.name for s in self.steps),
            self.path,
        )

    def relative(self, path: Path) -> str:
        """``path`` as the recipe writes it (relative to its folder when inside it)."""
        try:
            return Path(path).relative_to(self.root).as_posix()
        except ValueError:
            return os.fspath(path)


def load_recipe(
    path: str | os.PathLike, *, allow_folder: str | os.PathLike | None = None
) -> Recipe:
    """Read and validate a recipe file (see the module notes); raises
    :class:`~bakeshop.errors.BakeshopError` naming the file and what is wrong. ``allow_folder``
    confirms a ``[bake] folder`` outside the recipe's own folder."""
    from bakeshop.io import check_input, open_input

    if "\0" in os.fspath(path):
        raise ArgumentError(
            "a path cannot hold a NUL character", os.fspath(path).replace("\0", "\\0")
        )
    path = Path(path)
    if check_input(path).st_size > MAX_RECIPE_BYTES:
        raise FormatError(f"a recipe is at most {MAX_RECIPE_BYTES >> 20} MiB of text", path)
    with open_input(path) as f:
        data = f.read(MAX_RECIPE_BYTES + 1)
    if len(data) > MAX_RECIPE_BYTES:  # it grew since the check
        raise FormatError(f"a recipe is at most {MAX_RECIPE_BYTES >> 20} MiB of text", path)
    try:
        document = tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError:
        raise FormatError("a recipe is UTF-8 text", path) from None
    except tomllib.TOMLDecodeError as e:
        raise FormatError(f"not valid TOML: {e}", path) from None
    except RecursionError:
        raise FormatError("not valid TOML: arrays or tables nested too deeply", path) from None
    except ValueError:  # an integer beyond Python's digit limit
        digits = sys.get_int_max_str_digits()
        raise FormatError(f"an integer of more than {digits} digits", path) from None
    return parse_recipe(document, path, allow_folder=allow_folder)


def parse_recipe(
    document: dict, path: str | os.PathLike, *, allow_folder: str | os.PathLike | None = None
) -> Recipe:
    """Validate a recipe already parsed from TOML (``path`` gives its folder and its name in
    messages; ``allow_folder`` as for :func:`load_recipe`)."""
    path = Path(path).resolve()
    root = path.parent

    def fail(reason: str) -> NoReturn:
        raise ArgumentError(reason, path)

    known = ["bake", "defaults", *OPERATIONS]
    for key, value in document.items():
        if key not in known:
            fail(f"unknown table [{key}]; a recipe has: {', '.join(known)}")
        if not isinstance(value, dict):
            fail(f"[{key}] must be a table")
    settings = dict(BAKE_KEYS)
    for key, value in document.get("bake", {}).items():
        if key not in BAKE_KEYS:
            fail(f"unknown key {key!r} in [bake]; valid: {', '.join(BAKE_KEYS)}")
        if not isinstance(value, str) or not value:
            fail(f"[bake] {key} must be a path (a string)")
        settings[key] = value
    defaults = document.get("defaults", {})
    for op_name, table in defaults.items():
        if op_name not in OPERATIONS:
            fail(f"unknown operation [defaults.{op_name}]; operations: {', '.join(OPERATIONS)}")
        if not isinstance(table, dict):
            fail(f"[defaults.{op_name}] must be a table")
        op = OPERATIONS[op_name]
        for key in table:
            if key in op.paths:
                fail(f"[defaults.{op_name}] {key}: inputs and outputs are set per step")
            if key not in op.options:
                fail(_unknown_key(op, key, f"[defaults.{op_name}]"))
    steps = []
    for op_name, tables in document.items():  # in the file's order
        if op_name not in OPERATIONS:
            continue
        op = OPERATIONS[op_name]
        for name, table in tables.items():
            where = f"[{op_name}.{name}]"
            if not isinstance(table, dict):
                fail(f"{where} must be a table (a step), not a value")
            merged = {**defaults.get(op_name, {}), **table}
            steps.append(_step(op, f"{op_name}.{name}", merged, root, where, fail))
    if not steps:
        fail("the recipe has no steps; add one, e.g. [probe.NAME] with input and output")
    folder = _resolve(settings["folder"], root, "[bake] folder", fail)
    if not _inside(folder, root):
        if allow_folder is None or Path(allow_folder).resolve() != folder:
            fail(
                f"[bake] folder is {folder}, outside the recipe's folder: the bake writes and "
                f"deletes there only when you confirm it (--allow-folder {folder})"
            )
        if not folder.is_dir():
            fail(f"[bake] folder {folder} is not a folder")
    manifest = _resolve(
        settings["manifest"].replace("{stem}", path.stem), root, "[bake] manifest", fail
    )
    cache = _resolve(settings["cache"], root, "[bake] cache", fail)
    _confine(steps, path, folder, manifest, cache, fail)
    return Recipe(
        path=path,
        root=root,
        steps=tuple(_order(steps, fail)),
        manifest=manifest,
        cache=cache,
        folder=folder,
        settings=settings,
    )


def _unknown_key(op: Operation, key: str, where: str) -> str:
    valid = [*op.paths, *op.options]
    return f"unknown key {key!r} in {where}; {op.name} takes: {', '.join(valid)}"


def _step(op: Operation, name: str, table: dict, root: Path, where: str, fail: Fail) -> Step:
    for key in table:
        if key not in op.paths and key not in op.options:
            fail(_unknown_key(op, key, where))
    options: dict[str, Any] = {}
    for key, kind in op.paths.items():
        value = table.get(key)
        optional = kind.endswith("?")
        if value is None:
            if not optional:
                fail(f"{where} needs {key} (a path)")
            options[key] = None
            continue
        options[key] = _resolve(value, root, f"{where} {key}", fail)
    for key, spec in op.options.items():
        value = table.get(key, spec.default)
        options[key] = spec.check(value, f"{where} {key}", fail)

    def step_fail(reason: str) -> NoReturn:
        fail(f"{where} {reason}")

    def resolve(value: object, what: str) -> Path:
        return _resolve(value, root, f"{where} {what}", fail)

    options.update(op.check(options, resolve, step_fail))  # cross-option rules, nested tables
    inputs = tuple(op.inputs(options))
    output = options[op.output_key]
    return Step(name=name, operation=op.name, options=options, inputs=inputs, output=output)


def _resolve(value: object, root: Path, what: str, fail: Fail) -> Path:
    if not isinstance(value, str) or not value:
        fail(f"{what} must be a path (a string)")
    if "\0" in value:
        fail(f"{what}: a path cannot hold a NUL character")
    return (root / value).resolve()


def _inside(path: Path, folder: Path) -> bool:
    """``path`` is ``folder`` or lies in it (both resolved)."""
    return path == folder or os.fspath(path).startswith(os.path.join(folder, ""))


def _confine(
    steps: list[Step], recipe: Path, folder: Path, manifest: Path, cache: Path, fail: Fail
) -> None:
    """Refuse a recipe whose bake could write or delete outside ``folder``, or replace the
    recipe, its manifest or cache, or an input with its own bookkeeping."""
    for what, path in (("[bake] manifest", manifest), ("[bake] cache", cache)):
        if path == folder or not _inside(path, folder):
            fail(f"{what} {path} must lie inside {folder}, the folder the bake writes in")
    if manifest.suffix != ".json" or _inside(recipe, cache) or _inside(manifest, cache):
        fail(
            "[bake] manifest must be a .json file apart from the recipe, and [bake] cache a "
            "folder holding neither"
        )
    for s in steps:
        if s.output == folder or not _inside(s.output, folder):
            fail(
                f"{s.name} writes {s.output}, outside {folder}: a bake writes only inside the "
                "folder it governs (its recipe's, or [bake] folder)"
            )
        for what, path in (("the recipe", recipe), ("its manifest", manifest)):
            if _inside(path, s.output):
                fail(f"{s.name} would write over {what} {path}")
        if _inside(s.output, cache) or _inside(cache, s.output):
            fail(f"{s.name} writes {s.output}, which overlaps the digest cache {cache}")
        for path in s.inputs:
            if path == manifest or _inside(path, cache):
                fail(f"{s.name} reads {path}, which the bake writes as its own bookkeeping")


def _order(steps: list[Step], fail: Fail) -> list[Step]:
    """Link each step to the steps whose outputs it reads; order them; refuse circles, two
    steps writing one path, inputs that neither exist nor are made, and inputs that are no
    regular file (a FIFO). Linear in the steps: each path is looked up with its folders in a
    table of the outputs."""
    from bakeshop.io import check_input

    makers: dict[Path, Step] = {}
    for s in steps:
        if s.output in makers:
            fail(f"{makers[s.output].name} and {s.name} both write {s.output}")
        makers[s.output] = s
    for s in steps:
        for folder in s.output.parents:
            if folder in makers:
                fail(f"{makers[folder].name} and {s.name} both write {s.output}")
    linked = []
    for s in steps:
        after: list[str] = []
        for path in s.inputs:
            maker = next((makers[p] for p in (path, *path.parents) if p in makers), None)
            if maker is None:
                if not path.exists():
                    fail(f"{s.name}: input {path} does not exist and no step makes it")
                try:
                    check_input(path)
                except BakeshopError as e:
                    fail(f"{s.name}: input {path} {e.reason}")
                continue
            if maker.name == s.name:
                fail(f"{s.name} reads its own output {path}")
            if maker.name not in after:
                after.append(maker.name)
        linked.append(Step(s.name, s.operation, s.options, s.inputs, s.output, tuple(after)))
    by_name = {s.name: s for s in linked}
    done: list[Step] = []
    state: dict[str, int] = {}  # 1: on the path being walked, 2: placed
    for first in linked:  # depth first, without recursion (a chain can be thousands long)
        if first.name in state:
            continue
        state[first.name] = 1
        walk = [(first, iter(first.after))]
        while walk:
            step, deps = walk[-1]
            dep = next(deps, None)
            if dep is None:
                walk.pop()
                state[step.name] = 2
                done.append(step)
            elif state.get(dep) == 1:
                chain = [p.name for p, _ in walk]
                fail(
                    "steps read each other's outputs in a circle: "
                    + " -> ".join(chain[chain.index(dep) :] + [dep])
                )
            elif dep not in state:
                state[dep] = 1
                walk.append((by_name[dep], iter(by_name[dep].after)))
    return done


#: name parts that mark a picture as a tangent-space normal map in a starter recipe.
NORMAL_MAP_MARKS = ("_n.", "_nrm.", "_normal.", "_normals.", "-normal.", "_nor_gl.")
#: folders a starter recipe does not look into (a bake's own outputs).
SKIPPED_FOLDERS = ("baked", "engine", "node_modules")
#: files a starter recipe lists at most.
MAX_STARTER_FILES = 500


def starter_recipe(folder: str | os.PathLike) -> str:
    """A commented starter recipe for the files in ``folder`` (and below it): a ``probe`` step
    for every float image (.hdr, .exr, .pfm), a ``normals`` step for every picture named like a
    normal map (``*_n.png``, ``*_normal.tga``, ...) with its first detail layer to fill in, and
    commented ``compress`` and ``water`` examples. The normals steps are commented out until a
    detail map is named, so the starter bakes as it is. Paths are relative to ``folder``, where the
    recipe is meant to be saved."""
    from bakeshop.io import CODECS, HDR_CODECS

    root = Path(folder)
    hdr = {e for name in HDR_CODECS for e in CODECS[name]}
    pictures = {e for name in ("ldr", "tga", "tiff") for e in CODECS[name]}
    probes, normal_maps = [], []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if any(p.startswith(".") or p in SKIPPED_FOLDERS for p in rel.parts[:-1]):
            continue
        if not path.is_file() or rel.name.startswith("."):
            continue
        ext = path.suffix.lower()
        if ext in hdr:
            probes.append(rel)
        elif ext in pictures and any(m in rel.name.lower() for m in NORMAL_MAP_MARKS):
            normal_maps.append(rel)
        if len(probes) + len(normal_maps) >= MAX_STARTER_FILES:
            break
    lines = [
        "# A bake recipe: 'bakeshop bake THIS_FILE' builds it, rebuilding only what changed;",
        "# --dry-run says what would run and why. 'bakeshop bake --operations' lists every key;",
        "# docs/recipes.md walks through one. Paths are relative to this file.",
        "",
        "# Settings every probe shares (a step's own keys override them).",
        "[defaults.probe]",
        "specular_size = 256      # face size of level 0 of the GGX chain",
        "mips = 9                 # levels of the GGX chain (roughness m / (mips - 1))",
        'format = "hdr"           # hdr, exr, pfm or tif: cube faces, DIMs, shadow probe',
        'container = "dds"        # dds, ktx or ktx2: the GGX chain and the DFG table',
        "",
    ]
    names: set[str] = set()
    first = None

    def unique(stem: str) -> str:
        base = "".join(c if c.isalnum() or c in "_-" else "_" for c in stem) or "step"
        name, i = base, 2
        while name in names:
            name, i = f"{base}_{i}", i + 1
        names.add(name)
        return name

    for rel in probes:
        name = unique(rel.stem)
        first = first or name
        lines += [f"[probe.{name}]", f'input = "{rel.as_posix()}"',
                  f'output = "baked/{name}"', ""]  # fmt: skip
    if not probes:
        lines += ["# No .hdr, .exr or .pfm probe was found here; a probe step reads like this:",
                  "# [probe.atrium]", '# input = "probes/atrium.hdr"',
                  '# output = "baked/atrium"', ""]  # fmt: skip
    for rel in normal_maps:
        name = unique(rel.stem)
        out = f"baked/{rel.stem}{rel.suffix.lower()}"
        lines += [
            "# Detail normal maps blended onto this one: name a detail map, then uncomment.",
            f"# [normals.{name}]",
            f'# macro = "{rel.as_posix()}"',
            f'# output = "{out}"',
            "# each layer: detail (a tileable normal map), tile, offset, rotate, strength, mask",
            '# layers = [{ detail = "textures/detail_n.png", tile = 8, strength = 1.0 }]',
            "",
        ]
    source = f"baked/{first}/specular.dds" if first else "baked/atrium/specular.dds"
    lines += [
        "# The GGX chain block-compressed for an engine (BC6H with its quality sidecar):",
        "# [compress.specular]",
        f'# input = "{source}"',
        '# output = "engine/specular_bc6h.ktx2"',
        "# zstd = true",
        "",
        "# A tileable, looping ocean normal-map sequence (16-bit PNG frames + JSON sidecar):",
        "# [water.ocean]",
        '# output = "baked/ocean"',
        "# wind = 8.0              # m/s at 10 m",
        "# size = 64.0             # patch side, m",
        "# resolution = 256",
    ]
    return "\n".join(lines) + "\n"
