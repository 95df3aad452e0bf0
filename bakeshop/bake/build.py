"""Running a recipe incrementally: what to rebuild, why, and the manifest that proves the rest.

A step is up to date when its manifest record (``RECIPE.bake.json``) was made by the same
bakeshop version and code (:func:`source_digest`: a development checkout changes code without
changing its version) and operation version, from the same options, from inputs with the same
contents (SHA-256), and every output it wrote still has the contents it had when it was written
and re-read. Anything else rebuilds the step, and the first difference found in each of those
classes is its reason (:class:`Decision`). Contents are hashed only when a file's size,
modification time or inode differ from the digest cache (``.bakeshop/hashes.json``), so an
unchanged 1 GB input costs one ``stat``.

Steps run in the recipe's order (each after the steps whose outputs it reads), or with
``jobs`` > 1 several at once on dask's local threaded scheduler; a step whose
inputs come from a step rebuilt in this run is decided once that step is done, so an upstream
rebuild that gives the same bytes rebuilds nothing downstream. Every file a step writes goes
through :mod:`bakeshop.io` inside :func:`bakeshop.io.verify_writes`: it is read back and
compared with what was meant to be written before it takes its name, and the check is recorded
in the manifest. Outputs of a step's previous bake that it no longer writes are removed when
they are unchanged since (an edited one is left alone) and their names are still ones the step
makes (a renamed output is left in place, and said so). A failed step keeps the previous
outputs it did not replace, is recorded as failed (it runs again next time, saying so) and
stops the steps that read it; the others still run. The manifest is rewritten after every
step, so an interrupted bake resumes where it stopped.

The manifest and the digest cache are untrusted input: each is checked against its schema
(JSON types, output files inside the folder the recipe governs) and refused in one line when
it does not fit. A bake replaces or deletes only files it wrote itself: a file the manifest
records as the step's output, with the size and digest recorded, inside the step's output and
the governed folder, never an input of the recipe. Only regular files are hashed.
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import glob
import hashlib
import json
import os
import re
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from bakeshop import __version__, progress
from bakeshop.bake.manifest import (
    FileHashes,
    check_manifest,
    guard_writes,
    journal_path,
    makes,
    output_change,
    output_file,
    resume,
)
from bakeshop.bake.operations import OPERATIONS
from bakeshop.bake.recipe import Recipe, Step
from bakeshop.errors import BakeshopError

__all__ = ["BakeResult", "Decision", "FileHashes", "plan", "run", "step_key"]

#: version of the manifest's layout.
MANIFEST_VERSION = 1


@functools.cache
def source_digest() -> str:
    """SHA-256 (16 hex digits) of bakeshop's own Python sources: a bake made by other code is
    not trusted to match what this code would make, even under the same version number."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


@dataclass
class Decision:
    """What a bake does with one step: ``action`` is ``"build"``, ``"skip"`` (up to date),
    ``"wait"`` (a dry run cannot know yet: an input is remade first) or ``"blocked"`` (a step
    it reads failed); ``reasons`` say why, one sentence each."""

    step: str
    action: str
    reasons: list[str] = field(default_factory=list)

    def describe(self) -> str:
        """One line: the action, the step and its reasons."""
        words = {"build": "rebuild", "skip": "up to date", "wait": "maybe", "blocked": "not run"}
        why = "; ".join(self.reasons)
        return f"{words[self.action]:<10} {self.step}" + (f": {why}" if why else "")


@dataclass
class BakeResult:
    """What a bake did: ``decisions`` for every step in order, ``built`` (the steps that ran:
    the work done), ``failed`` (step -> error), ``seconds``, ``hashed`` (files read in full
    to hash them) and the ``manifest`` written."""

    decisions: list[Decision]
    built: list[str]
    failed: dict[str, BakeshopError]
    seconds: float
    hashed: int
    manifest: Path

    @property
    def up_to_date(self) -> list[str]:
        """The steps that were already up to date."""
        return [d.step for d in self.decisions if d.action == "skip"]


def _canonical(value: object, recipe: Recipe) -> Any:
    """``value`` as JSON data: paths relative to the recipe, dict keys sorted, tuples as lists."""
    if isinstance(value, Path):
        return recipe.relative(value)
    if isinstance(value, dict):
        return {k: _canonical(v, recipe) for k, v in sorted(value.items())}
    if isinstance(value, (list, tuple)):
        return [_canonical(v, recipe) for v in value]
    return value


def step_key(step: Step, recipe: Recipe, inputs: dict[str, str]) -> str:
    """The step's key: SHA-256 of its operation and algorithm version, bakeshop's version and
    code, its canonical options and its inputs' digests."""
    op = OPERATIONS[step.operation]
    document = {
        "operation": op.name,
        "operation_version": op.version,
        "bakeshop": __version__,
        "bakeshop_source": source_digest(),
        "options": _canonical(step.options, recipe),
        "inputs": inputs,
    }
    return hashlib.sha256(json.dumps(document, sort_keys=True).encode()).hexdigest()


def _load_manifest(recipe: Recipe) -> tuple[dict, str | None]:
    """The step records of the manifest, with what the journal of a killed bake adds, and a
    note when the manifest is of another layout."""
    from bakeshop.io import read_json

    records: dict[str, dict] = {}
    note = None
    if os.path.lexists(recipe.manifest):
        document = read_json(recipe.manifest)
        if document.get("manifest_version") != MANIFEST_VERSION:
            note = "the manifest was written by another version of bakeshop's bake"
        else:
            records = check_manifest(document, recipe)
    resume(recipe, records)
    return records, note


def _decide(
    step: Step,
    recipe: Recipe,
    record: dict | None,
    hashes: FileHashes,
    force: bool,
    note: str | None,
) -> tuple[Decision, dict]:
    op = OPERATIONS[step.operation]
    inputs = {}
    for path in step.inputs:
        digest = hashes.digest(path)
        if digest is None:
            raise BakeshopError(f"input of {step.name} not found", path)
        inputs[recipe.relative(path)] = digest
    reasons = []
    if force:
        reasons.append("forced")
    if record is None:
        reasons.append(note or "never built")
        return Decision(step.name, "build", reasons), inputs
    if "failed" in record:
        reasons.append(f"its last bake failed ({record['failed']})")
        return Decision(step.name, "build", reasons), inputs
    if record.get("bakeshop") != __version__:
        reasons.append(f"bakeshop version changed ({record.get('bakeshop')} -> {__version__})")
    elif record.get("bakeshop_source") != source_digest():
        reasons.append(
            f"bakeshop's code changed (version {__version__}, source "
            f"{record.get('bakeshop_source')} -> {source_digest()})"
        )
    if record.get("operation_version") != op.version:
        reasons.append(
            f"{op.name}'s algorithm version changed "
            f"({record.get('operation_version')} -> {op.version})"
        )
    old, new = record.get("options", {}), _canonical(step.options, recipe)
    for key in sorted(set(old) | set(new)):
        if old.get(key, _UNSET) != new.get(key, _UNSET):
            where, was, now = _first_difference(old.get(key, _UNSET), new.get(key, _UNSET))
            reasons.append(f"option {key}{where} changed ({_show(was)} -> {_show(now)})")
    before = record.get("inputs", {})
    for name, digest in inputs.items():
        if name not in before:
            reasons.append(f"new input {name}")
        elif before[name] != digest:
            reasons.append(f"input {name} changed")
    for name in before:
        if name not in inputs:
            reasons.append(f"input {name} is no longer read")
    for out in record.get("outputs", []):
        change = output_change(recipe, out, hashes)
        if change is not None:
            reasons.append(change)
    if not record.get("outputs"):
        reasons.append("no outputs recorded")
    return Decision(step.name, "build" if reasons else "skip", reasons), inputs


#: an option a record or a recipe does not hold.
_UNSET = object()


def _first_difference(old: object, new: object, where: str = "") -> tuple[str, object, object]:
    """Where two option values first differ (``.key`` and ``[i]`` steps into tables and lists
    of one length) and the two values there."""
    if isinstance(old, dict) and isinstance(new, dict):
        for key in sorted(set(old) | set(new), key=str):
            if old.get(key, _UNSET) != new.get(key, _UNSET):
                return _first_difference(
                    old.get(key, _UNSET), new.get(key, _UNSET), f"{where}.{key}"
                )
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        for i, (a, b) in enumerate(zip(old, new, strict=True)):
            if a != b:
                return _first_difference(a, b, f"{where}[{i}]")
    return where, old, new


def _show(value: object) -> str:
    return "unset" if value is _UNSET else json.dumps(value)


def plan(recipe: Recipe, *, force: Iterable[str] = ()) -> list[Decision]:
    """What :func:`run` would do now, and why, without running anything (a dry run)."""
    force = _check_force(recipe, force)
    records, note = _load_manifest(recipe)
    hashes = FileHashes(recipe.cache / "hashes.json")
    decisions: dict[str, Decision] = {}
    for step in recipe.steps:
        remade = [d for d in step.after if decisions[d].action in ("build", "wait")]
        if remade:
            decision, _ = _decide_waiting(
                step, recipe, records.get(step.name), hashes, step.name in force, note, remade
            )
        else:
            decision, _ = _decide(
                step, recipe, records.get(step.name), hashes, step.name in force, note
            )
        decisions[step.name] = decision
    return list(decisions.values())


def _decide_waiting(
    step: Step,
    recipe: Recipe,
    record: dict | None,
    hashes: FileHashes,
    force: bool,
    note: str | None,
    remade: list[str],
) -> tuple[Decision, dict]:
    """A dry run's decision for a step that reads outputs remade first: it rebuilds for its own
    reasons, or it waits to see whether those outputs change."""
    made = {p for p in step.inputs if any(_made_by(recipe, d, p) for d in remade)}
    own = [p for p in step.inputs if p not in made]
    reasons = ["forced"] if force else []
    if record is None:
        reasons.append(note or "never built")
    else:
        probe = Step(step.name, step.operation, step.options, tuple(own), step.output)
        partial = dict(
            record,
            inputs={
                k: v for k, v in record.get("inputs", {}).items() if recipe.root / k not in made
            },
        )
        decision, _ = _decide(probe, recipe, partial, hashes, False, note)
        reasons += decision.reasons
    if reasons:
        return Decision(step.name, "build", reasons), {}
    names = ", ".join(remade)
    return Decision(step.name, "wait", [f"rebuilt if {names} changes what it reads"]), {}


def _made_by(recipe: Recipe, name: str, path: Path) -> bool:
    out = recipe.step(name).output
    return path == out or out in path.parents


def _check_force(recipe: Recipe, force: Iterable[str]) -> set[str]:
    names = set(force)
    for name in names:
        recipe.step(name)  # raises, listing the steps
    return names


@contextlib.contextmanager
def _lock(recipe: Recipe) -> Iterator[None]:
    """One bake of a recipe at a time (its manifest and cache are shared)."""
    import fcntl

    recipe.cache.mkdir(parents=True, exist_ok=True)
    fd = os.open(recipe.cache / f"{recipe.path.stem}.lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise BakeshopError(
                "another bake of this recipe is running (its cache is locked)", recipe.path
            ) from None
        yield
    finally:
        os.close(fd)


def run(
    recipe: Recipe,
    *,
    force: Iterable[str] = (),
    jobs: int = 1,
    on_decision: Callable[..., object] | None = None,
) -> BakeResult:
    """Bake: run every step that is not up to date (see the module notes).

    Parameters
    ----------
    recipe : Recipe
        From :func:`bakeshop.bake.load_recipe`.
    force : iterable of str
        Step names to rebuild whatever their state.
    jobs : int
        Steps run at once (threads of dask's local scheduler), each as soon as the steps it
        reads are done; 1 runs them one after another in the recipe's order. The outputs are
        the same either way.
    on_decision : callable, optional
        Called with each :class:`Decision` as it is made (before the step runs), and with the
        finished step's manifest record as a second argument once it has run (never from two
        threads at once).

    Returns
    -------
    BakeResult
        Its ``failed`` is empty when every step is up to date or was rebuilt; otherwise the
        caller decides how to report the errors (the command line exits 2 with the first).
        ``decisions`` are in the recipe's order, ``built`` in the order the steps finished.
    """
    from bakeshop.io import record_writes, write_json

    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise BakeshopError(f"jobs must be a whole number of at least 1, got {jobs!r}")
    started = time.perf_counter()
    force = _check_force(recipe, force)
    with _lock(recipe):
        for path in (recipe.manifest, recipe.cache / "hashes.json"):
            _remove_temporaries(path)
        records, note = _load_manifest(recipe)
        records = {s.name: records[s.name] for s in recipe.steps if s.name in records}
        hashes = FileHashes(recipe.cache / "hashes.json")
        reads = {path for s in recipe.steps for path in s.inputs}
        decided: dict[str, Decision] = {}
        built: list[str] = []
        failed: dict[str, BakeshopError] = {}
        lock = threading.RLock()  # the records, the lists above, the manifest and callbacks

        def save() -> None:
            write_json(
                recipe.manifest,
                {
                    "manifest_version": MANIFEST_VERSION,
                    "bakeshop": __version__,
                    "recipe": recipe.relative(recipe.path),
                    "steps": {s.name: records[s.name] for s in recipe.steps if s.name in records},
                },
            )
            hashes.save()

        def report(decision: Decision, record: dict | None = None) -> None:
            if on_decision:
                on_decision(decision, record)

        def bake_step(step: Step, *_done: object) -> None:
            with lock:
                broken = [d for d in step.after if d in failed or decided[d].action == "blocked"]
                if broken:
                    decided[step.name] = Decision(
                        step.name, "blocked", [f"{', '.join(broken)} failed"]
                    )
                    report(decided[step.name])
                    return
                decision, inputs = _decide(
                    step, recipe, records.get(step.name), hashes, step.name in force, note
                )
                decided[step.name] = decision
                report(decision)
                if decision.action == "skip":
                    return
                previous = records.pop(step.name, None)
            written: list[Path] = []
            try:
                with record_writes(this_thread=True) as written:
                    record = _build(step, recipe, inputs, hashes, previous, written, reads)
            except BaseException as e:
                if isinstance(e, BakeshopError) and not e.reason.startswith(step.name):
                    e.reason = f"{step.name}: {e.reason}"
                    e.args = (e.reason, *e.args[1:])
                why = (
                    str(e) if isinstance(e, BakeshopError) else f"interrupted ({type(e).__name__})"
                )
                kept = _outputs(recipe, written, hashes, previous)
                with lock:
                    records[step.name] = {"failed": why, "inputs": inputs, "outputs": kept}
                    save()
                    if not isinstance(e, BakeshopError):
                        raise
                    failed[step.name] = e
                return
            with lock:
                records[step.name] = record
                built.append(step.name)
                save()
                report(decision, record)

        if jobs == 1:
            for step in recipe.steps:
                bake_step(step)
        else:
            import dask

            graph = {s.name: (functools.partial(bake_step, s), *s.after) for s in recipe.steps}
            dask.threaded.get(graph, list(graph), num_workers=jobs)
        if not recipe.manifest.is_file() or hashes.dirty or journal_path(recipe).exists():
            save()
        with contextlib.suppress(FileNotFoundError):
            journal_path(recipe).unlink()  # every file it names is in the manifest now
    decisions = [decided[s.name] for s in recipe.steps]
    return BakeResult(
        decisions, built, failed, time.perf_counter() - started, hashes.hashed, recipe.manifest
    )


def _build(
    step: Step,
    recipe: Recipe,
    inputs: dict,
    hashes: FileHashes,
    previous: dict | None,
    written: list[Path],
    reads: set[Path],
) -> dict:
    """Run one step with every write re-read and checked (``written`` collects the files, as
    :func:`bakeshop.io.record_writes` does) and guarded (:func:`_guard`); its manifest record.
    Then tidy: the outputs of its previous bake that it no longer writes are removed when they
    are still as that bake left them (water frames beyond a new, shorter loop; a probe's faces
    in the old format) and no step reads them, and so are temporaries of its outputs left by a
    killed bake."""
    from bakeshop.io import verify_writes

    op = OPERATIONS[step.operation]
    step.output.parent.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    with (
        progress.step(f"{step.name}"),
        verify_writes(
            this_thread=True, guard=guard_writes(step, recipe, hashes, previous)
        ) as checks,
    ):
        facts = op.run(dict(step.options))
    seconds = time.perf_counter() - started
    if not written:
        raise BakeshopError(
            f"{step.name} wrote nothing through bakeshop.io in its own thread (the files a step "
            "writes are re-read and recorded only there)",
            step.output,
        )
    proofs = {os.path.abspath(c["file"]): c for c in checks}
    outputs = _outputs(recipe, written, hashes, None)
    for out in outputs:
        proof = proofs[os.fspath(output_file(recipe, out["file"]))]
        out["reload"] = {k: v for k, v in proof.items() if k != "file"}
    removed, left = _tidy(step, recipe, {o["file"] for o in outputs}, previous, hashes, reads)
    return {
        "operation": op.name,
        "operation_version": op.version,
        "bakeshop": __version__,
        "bakeshop_source": source_digest(),
        "key": step_key(step, recipe, inputs),
        "options": _canonical(step.options, recipe),
        "inputs": inputs,
        "outputs": outputs,
        "facts": facts,
        "removed": removed,
        "left": left,
        "seconds": round(seconds, 3),
        "built": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }


def _outputs(
    recipe: Recipe, written: list[Path], hashes: FileHashes, previous: dict | None
) -> list[dict]:
    """Manifest entries (file, bytes, sha256) of the files ``written``, after those of the
    ``previous`` record that were not rewritten (what a failed step leaves)."""
    fresh = [Path(p).parent.resolve() / Path(p).name for p in dict.fromkeys(written)]
    names = [recipe.relative(p) for p in fresh]
    kept = [o for o in (previous or {}).get("outputs", []) if o["file"] not in names]
    made = [
        {"file": name, "bytes": path.stat().st_size, "sha256": hashes.digest(path)}
        for name, path in zip(names, fresh, strict=True)
    ]
    return kept + made


def _tidy(
    step: Step,
    recipe: Recipe,
    written: set,
    previous: dict | None,
    hashes: FileHashes,
    reads: set[Path],
) -> tuple[list, list]:
    """Remove ``step``'s stale outputs (names it :func:`makes`, unchanged since its previous
    bake wrote them, read by no step) and the temporaries of its outputs (``.STEM.<12 hex>.EXT``,
    what :func:`bakeshop.io.atomic_path` leaves only when killed); return the stale outputs
    removed, and those left in place because no step of the recipe makes their names (a renamed
    output, or a forged entry: the manifest alone proves nothing)."""
    removed, left = [], []
    for out in (previous or {}).get("outputs", []):
        path = output_file(recipe, out["file"])
        if out["file"] in written or path in reads:
            continue
        if not makes(step, path):
            if not any(makes(s, path) for s in recipe.steps):
                left.append(out["file"])
        elif output_change(recipe, out, hashes) is None:
            with contextlib.suppress(OSError):
                path.unlink()
                removed.append(out["file"])
    for name in written:
        _remove_temporaries(output_file(recipe, name))
    return removed, left


def _remove_temporaries(path: Path) -> None:
    """Remove the temporaries of ``path`` that a killed :func:`bakeshop.io.atomic_path` left."""
    pattern = re.compile(rf"\.{re.escape(path.stem)}\.[0-9a-f]{{12}}{re.escape(path.suffix)}")
    for candidate in path.parent.glob(f".{glob.escape(path.stem)}.*"):
        if pattern.fullmatch(candidate.name):
            with contextlib.suppress(OSError):
                candidate.unlink()
