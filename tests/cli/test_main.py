"""The root command: its table of commands matches the commands, and start-up loads only what
the command uses (measured by what is imported, not by time)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import click
import pytest

from bakeshop.cli import main

CLI_DIR = Path(main.__file__).parent

#: run in a fresh interpreter: the command line with ARGS, then print the heavy modules loaded.
PROBE = """
import json, sys
from bakeshop.cli.main import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
heavy = ("numpy", "scipy", "matplotlib", "OpenEXR", "mujoco", "trimesh", "rich")
print(json.dumps(sorted(m for m in heavy if m in sys.modules)))
"""


def loaded(*args: str) -> list[str]:
    out = subprocess.run(
        [sys.executable, "-c", PROBE, *args], check=True, capture_output=True, text=True
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_the_table_lists_every_command_module():
    sources = {p.stem: p for p in CLI_DIR.glob("*.py")}
    sources |= {p.parent.name: p for p in CLI_DIR.glob("*/__init__.py")}  # command packages
    modules = {
        name
        for name, path in sources.items()
        if not name.startswith("_") and "\ndef register(" in path.read_text()
    }
    assert modules == {module for module, _ in main.COMMANDS.values()}


@pytest.mark.parametrize("name", list(main.COMMANDS))
def test_the_table_names_each_command_and_starts_its_help(name):
    """The listing of ``bakeshop --help`` (from the table) is what the commands would show."""
    ctx = click.Context(main.cli)
    command = main.cli.get_command(ctx, name)
    assert command is not None and command.name == name
    listed = click.Command(name, help=main.COMMANDS[name][1])
    for limit in range(30, 101):
        assert listed.get_short_help_str(limit) == command.get_short_help_str(limit), limit


@pytest.mark.parametrize("args", [["--version"], ["--help"]])
def test_version_and_help_load_no_numerical_library(args):
    assert loaded(*args) == []


def command_paths() -> list[list[str]]:
    """Every command and subcommand, as the words that name it."""
    ctx = click.Context(main.cli)
    found = []
    for name in main.COMMANDS:
        command = main.cli.get_command(ctx, name)
        found.append([name])
        if isinstance(command, click.Group):
            found += [[name, sub] for sub in command.list_commands(ctx)]
    return found


@pytest.mark.parametrize("words", command_paths(), ids=" ".join)
def test_a_commands_help_loads_no_kernels(words):
    """``bakeshop COMMAND --help`` names layouts, methods and encodings without loading the
    libraries behind them."""
    assert {"scipy", "matplotlib", "rich"}.isdisjoint(loaded(*words, "--help"))


@pytest.mark.parametrize("name", ["probe.exr", "probe.hdr"])
def test_info_loads_only_numpy_and_the_codec(tmp_path, name):
    """``info`` of an OpenEXR or Radiance probe: numpy and the file's codec, no kernels, and no
    rich (its output is plain text, and progress makes its console only when it shows some)."""
    import numpy as np

    from bakeshop.io import write_image

    path = tmp_path / name
    write_image(path, np.ones((16, 32, 3), np.float32))
    assert {"scipy", "matplotlib", "rich"}.isdisjoint(loaded("info", str(path)))


def test_an_unknown_command_is_one_error_line():
    out = subprocess.run(
        [sys.executable, "-m", "bakeshop.cli.main", "bake-everything"],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2
    assert "No such command 'bake-everything'" in out.stderr


#: the executable's entry point in a fresh interpreter, after an exit handler of the caller's
#: and, when told, a thread: ``bakeshop --version``.
EXECUTABLE = """
import atexit, sys, threading, time
from pathlib import Path
from bakeshop.cli.main import command
out = Path(sys.argv[1])
atexit.register(lambda: (out / "handler").write_text("ran"))
def late():
    time.sleep(0.5)
    (out / "thread").write_text("done")
if sys.argv[2] == "thread":
    threading.Thread(target=late).start()
sys.argv[1:] = ["--version"]
command()
"""


@pytest.mark.parametrize("thread", ["thread", "none"])
def test_the_executable_runs_exit_handlers_and_waits_for_threads(tmp_path, thread):
    """``command`` exits the ordinary way: the exit handlers run, and a running thread is
    waited for."""
    done = subprocess.run(
        [sys.executable, "-c", EXECUTABLE, str(tmp_path), thread], capture_output=True, text=True
    )
    assert done.returncode == 0 and done.stdout.startswith("bakeshop, version")
    assert (tmp_path / "handler").read_text() == "ran"
    assert (tmp_path / "thread").exists() == (thread == "thread")
    if thread == "thread":
        assert (tmp_path / "thread").read_text() == "done"


def test_the_executable_exits_with_the_commands_status(tmp_path):
    """0 for a command that worked, 2 and one line for bad input."""
    good = subprocess.run([sys.executable, "-m", "bakeshop.cli.main", "--help"],
                          capture_output=True, text=True)  # fmt: skip
    bad = subprocess.run([sys.executable, "-m", "bakeshop.cli.main", "info",
                          str(tmp_path / "none.hdr")], capture_output=True, text=True)  # fmt: skip
    assert good.returncode == 0 and "Usage: bakeshop" in good.stdout
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and bad.stdout == ""


@pytest.mark.parametrize("args,status", [(["--version"], 0), (["info", "none.hdr"], 2)])
def test_the_executable_with_stdout_closed(tmp_path, args, status):
    """With its standard output closed (``sys.stdout`` is None) the command keeps its status and
    its stderr."""
    command = " ".join([sys.executable, "-m", "bakeshop.cli.main", *args]) + " >&-"
    done = subprocess.run(["sh", "-c", command], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == status
    assert "Traceback" not in done.stderr and done.stderr.count("\n") == (status != 0)


def test_the_executable_under_a_profiler_exits_the_ordinary_way(tmp_path):
    """cProfile writes its results at the exit."""
    profile = tmp_path / "run.prof"
    done = subprocess.run(
        [sys.executable, "-m", "cProfile", "-o", str(profile), "-m", "bakeshop.cli.main",
         "--version"], capture_output=True, text=True,
    )  # fmt: skip
    assert done.returncode == 0 and profile.stat().st_size > 0


def test_an_openexr_read_with_stderr_closed(tmp_path):
    """The OpenEXR reader collects the library's messages from descriptor 2; with stderr closed
    (``sys.stderr`` is None) it reads all the same."""
    import numpy as np

    from bakeshop.io import write_image

    write_image(tmp_path / "probe.exr", np.ones((8, 16, 3), np.float32))
    command = f"{sys.executable} -m bakeshop.cli.main info probe.exr 2>&- >/dev/null"
    done = subprocess.run(["sh", "-c", command], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0


def test_a_bilinear_remap_loads_no_sparse_matrices(tmp_path):
    """scipy.sparse (0.08 s) is imported by the filters that build sparse weights (the area
    filter's exact reductions, resize), not by every command that could reach them."""
    import numpy as np

    from bakeshop.io import write_image

    write_image(tmp_path / "probe.hdr", np.ones((32, 64, 3), np.float32))
    probe = "import sys\nfrom bakeshop.cli.main import main\nmain(sys.argv[1:])\n"
    probe += "print('scipy.sparse' in sys.modules)"
    args = ["-q", "remap", str(tmp_path / "probe.hdr"), str(tmp_path / "f_{face}.hdr"), "--to",
            "faces"]  # fmt: skip
    out = subprocess.run([sys.executable, "-c", probe, *args], check=True, capture_output=True,
                         text=True).stdout  # fmt: skip
    assert out.strip().splitlines()[-1] == "False"
    assert len(list(tmp_path.glob("f_*.hdr"))) == 6
