"""Benchmark: the cost of deciding that a recipe has nothing to do.

A recipe of N steps, each reading one input file of S MB and writing a small JSON summary
through bakeshop.io (the operation itself is trivial: what is measured is the bake's own
bookkeeping). Three bakes are timed in one run:

``first``
    Every step built: every input hashed, every output written and re-read.
``no-op``
    Nothing changed: one ``stat`` per input and output against the digest cache
    (.bakeshop/hashes.json), the manifest read, no input read.
``no-op, no cache``
    The same decision with the digest cache deleted, so every input is hashed in full: the
    peer, what a build tool that hashes contents on every run pays (doit's MD5 checker).

The physical limit of the no-op check is the ``stat`` calls and reading the manifest; of the
uncached check, reading N x S MB from the page cache (a few GB/s) or the disk.

Run: .venv/bin/python benchmarks/bench_bake.py [--steps 40] [--megabytes 16]
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

import bakeshop.io as bio
from bakeshop.bake import OPERATIONS, Operation, load_recipe, run


def _summary(options):
    size = os.path.getsize(options["input"])
    bio.write_json(options["output"], {"bytes": size})
    return {"bytes": size}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--megabytes", type=int, default=16)
    args = parser.parse_args()
    OPERATIONS["summary"] = Operation(
        name="summary",
        version=1,
        summary="the size of a file",
        paths={"input": "input", "output": "output"},
        options={},
        run=_summary,
    )
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        (root / "in").mkdir()
        block = os.urandom(1 << 20)
        lines = []
        old = time.time() - 3600  # inputs older than the racy window, as a level's are
        for i in range(args.steps):
            path = root / "in" / f"probe{i:03d}.bin"
            with open(path, "wb") as f:
                for _ in range(args.megabytes):
                    f.write(block)
            os.utime(path, (old, old))
            lines += [f"[summary.p{i:03d}]", f'input = "in/{path.name}"',
                      f'output = "out/p{i:03d}.json"', ""]  # fmt: skip
        (root / "level.toml").write_text("\n".join(lines))
        recipe = load_recipe(root / "level.toml")
        timings = {}
        started = time.perf_counter()
        first = run(recipe)
        timings["first"] = (time.perf_counter() - started, first.hashed, len(first.built))
        time.sleep(2.1)  # the outputs leave the racy window once and are cached
        run(recipe)
        best = None
        for _ in range(3):
            started = time.perf_counter()
            again = run(recipe)
            elapsed = time.perf_counter() - started
            best = elapsed if best is None else min(best, elapsed)
        timings["no-op"] = (best, again.hashed, len(again.built))
        (recipe.cache / "hashes.json").unlink()
        started = time.perf_counter()
        uncached = run(recipe)
        timings["no-op, no cache"] = (time.perf_counter() - started, uncached.hashed,
                                      len(uncached.built))  # fmt: skip
    total = args.steps * args.megabytes
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")  # fmt: skip
    print(f"recipe: {args.steps} steps, {args.megabytes} MB input each ({total} MB)")
    print(f"{'bake':<18}{'seconds':>10}{'files hashed':>14}{'steps built':>13}")
    for name, (seconds, hashed, built) in timings.items():
        print(f"{name:<18}{seconds:>10.3f}{hashed:>14}{built:>13}")
    ratio = timings["no-op, no cache"][0] / timings["no-op"][0]
    print(
        f"no-op with the digest cache: {ratio:.0f}x faster than hashing every input "
        f"({total / timings['no-op, no cache'][0]:.0f} MB/s hashed)"
    )


if __name__ == "__main__":
    main()
