"""The command line as a process, for every command: special files as inputs fail at once,
signals clean up and exit 128 + N, a failing disk names the target and lists the files already
written, and every error is one line on stderr naming the file, with nothing else around it.

The commands and their input arguments are found by walking the click tree, so a command added
later is covered without touching these tests.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import click
import numpy as np
import pytest

from bakeshop.cli._process import InputPath
from bakeshop.cli.main import cli, main
from bakeshop.io import read_image, write_image
from tests.io import bombs
from tests.io.test_files import no_hang, special_files, tmpfs  # noqa: F401 - a fixture

#: seconds a signalled command may take to clean up and exit
EXIT_SECONDS = 60


def commands(group: click.Group = cli, prefix: tuple[str, ...] = ()):
    """(words that run it, click command) for every command of the tree (each module loaded)."""
    ctx = click.Context(group)
    for name in group.list_commands(ctx):
        command = group.get_command(ctx, name)
        if isinstance(command, click.Group):
            yield from commands(command, (*prefix, name))
        else:
            yield (*prefix, name), command


INPUTS = [
    (words, param.name)
    for words, command in commands()
    for param in command.params
    if isinstance(param.type, InputPath)
]


def argv(words, special: str, value: str, folder: Path) -> list[str]:
    """Arguments that run the command ``words`` with ``value`` for its parameter ``special``
    and placeholders that parse for every other required parameter."""
    command = dict(commands())[words]
    regular = folder / "regular.hdr"
    if not regular.exists():
        write_image(regular, np.ones((8, 16, 3), np.float32))
    args = list(words)
    for param in command.params:
        if param.name == special:
            given = value
        elif not param.required:
            continue
        elif isinstance(param.type, InputPath):
            given = str(regular)
        elif isinstance(param.type, click.Choice):
            given = param.type.choices[0]
        elif isinstance(param.type, click.Path):
            given = str(folder / "out.hdr")
        else:
            given = "1"
        args += [given] if isinstance(param, click.Argument) else [param.opts[0], given]
    return args


def one_error_line(capfd) -> str:
    """The command's stderr, checked to be exactly one ``bakeshop: error:`` line."""
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and err.startswith("bakeshop: error: "), repr(err)
    return err.strip()


def test_every_command_that_reads_files_is_covered():
    names = {" ".join(words) for words, _ in INPUTS}
    assert {"info", "convert", "remap", "normals check", "tonemap", "float", "bake-probe"} <= names


@pytest.mark.parametrize("words, param", INPUTS, ids=[f"{' '.join(w)}:{p}" for w, p in INPUTS])
def test_special_files_as_any_input_fail_at_once_in_one_line(tmp_path, capfd, words, param):
    for kind, (path, reason) in special_files(tmp_path, ".hdr").items():
        with no_hang():
            status = main(["-q", *argv(words, param, str(path), tmp_path)])
        line = one_error_line(capfd)
        assert status == 2, (kind, line)
        assert line.startswith(f"bakeshop: error: {path}: ") and reason in line, (kind, line)


def test_a_special_file_among_six_faces(tmp_path, capfd):
    for face in ("posx", "negx", "posy", "negy", "posz", "negz"):
        write_image(tmp_path / f"env_{face}.hdr", np.ones((8, 8, 3), np.float32))
    (tmp_path / "env_posz.hdr").unlink()
    os.mkfifo(tmp_path / "env_posz.hdr")
    with no_hang():
        status = main(
            [
                "-q",
                "remap",
                str(tmp_path / "env_{face}.hdr"),
                str(tmp_path / "o.hdr"),
                "--to",
                "latlong",
            ]  # fmt: skip
        )
    assert status == 2
    assert one_error_line(capfd).endswith("env_posz.hdr: is a named pipe (FIFO), not a file: "
                                          "bakeshop reads regular files only")  # fmt: skip


# --- signals during a large write -------------------------------------------------------------


@pytest.fixture(scope="module")
def large_source(tmp_path_factory) -> Path:
    """A 4096 x 2048 RGB PFM of noise (96 MiB): writing it as .hdr, .exr or .png takes seconds."""
    path = tmp_path_factory.mktemp("signals") / "large.pfm"
    rng = np.random.default_rng(3)
    write_image(path, rng.lognormal(0, 1, (2048, 4096, 3)).astype(np.float32))
    return path


def run_and_signal(source: Path, target: Path, signum: int, ignore: tuple[int, ...] = ()):
    """Start ``bakeshop convert source target`` (with ``ignore`` signals set to SIG_IGN, as a
    parent may), send ``signum`` once its temporary file exists, and return (status, stderr,
    whether the temporary existed when the signal was sent)."""

    def before_exec():
        for s in ignore:
            signal.signal(s, signal.SIG_IGN)

    process = subprocess.Popen(
        [sys.executable, "-m", "bakeshop.cli.main", "-q", "convert", str(source), str(target)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=before_exec,
    )
    deadline = time.monotonic() + EXIT_SECONDS
    pattern = f".{target.stem}.*{target.suffix}"
    while not list(target.parent.glob(pattern)) and process.poll() is None:
        assert time.monotonic() < deadline, "the write never started"
        time.sleep(0.005)
    started = bool(list(target.parent.glob(pattern)))
    process.send_signal(signum)
    _, err = process.communicate(timeout=EXIT_SECONDS)
    return process.returncode, err, started


@pytest.mark.slow
@pytest.mark.parametrize("ext", ["hdr", "exr", "png"])
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_during_a_write_removes_the_temporary(tmp_path, large_source, ext, signum):
    target = tmp_path / f"out.{ext}"
    status, err, started = run_and_signal(large_source, target, signum)
    assert started
    assert_interrupted(status, err, target, signum)


def assert_interrupted(status: int, err: str, target: Path, signum: int) -> None:
    """The command stopped with 128 + signum and one line, leaving no temporary: no target, or
    the whole target when the signal was handled after the write was done."""
    assert status == 128 + signum, err
    interrupted = f"bakeshop: interrupted by {signal.Signals(signum).name}"
    left = sorted(p.name for p in target.parent.iterdir())
    if err == f"{interrupted}; written before it: {target}\n":
        # Python runs the handler between bytecodes: a signal that arrives during one long
        # C call (zlib over the whole picture) is handled after it, when the file is complete
        assert left == [target.name]
        assert read_image(target).shape[:2] == (2048, 4096)
    else:
        assert err == f"{interrupted}\n"
        assert left == []  # no temporary, no target


@pytest.mark.slow
def test_sigint_counts_even_when_the_parent_ignored_it(tmp_path, large_source):
    # a shell script's background job starts with SIGINT ignored: `kill -INT` must still stop it
    target = tmp_path / "out.hdr"
    status, err, _ = run_and_signal(large_source, target, signal.SIGINT, ignore=(signal.SIGINT,))
    assert_interrupted(status, err, target, signal.SIGINT)


@pytest.mark.slow
def test_sighup_under_nohup_stays_ignored(tmp_path, large_source):
    status, err, _ = run_and_signal(
        large_source, tmp_path / "out.hdr", signal.SIGHUP, ignore=(signal.SIGHUP,)
    )
    assert status == 0 and err == ""
    assert [p.name for p in tmp_path.iterdir()] == ["out.hdr"]


def test_a_signal_during_compiled_kernels_is_raised_when_a_kernel_returns():
    """A compiled kernel releases the GIL and runs to its end; the signal that arrived meanwhile
    is raised as soon as the kernel returns, so a loop of kernel calls stops at once."""
    code = (
        "import json, os, signal, threading, time\n"
        "import numpy as np\n"
        "from bakeshop.io._half import half_planes\n"
        "from bakeshop.cli._process import Interrupted, signals_as_exceptions\n"
        "image = np.ones((1024, 1024, 3), np.float32)\n"
        "threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGTERM)).start()\n"
        "calls, outcome = 0, 'ran'\n"
        "with signals_as_exceptions() as received:\n"
        "    try:\n"
        "        for calls in range(100000):\n"
        "            planes = half_planes(image)\n"
        "    except Interrupted:\n"
        "        outcome = 'interrupted'\n"
        "print(json.dumps([outcome, received, 0 < calls < 99999, float(planes.min())]))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    assert json.loads(run.stdout.splitlines()[-1]) == ["interrupted", [signal.SIGTERM], True, 1.0]


# --- failing disks --------------------------------------------------------------------------------


def test_a_full_disk_half_way_lists_the_files_written(tmpfs, tmp_path, capfd):  # noqa: F811
    folder = tmpfs("400k")
    source = tmp_path / "probe.pfm"
    write_image(source, np.random.default_rng(0).random((256, 512, 3), dtype=np.float32))
    # six faces of 160 x 160 RGB float32 (300 KiB each as PFM): the second does not fit
    status = main(
        ["-q", "remap", str(source), str(folder / "f_{face}.pfm"), "--to", "cube", "--size", "160"]
    )
    assert status == 2
    assert one_error_line(capfd) == (
        f"bakeshop: error: {folder}/f_negx.pfm: cannot write the file: no space left on the "
        f"device (the disk is full); written before it: {folder}/f_posx.pfm"
    )
    assert [p.name for p in folder.iterdir()] == ["f_posx.pfm"]


@pytest.mark.slow
def test_bake_probe_on_a_full_disk_says_what_it_wrote(tmpfs, capfd, monkeypatch):  # noqa: F811
    """A disk that fills during the bake (another writer: the room checked before the bake is
    faked here; tests/cli/test_engine_chains.py has the refusal) still ends the line with the
    files written."""
    folder = tmpfs("200k")
    monkeypatch.setattr("shutil.disk_usage", lambda path: SimpleNamespace(free=2**40))
    status = main(
        [
            "-q",
            "bake-probe",
            "-o",
            str(folder),
            "--cube-size",
            "64",
            "--specular-size",
            "16",
            "--mips",
            "3",
        ]  # fmt: skip
    )
    line = one_error_line(capfd)
    assert status == 2 and "no space left" in line
    written = [p.name for p in folder.iterdir()]
    assert written and all(name in line for name in written)
    assert not any(name.startswith(".") for name in written)


@pytest.mark.parametrize("target", ["/proc/out.exr", "/proc/out.hdr", "/proc/out.png"])
def test_a_target_in_proc_is_named(tmp_path, capfd, target):
    source = tmp_path / "a.pfm"
    write_image(source, np.ones((4, 8, 3), np.float32))
    assert main(["-q", "convert", str(source), target]) == 2
    reason = "cannot create a file in '/proc': no such file or directory"
    assert one_error_line(capfd) == f"bakeshop: error: {target}: {reason}"


# --- one line, naming the file -----------------------------------------------------------------


@pytest.fixture
def files(tmp_path):
    """Small inputs for the error paths."""
    nan = np.ones((16, 32, 3), np.float32)
    nan[2, 3, 1] = np.nan
    write_image(tmp_path / "nan.pfm", nan)
    write_image(tmp_path / "square.pfm", np.ones((16, 16, 3), np.float32))
    write_image(tmp_path / "ok.hdr", np.ones((16, 32, 3), np.float32))
    write_image(tmp_path / "n.png", np.full((16, 16, 3), (0.5, 0.5, 1.0), np.float32))  # flat
    write_image(tmp_path / "grey.png", np.ones((16, 16, 1), np.float32))
    (tmp_path / "corrupt.exr").write_bytes(b"\x76\x2f\x31\x01" + bytes(40))
    (tmp_path / "bomb.hdr").write_bytes(bombs.radiance_old_rle(4096, 4096))
    (tmp_path / "tet.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    )
    (tmp_path / "open.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for name, s in (("tiny", "1e-6"), ("big", "1e30"), ("huge", "1e200")):  # sides, metres
        (tmp_path / f"{name}.obj").write_text(
            f"v 0 0 0\nv {s} 0 0\nv 0 {s} 0\nv 0 0 {s}\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
        )
    return tmp_path


ERRORS = {
    # case: (arguments, the file the line must name, words it must hold)
    "corrupt file": (["info", "{d}/corrupt.exr"], "{d}/corrupt.exr", "corrupt or truncated"),
    "bomb": (["--max-decoded", "64M", "info", "{d}/bomb.hdr"], "{d}/bomb.hdr", "bomb"),
    "NaN in the library": (["irradiance", "{d}/nan.pfm", "{d}/o.hdr"], "{d}/nan.pfm", "NaN"),
    "cross shape in the library": (
        ["remap", "{d}/square.pfm", "{d}/o.hdr", "--from", "cross-vertical", "--to", "latlong"],
        "{d}/square.pfm",
        "4 x 3 square faces",
    ),
    "NaN in prefilter": (["prefilter", "{d}/nan.pfm", "{d}/s.dds"], "{d}/nan.pfm", "NaN"),
    "open mesh": (["float", "{d}/open.obj"], "{d}/open.obj", "not watertight"),
    # trimesh and numpy printed 58 lines of overflow warnings before this one, without the file
    "library warnings around the error": (
        ["float", "{d}/huge.obj", "--seconds", "0.1"],
        "{d}/huge.obj",
        "the mesh encloses no volume",
    ),
    "MuJoCo's XML parser": (
        ["float", "{d}/tiny.obj", "--backend", "mujoco", "--seconds", "0.1"],
        "{d}/tiny.obj",
        "MuJoCo cannot simulate the body: mesh volume is too small",
    ),
    "missing output folder": (["convert", "{d}/ok.hdr", "{d}/no/o.exr"], "{d}/no/o.exr", "exist"),
    # a library error about several inputs names them all
    "several inputs": (
        [
            "normals",
            "combine",
            "{d}/n.png",
            "{d}/n.png",
            "{d}/o.png",
            "--mask",
            "{d}/grey.png",
            "--mask-id",
            "1,2,3",
        ],  # fmt: skip
        "{d}/n.png, {d}/grey.png",
        "must be a grey level or an (r, g, b) colour of an RGB mask",
    ),
}


@pytest.mark.parametrize("case", sorted(ERRORS))
def test_every_error_is_one_line_naming_the_file(files, capfd, case):
    args, named, words = ERRORS[case]
    status = main(["-q", *(a.format(d=files) for a in args)])
    out = capfd.readouterr()
    assert status == 2, out
    assert out.err.count("\n") == 1 and out.err.startswith("bakeshop: error: "), out.err
    names, _, reason = out.err.removeprefix("bakeshop: error: ").partition(": ")
    assert set(names.split(", ")) == set(named.format(d=files).split(", ")), out.err
    assert words in reason
    assert not (files / "MUJOCO_LOG.TXT").exists() and not Path("MUJOCO_LOG.TXT").exists()


def test_an_option_error_of_the_command_line_is_not_attributed(files, capfd):
    assert main(["-q", "resize", str(files / "ok.hdr"), str(files / "o.hdr"), "--size", "x"]) == 2
    assert one_error_line(capfd) == (
        "bakeshop: error: Invalid value for '--size': 'x' is not a size: expected N or WxH "
        "(whole numbers) (see 'bakeshop resize --help')"
    )


def test_library_warnings_of_a_successful_run_are_one_line_each(files, capfd):
    status = main(["-q", "float", str(files / "big.obj"), "--seconds", "0.1"])
    err = capfd.readouterr().err
    assert status == 0
    lines = err.splitlines()
    assert lines and all(line.startswith("bakeshop: warning: ") for line in lines), err
    assert len(lines) == len(set(lines))


def test_bakeshops_own_warning_names_the_file_once(tmp_path, capfd):
    write_image(tmp_path / "sun.pfm", np.full((4, 8, 3), 1e5, np.float32))
    out = tmp_path / "sun.exr"
    assert main(["-q", "convert", str(tmp_path / "sun.pfm"), str(out)]) == 0
    assert capfd.readouterr().err == (
        f"bakeshop: warning: {out}: values reach 1e+05, beyond the 65504 that half floats "
        "hold: written as 32-bit floats\n"
    )


@pytest.mark.parametrize("size", ["0", "-1", "nan", "inf", "1e300", "lots", "8Q"])
def test_a_bad_decode_budget_is_one_line(files, capfd, size):
    assert main(["--max-decoded", size, "info", str(files / "ok.hdr")]) == 2
    assert "--max-decoded" in one_error_line(capfd)


def test_the_decode_budget_option_allows_and_refuses(files, capfd):
    assert main(["-q", "--max-decoded", "256M", "info", "--json", str(files / "bomb.hdr")]) == 0
    assert '"width": 4096' in capfd.readouterr().out
    assert main(["-q", "--max-decoded", "1G", "info", str(files / "ok.hdr")]) == 0
    capfd.readouterr()
    assert main(["-q", "info", str(files / "ok.hdr")]) == 0  # the budget does not stay set
    from bakeshop.io.budget import decode_limit

    assert decode_limit(0) == 1 << 30


def test_without_quiet_an_error_is_still_one_line(files, capfd):
    # progress bars are for terminals: on a pipe, rich's bar left a blank line beside the error
    args = ["prefilter", str(files / "ok.hdr"), "/proc/x.dds", "--size", "8", "--mips", "2"]
    assert main(args) == 2
    assert one_error_line(capfd).startswith("bakeshop: error: /proc/x.dds: cannot create")
