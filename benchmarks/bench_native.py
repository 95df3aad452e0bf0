"""Time each compiled kernel against the kernel of an earlier revision, in one run.

The cases are benchmarks/native_cases/*.py: each file's ``cases()`` returns ``(label, thunk)``
pairs that call functions whose names and signatures are the same in both revisions. Each case
file runs in a fresh process twice: on this tree (the compiled core) and on the tree of git
revision BEFORE (default 9f4eaba, the last with the kernels compiled just in time), exported to a
temporary folder and run in a virtual environment that sees this environment's packages (not
its bakeshop) and gets what the old tree's pyproject.toml lists and this one lacks.

Per case: the first call in the process (the old kernels compile, or load their cache, here;
the compiled core does neither) and the best of REPEATS later calls, wall seconds; the ratio is
the old best over the native best (above 1: the native kernel is faster).

usage: python benchmarks/bench_native.py [--before REV] [--repeats N] [CASE_FILE ...]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import peers

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
CASES = ROOT / "benchmarks" / "native_cases"

#: one case file in this process: first call and best of N, per case, as JSON.
RUNNER = """
import json, runpy, sys, time
cases = runpy.run_path(sys.argv[1])["cases"]()
repeats, found = int(sys.argv[2]), {}
for label, thunk in cases:
    t = time.perf_counter(); thunk(); first = time.perf_counter() - t
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter(); thunk(); best = min(best, time.perf_counter() - t)
    found[label] = [first, best]
import bakeshop
print(bakeshop.__file__, file=sys.stderr)  # which tree ran
print(json.dumps(found))
"""


def run_cases(python: str, case_file: Path, repeats: int, env: dict[str, str]) -> dict:
    # run from an empty folder: `python -c` puts the working folder first on the path, which
    # must not be a tree holding a bakeshop package
    with tempfile.TemporaryDirectory() as empty:
        done = subprocess.run([python, "-c", RUNNER, str(case_file.resolve()), str(repeats)],
                              env=env, capture_output=True, text=True, cwd=empty)  # fmt: skip
    if done.returncode != 0:
        print(f"  {case_file.name}: failed: {done.stderr.strip().splitlines()[-1:]}")
        return {}
    print(f"  {case_file.name}: ran {done.stderr.strip().splitlines()[-1]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def before_interpreter(folder: Path, revision: str) -> tuple[str, dict[str, str]]:
    """An interpreter and environment that run the tree of ``revision``."""
    tree = folder / "tree"
    tree.mkdir()
    archive = subprocess.run(["git", "archive", revision, "bakeshop", "pyproject.toml"], cwd=ROOT,
                             check=True, capture_output=True).stdout  # fmt: skip
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    venv = folder / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = str(venv / "bin" / "python")
    purelib = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()"
                              "['purelib'])"], check=True, capture_output=True,
                             text=True).stdout.strip()  # fmt: skip
    # a plain path line: this environment's packages, without the .pth of its editable bakeshop
    Path(purelib, "environment.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    with open(tree / "pyproject.toml", "rb") as f:
        needs = tomllib.load(f)["project"]["dependencies"]
    subprocess.run([python, "-m", "pip", "install", "-q", *needs], check=True)
    env = {**os.environ, "PYTHONPATH": str(tree)}  # the old kernels cache in the temporary tree
    return python, env


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default="9f4eaba")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("files", nargs="*", type=Path)
    args = parser.parse_args()
    files = args.files or sorted(CASES.glob("*.py"))
    print(f"machine: {peers.machine()}")
    print(f"before: {args.before} (its kernel cache empty: the first call compiles)")
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        before = before_interpreter(Path(folder), args.before)
        for case_file in files:
            native = run_cases(sys.executable, case_file, args.repeats, dict(os.environ))
            old = run_cases(before[0], case_file, args.repeats, before[1])
            for label, (first, best) in native.items():
                rows.append((label, old.get(label), (first, best)))
    print(f"{'kernel':44} {'old 1st':>10} {'old':>9} {'native 1st':>10} {'native':>9} "
          f"{'ratio':>6}")  # fmt: skip
    for label, old, (first, best) in rows:
        o1, ob = (f"{old[0]:.4f}", f"{old[1]:.4f}") if old else ("-", "-")
        ratio = f"{old[1] / best:.2f}" if old and best > 0 else "-"
        print(f"{label:44} {o1:>10} {ob:>9} {first:>10.4f} {best:>9.4f} {ratio:>6}")


if __name__ == "__main__":
    main()
