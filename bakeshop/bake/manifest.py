"""The bake's bookkeeping as untrusted input, and the proof that a file is the bake's own.

The manifest (``RECIPE.bake.json``), the digest cache (``.bakeshop/hashes.json``) and the journal
(``.bakeshop/RECIPE.journal``) may have been edited by anyone: each is checked against its
schema (the JSON type of every key a bake reads; output files inside the folder the recipe
governs, neither the recipe nor the bookkeeping) and refused in one line naming the file and the
key. A file is the bake's own when the manifest (or the journal of a killed bake) records it
for the step with the size and SHA-256 it has now; only such a file is replaced or deleted
(:func:`guard_writes`, :func:`output_change`). Only regular files are hashed.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO, NoReturn

from bakeshop.bake.recipe import Recipe, Step
from bakeshop.errors import BakeshopError, FormatError

__all__ = ["FileHashes", "check_manifest", "guard_writes", "journal_path", "output_change",
           "output_file", "resume"]  # fmt: skip

#: a cached digest is trusted only for files last modified this long before they were hashed
#: (a write within the same timestamp tick as the hash would otherwise go unseen).
RACY_NS = 2_000_000_000
_CHUNK = 1 << 20
#: a journal larger than this is not one of a bake's (a line is about 150 bytes per file).
MAX_JOURNAL_BYTES = 64 << 20


def _sha256(f: BinaryIO) -> str:
    h = hashlib.sha256()
    while chunk := f.read(_CHUNK):
        h.update(chunk)
    return h.hexdigest()


class FileHashes:
    """SHA-256 digests of files, cached by (size, mtime, inode) in a JSON file."""

    def __init__(self, path: Path):
        self.path = path
        self.entries: dict[str, list] = {}
        self.hashed = 0  # files read in full (the work the cache saves)
        self.dirty = False
        self._lock = threading.Lock()
        if os.path.lexists(path):
            from bakeshop.io import read_json

            self.entries = _cache_entries(read_json(path), path)

    def digest(self, path: Path) -> str | None:
        """The file's SHA-256 (hex), or None when it does not exist; anything but a regular
        file is a :class:`~bakeshop.errors.BakeshopError` (it is never opened)."""
        from bakeshop.io import open_input

        if not os.path.lexists(path):
            return None
        key = os.fspath(path)
        with self._lock:
            entry = self.entries.get(key)
        with open_input(path) as f:
            st = os.fstat(f.fileno())
            stamp = [st.st_size, st.st_mtime_ns, st.st_ino]
            if entry is not None and entry[:3] == stamp and st.st_mtime_ns < entry[3] - RACY_NS:
                return entry[4]
            digest = _sha256(f)
        with self._lock:
            self.hashed += 1
            self.entries[key] = [*stamp, time.time_ns(), digest]
            self.dirty = True
        return digest

    def save(self) -> None:
        """Write the cache when a digest was added or refreshed."""
        from bakeshop.io import write_json

        with self._lock:
            if not self.dirty:
                return
            entries, self.dirty = dict(self.entries), False
        self.path.parent.mkdir(parents=True, exist_ok=True)
        write_json(self.path, {"files": entries})


def _cache_entries(document: dict, path: Path) -> dict[str, list]:
    """The digest cache's entries, each ``[size, mtime_ns, inode, hashed_ns, sha256]``; a
    :class:`~bakeshop.errors.FormatError` naming the cache when they are not."""
    files = document.get("files", {})
    if not isinstance(files, dict):
        raise FormatError(f"files must be an object, not {_json_type(files)}{_CACHE_HINT}", path)
    for name, entry in files.items():
        if not (
            isinstance(entry, list)
            and len(entry) == 5
            and all(_is(v, int) for v in entry[:4])
            and isinstance(entry[4], str)
        ):
            raise FormatError(
                f"files.{name} must be [size, mtime_ns, inode, hashed_ns, sha256], not "
                f"{_json_type(entry)}{_CACHE_HINT}",
                path,
            )
    return dict(files)


_CACHE_HINT = " (delete the digest cache: it is rebuilt)"
_MANIFEST_HINT = " (delete the manifest to bake every step again)"
#: the manifest's keys that a bake reads, with their JSON types (every one optional).
_MANIFEST_TYPES = {"manifest_version": int, "bakeshop": str, "recipe": str, "steps": dict}
_RECORD_TYPES = {
    "failed": str,
    "operation": str,
    "operation_version": int,
    "bakeshop": str,
    "bakeshop_source": str,
    "key": str,
    "options": dict,
    "inputs": dict,
    "outputs": list,
    "facts": dict,
    "removed": list,
    "left": list,
    "seconds": (int, float),
    "built": str,
}
#: an output's keys and types: ``file``, ``bytes`` and ``sha256`` are required.
_OUTPUT_TYPES = {"file": str, "bytes": int, "sha256": str, "reload": dict}


def _is(value: object, kind: type | tuple[type, ...]) -> bool:
    """``isinstance``, where true and false are not numbers."""
    return isinstance(value, kind) and not isinstance(value, bool)


def _json_type(value: object) -> str:
    if isinstance(value, bool):
        return "true or false"
    names = {dict: "an object", list: "a list", str: "a string", int: "an integer"}
    return names.get(
        type(value),
        "a number with a fraction or an exponent" if isinstance(value, float) else "null",
    )


def _typed(document: dict, types: dict, where: str, fail: Callable[[str], NoReturn]) -> None:
    for key, kind in types.items():
        if key in document and not _is(document[key], kind):
            expected = "a number" if isinstance(kind, tuple) else _json_type(kind())
            fail(f"{where}{key} must be {expected}, not {_json_type(document[key])}")


def check_manifest(document: dict, recipe: Recipe) -> dict[str, dict]:
    """The manifest's step records, checked against its schema: the JSON types of every key a
    bake reads, and output files that lie inside the folder the recipe governs."""

    def fail(reason: str) -> NoReturn:
        raise FormatError(reason + _MANIFEST_HINT, recipe.manifest)

    _typed(document, _MANIFEST_TYPES, "", fail)
    steps = document.get("steps", {})
    for name, record in steps.items():
        where = f"steps.{name}"
        if not isinstance(record, dict):
            fail(f"{where} must be an object, not {_json_type(record)}")
        _typed(record, _RECORD_TYPES, where + ".", fail)
        for key, digest in record.get("inputs", {}).items():
            if not isinstance(digest, str):
                fail(f"{where}.inputs.{key} must be a string, not {_json_type(digest)}")
        for key in ("removed", "left"):
            for i, name in enumerate(record.get(key, [])):
                if not isinstance(name, str):
                    fail(f"{where}.{key}[{i}] must be a string, not {_json_type(name)}")
        for i, out in enumerate(record.get("outputs", [])):
            _check_output(out, f"{where}.outputs[{i}]", recipe, fail)
    return dict(steps)


def _check_output(out: object, at: str, recipe: Recipe, fail: Callable[[str], NoReturn]) -> None:
    """An output entry of the manifest or the journal: its keys and types, and a file inside
    the folder the recipe governs that is neither the recipe nor the bake's bookkeeping."""
    if not isinstance(out, dict):
        fail(f"{at} must be an object, not {_json_type(out)}")
    for key in ("file", "bytes", "sha256"):
        if key not in out:
            fail(f"{at} has no {key}")
    _typed(out, _OUTPUT_TYPES, at + ".", fail)
    path = "\0" not in out["file"] and output_file(recipe, out["file"])
    if not path or path == recipe.folder or recipe.folder not in path.parents:
        fail(f"{at}.file {out['file']!r} is not a file inside {recipe.folder}")
    if path == recipe.path or path == recipe.manifest or recipe.cache in path.parents:
        fail(f"{at}.file {out['file']!r} is the recipe or the bake's bookkeeping")


def journal_path(recipe: Recipe) -> Path:
    """Where a running bake notes each file just before it takes its name (JSON lines: the
    step, and the file's entry), so that a bake killed mid-step (SIGKILL) leaves a record of
    what it replaced for the next bake to trust."""
    return recipe.cache / f"{recipe.path.stem}.journal"


_journal_lock = threading.Lock()


def _note(recipe: Recipe, step: str, out: dict) -> None:
    line = json.dumps({"step": step, **out}) + "\n"
    with _journal_lock, open(journal_path(recipe), "a", encoding="utf-8") as f:
        f.write(line)


def resume(recipe: Recipe, records: dict[str, dict]) -> None:
    """Fold the journal of a killed bake into ``records``: each step it names with files its
    record does not hold is recorded as failed, with those files among its outputs."""
    from bakeshop.io import open_input

    path = journal_path(recipe)
    if not os.path.lexists(path):
        return

    def fail(reason: str) -> NoReturn:
        raise FormatError(reason + _CACHE_HINT, path)

    with open_input(path) as f:
        lines = f.read(MAX_JOURNAL_BYTES + 1).split(b"\n")[:-1]  # the last: cut by a kill
    if sum(map(len, lines)) > MAX_JOURNAL_BYTES:
        fail(f"a journal holds at most {MAX_JOURNAL_BYTES >> 20} MiB")
    written: dict[str, dict[str, dict]] = {}
    for i, line in enumerate(lines):
        try:
            entry = json.loads(line)
        except (ValueError, RecursionError):
            fail(f"line {i + 1} is not a JSON object")
        _check_output(entry, f"line {i + 1}", recipe, fail)
        if not isinstance(entry.get("step"), str):
            fail(f"line {i + 1} names no step")
        out = {k: entry[k] for k in ("file", "bytes", "sha256")}
        written.setdefault(entry["step"], {})[out["file"]] = out
    for name, outs in written.items():  # a file may have been noted and not renamed: both
        old = records.get(name, {})
        known = {(o["file"], o["sha256"]) for o in old.get("outputs", [])}
        if all((o["file"], o["sha256"]) in known for o in outs.values()):
            continue  # the step finished and was recorded
        records[name] = {
            "failed": "interrupted while it wrote its outputs",
            "inputs": old.get("inputs", {}),
            "outputs": old.get("outputs", []) + list(outs.values()),
        }


def output_file(recipe: Recipe, name: str) -> Path:
    """An output the manifest names (relative to the recipe), resolved."""
    return (recipe.root / name).resolve()


def output_change(recipe: Recipe, out: dict, hashes: FileHashes) -> str | None:
    """Why the output the manifest records as ``out`` no longer holds what was baked, or None
    when it does (only a regular file of the recorded size is hashed)."""
    path, name = output_file(recipe, out["file"]), out["file"]
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return f"output {name} is missing"
    if not stat.S_ISREG(st.st_mode):
        return f"output {name} is no longer a regular file"
    if st.st_size != out["bytes"] or hashes.digest(path) != out["sha256"]:
        return f"output {name} differs from what was baked and re-read (edited or corrupted)"
    return None


def makes(step: Step, path: Path) -> bool:
    """Whether ``path`` (resolved) is a name ``step`` can make: its output, a file in its output
    folder, or one beside its output file named from it (``{face}`` files, ``OUT.json``
    sidecars). The only files a bake replaces or deletes are such names."""
    out = step.output
    return out in path.parents or (
        path.parent == out.parent and path.name.startswith(out.name.split("{")[0])
    )


def guard_writes(
    step: Step, recipe: Recipe, hashes: FileHashes, previous: dict | None
) -> Callable[[Path, Path], None]:
    """The check of each file ``step`` is about to write: a name it :func:`makes`; and where a
    file is already there, one that its previous bake wrote and left as it was. Each file let
    through is noted in the journal before it takes its name."""
    recorded: dict[str, list[dict]] = {}
    for o in (previous or {}).get("outputs", []):
        recorded.setdefault(o["file"], []).append(o)
    mine: set[Path] = set()

    def guard(target: Path, tmp: Path) -> None:
        path = Path(target).parent.resolve() / Path(target).name
        if not makes(step, path):
            raise BakeshopError(
                f"{step.name} writes only its output {recipe.relative(step.output)} and the files "
                "named from it",
                target,
            )
        name = recipe.relative(path)
        if path not in mine and os.path.lexists(path):
            if all(output_change(recipe, o, hashes) for o in recorded.get(name, [])):
                raise BakeshopError(
                    f"{step.name} would replace {name}, which its last bake did not leave there "
                    "(not in the manifest, or changed since): bakeshop replaces only files it "
                    "wrote; move it away to bake this step",
                    target,
                )
        mine.add(path)
        with open(tmp, "rb") as f:
            entry = {"file": name, "bytes": os.fstat(f.fileno()).st_size, "sha256": _sha256(f)}
        _note(recipe, step.name, entry)

    return guard
