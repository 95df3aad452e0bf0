"""The compiled core as a user meets it: nothing compiles on a first run, the thread count is the
user's, and the package builds into a wheel that installs and runs in a fresh environment."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from bakeshop import threads
from bakeshop.io import write_image

ROOT = Path(__file__).resolve().parents[1]

#: the command line with ARGS in this interpreter, every file opened for writing and every
#: process started recorded by an audit hook (Python's own record of what a process does).
AUDITED = textwrap.dedent(
    """
    import json, sys
    written, started = [], []
    def hook(event, args):
        if event == "open" and isinstance(args[0], str) and args[1] and set(args[1]) & set("wax+"):
            written.append(args[0])
        elif event == "open" and isinstance(args[0], str) and args[2] and args[2] & 0o3:
            written.append(args[0])
        elif event.startswith(("subprocess.", "os.exec", "os.posix_spawn", "os.spawn", "os.system",
                               "os.fork")):
            started.append(event)
    sys.addaudithook(hook)
    from bakeshop.cli.main import main
    status = main(sys.argv[1:])
    print(json.dumps([status, written, started]))
    """
)


def audited(args: list[str], cwd: Path, env: dict[str, str]) -> tuple[int, list[str], list[str]]:
    out = subprocess.run([sys.executable, "-c", AUDITED, *args], cwd=cwd, env=env, check=True,
                         capture_output=True, text=True).stdout  # fmt: skip
    status, written, started = json.loads(out.strip().splitlines()[-1])
    # Python's own bytecode of a module edited since the install is not compiled code; a
    # temporary file's random part (".out.3f2a9c01d2e4.hdr") is dropped
    temporary = re.compile(r"\.[0-9a-f]{12}(\.[^./]+)$")
    kept = {temporary.sub(r"\1", w) for w in written if not w.endswith(".pyc")}
    return status, sorted(kept), started


@pytest.mark.parametrize(
    "args",
    [
        ["irradiance", "probe.hdr", "dim.hdr"],
        ["remap", "probe.hdr", "cube.hdr", "--to", "cross-horizontal", "--filter", "area"],
        ["prefilter", "probe.hdr", "ggx.dds", "--size", "16"],
    ],
    ids=lambda a: a[0],
)
def test_a_first_run_compiles_nothing(tmp_path, args):
    """Run twice in fresh processes with fresh cache folders: the first run writes the same
    files as the second (its outputs, and the area matrix the first stores for later) and
    starts no process: no compiler, no cache of compiled code."""
    write_image(tmp_path / "probe.hdr", np.random.default_rng(0).random((32, 64, 3), np.float32))
    env = {
        **os.environ,
        "BAKESHOP_CACHE_DIR": str(tmp_path / "cache"),
        "BAKESHOP_CACHE_BYTES": "1000000000",
        "XDG_CACHE_HOME": str(tmp_path / "xdg"),
    }
    first = audited(["-q", *args], tmp_path, env)
    second = audited(["-q", *args], tmp_path, env)
    assert first[0] == second[0] == 0
    assert first[2] == second[2] == []  # no process started
    outputs = [w for w in second[1] if "cache" not in w]
    stored = [w for w in first[1] if "cache" in w]
    assert [w for w in first[1] if "cache" not in w] == outputs
    assert all(w.startswith(str(tmp_path / "cache")) for w in stored)  # the matrix store only
    assert not (tmp_path / "xdg").exists()


def test_the_thread_count_is_the_callers():
    before = threads.count()
    with threads.limited(1):
        assert threads.count() == 1
    assert threads.count() == before
    with pytest.raises(ValueError):
        threads.use(0)


def test_omp_num_threads_and_the_threads_option():
    probe = "from bakeshop import threads; print(threads.count())"
    env = {**os.environ, "OMP_NUM_THREADS": "3"}
    assert subprocess.run([sys.executable, "-c", probe], env=env, check=True, capture_output=True,
                          text=True).stdout.strip() == "3"  # fmt: skip
    code = textwrap.dedent(
        """
        import sys
        import bakeshop.cli.main as m
        from bakeshop import threads
        seen = []
        m.cli.add_command(m.click.Command("count", callback=lambda: seen.append(threads.count())))
        m.main(["--threads", "5", "count"])
        print(seen[0])
        """
    )
    assert subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                          text=True).stdout.strip() == "5"  # fmt: skip


@pytest.mark.slow  # builds the wheel and installs it with its dependencies (pip's cache)
def test_the_wheel_installs_into_a_fresh_environment_and_runs(tmp_path):
    wheels, venv = tmp_path / "wheels", tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(wheels),
                    str(ROOT)], check=True, capture_output=True)  # fmt: skip
    (wheel,) = wheels.glob("bakeshop-*.whl")
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "pip"), "install", "-q", str(wheel)], check=True,
                   capture_output=True)  # fmt: skip
    write_image(tmp_path / "probe.hdr", np.ones((32, 64, 3), np.float32))
    run = subprocess.run([str(venv / "bin" / "bakeshop"), "irradiance", "probe.hdr", "dim.hdr"],
                         cwd=tmp_path, capture_output=True, text=True)  # fmt: skip
    assert run.returncode == 0, run.stderr
    code = "import bakeshop.sphere._native as n; print(n.__file__)"
    where = subprocess.run([str(venv / "bin" / "python"), "-c", code], cwd=tmp_path, check=True,
                           capture_output=True, text=True).stdout  # fmt: skip
    assert where.startswith(str(venv))
