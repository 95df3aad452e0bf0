"""The file plumbing of bakeshop.io: what may be opened (special files fail at once, never
hang), and atomic writes on failing file systems (a full tmpfs, a read-only mount, /proc): the
error names the target, never the temporary, and no temporary is left."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from bakeshop.errors import BakeshopError, FormatError
from bakeshop.io import _files as files
from bakeshop.io import check_input, read_image, read_json, record_writes, write_image
from bakeshop.io.dds import read_dds, write_dds
from bakeshop.io.ktx import read_ktx
from bakeshop.io.ktx2 import read_ktx2

#: an operation on a special file fails within this (it must not block at all: a hang is
#: forever, while a loaded machine may take seconds to import and compile a command's code)
HANG_SECONDS = 30


@contextlib.contextmanager
def no_hang(seconds: int = HANG_SECONDS):
    """Fail the test instead of hanging when the block blocks (SIGALRM, main thread)."""

    def alarm(signum, frame):
        raise AssertionError(f"blocked for {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def special_files(folder: Path, ext: str) -> dict[str, tuple[Path, str]]:
    """Each kind of non-regular input, named with ``ext``, and the words its error must say."""
    made = {}
    fifo = folder / f"fifo{ext}"
    os.mkfifo(fifo)
    made["fifo"] = (fifo, "named pipe")
    directory = folder / f"dir{ext}"
    directory.mkdir()
    made["directory"] = (directory, "is a directory")
    loop_a, loop_b = folder / f"loop_a{ext}", folder / f"loop_b{ext}"
    loop_a.symlink_to(loop_b.name)
    loop_b.symlink_to(loop_a.name)
    made["symlink loop"] = (loop_a, "symbolic link loop")
    dangling = folder / f"dangling{ext}"
    dangling.symlink_to("nowhere" + ext)
    made["dangling symlink"] = (dangling, "symbolic link to a file that does not exist")
    device = folder / f"zero{ext}"
    device.symlink_to("/dev/zero")
    made["device"] = (device, "character device")
    sock = folder / f"s{ext}"
    with contextlib.closing(socket.socket(socket.AF_UNIX)) as s:
        s.bind(str(sock))
    made["socket"] = (sock, "socket")
    made["missing"] = (folder / f"missing{ext}", "no such file")
    return made


READERS = {
    ".hdr": read_image,
    ".pfm": read_image,
    ".exr": read_image,
    ".tga": read_image,
    ".png": read_image,
    ".jpg": read_image,
    ".dds": read_dds,
    ".ktx": read_ktx,
    ".ktx2": read_ktx2,
}


@pytest.mark.parametrize("ext", sorted(READERS))
def test_every_reader_refuses_special_files_at_once(tmp_path, ext):
    for kind, (path, words) in special_files(tmp_path, ext).items():
        with no_hang(), pytest.raises(BakeshopError, match=words) as caught:
            READERS[ext](path)
        assert caught.value.path == str(path), kind


@pytest.mark.parametrize("ext", [".obj", ".stl", ".glb"])
def test_the_mesh_loader_refuses_special_files_at_once(tmp_path, ext):
    from bakeshop.io import load_mesh

    for path, words in special_files(tmp_path, ext).values():
        with no_hang(), pytest.raises(BakeshopError, match=words):
            load_mesh(path)


#: Linux capabilities that let root read any file (capabilities(7)); dropped to test as root
CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH = 1, 2


def _without_read_override():
    """In the child before exec: drop from the bounding set the capabilities that let root
    ignore file permissions; the exec'd program then runs without them, root or not."""
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    for cap in (CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH):
        if libc.prctl(24, cap, 0, 0, 0) != 0:  # PR_CAPBSET_DROP
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")


def test_unreadable_file_says_permission_denied(tmp_path):
    path = tmp_path / "secret.hdr"
    write_image(path, np.ones((2, 8, 3), np.float32))
    path.chmod(0)
    try:
        if not os.access(path, os.R_OK):  # an ordinary user: permissions stop reading here
            with pytest.raises(BakeshopError, match="permission denied") as caught:
                read_image(path)
            assert caught.value.path == str(path)
            return
        # root reads anything: read in a child without the capabilities that allow it
        code = (
            "import sys\n"
            "from bakeshop.errors import BakeshopError\n"
            "from bakeshop.io import read_image\n"
            "try:\n"
            "    read_image(sys.argv[1])\n"
            "except BakeshopError as e:\n"
            "    print(e.path); print(e.reason)\n"
            "else:\n"
            "    print('read')\n"
        )
        done = subprocess.run(
            [sys.executable, "-c", code, str(path)],
            capture_output=True,
            text=True,
            timeout=120,
            preexec_fn=_without_read_override,
        )
        assert done.returncode == 0, done.stderr
        assert done.stdout.splitlines()[0] == str(path)
        assert "permission denied" in done.stdout.splitlines()[1]
    finally:
        path.chmod(0o644)


def test_a_file_swapped_for_a_pipe_after_the_check_does_not_block(tmp_path, monkeypatch):
    path = tmp_path / "swap.hdr"
    os.mkfifo(path)
    monkeypatch.setattr(files, "check_input", lambda p: None)  # as if it was a file then
    with no_hang(), pytest.raises(BakeshopError, match="not a regular file"):
        files.open_input(path)


def test_check_input_returns_the_status_of_a_regular_file(tmp_path):
    path = tmp_path / "a.pfm"
    write_image(path, np.ones((2, 2, 3), np.float32))
    assert check_input(path).st_size == path.stat().st_size


# --- atomic writes -------------------------------------------------------------------------------


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_record_writes_collects_completed_files_in_order(tmp_path):
    image = np.ones((4, 4, 3), np.float32)
    with record_writes() as outer:
        write_image(tmp_path / "a.hdr", image)
        with record_writes() as inner:
            write_dds(tmp_path / "b.dds", [image[None].repeat(6, 0)])
            with pytest.raises(BakeshopError):
                write_image(tmp_path / "missing" / "c.hdr", image)
    write_image(tmp_path / "d.hdr", image)
    assert outer == [tmp_path / "a.hdr", tmp_path / "b.dds"]
    assert inner == [tmp_path / "b.dds"]


def test_a_codec_error_is_about_the_target_and_leaves_nothing(tmp_path):
    with pytest.raises(BakeshopError) as caught:
        write_image(tmp_path / "a.pfm", np.ones((2, 2, 4), np.float32))
    assert caught.value.path == str(tmp_path / "a.pfm")
    assert leftovers(tmp_path) == []


def test_writing_over_a_directory_names_it(tmp_path):
    (tmp_path / "out.hdr").mkdir()
    with pytest.raises(BakeshopError, match="is a directory") as caught:
        write_image(tmp_path / "out.hdr", np.ones((2, 8, 3), np.float32))
    assert caught.value.path == str(tmp_path / "out.hdr")
    assert leftovers(tmp_path) == []


def test_a_target_in_proc_names_the_target(tmp_path):
    with pytest.raises(BakeshopError) as caught:
        write_image("/proc/bakeshop_out.exr", np.ones((2, 2, 3), np.float32))
    assert caught.value.path == "/proc/bakeshop_out.exr"
    assert "cannot create a file in '/proc'" in caught.value.reason
    assert ".bakeshop_out." not in str(caught.value)


@pytest.fixture
def tmpfs(tmp_path):
    """Mount a fresh tmpfs (root only); yields a function mount(size, read_only) -> folder."""
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root; run as root to test full and read-only disks")
    mounted = []

    def mount(size: str, read_only: bool = False) -> Path:
        folder = tmp_path / f"mnt{len(mounted)}"
        folder.mkdir()
        options = f"size={size}" + (",ro" if read_only else "")
        done = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)],
            capture_output=True,
            text=True,
        )
        if done.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()}")
        mounted.append(folder)
        return folder

    yield mount
    for folder in mounted:
        subprocess.run(["umount", "-l", str(folder)], check=False)


@pytest.mark.parametrize("name", ["big.exr", "big.hdr", "big.pfm", "big.png", "big.tga"])
def test_a_full_disk_names_the_target_and_leaves_nothing(tmpfs, name):
    folder = tmpfs("256k")
    image = np.random.default_rng(1).random((512, 512, 3), dtype=np.float32)
    target = folder / name
    with pytest.raises(BakeshopError) as caught:
        write_image(target, image)
    error = caught.value
    assert error.path == str(target)
    assert "no space left" in error.reason.lower()
    assert f".{target.stem}." not in str(error)  # the temporary's name
    assert list(folder.iterdir()) == []


def test_a_read_only_mount_names_the_target(tmpfs):
    folder = tmpfs("1m", read_only=True)
    with pytest.raises(BakeshopError, match="read-only file system") as caught:
        write_image(folder / "a.exr", np.ones((4, 4, 3), np.float32))
    assert caught.value.path == str(folder / "a.exr")
    assert "Errno" not in str(caught.value)  # plain words


@pytest.mark.slow
def test_a_signal_at_any_moment_of_writing_leaves_no_temporary(tmp_path):
    """Small writes in a loop, interrupted by SIGTERM at random moments (creating the
    temporary, writing it, renaming it), round after round in one child: no round leaves a
    temporary (tempfile.mkstemp, used before, left one in about 10 rounds: the file exists
    before its name is returned)."""
    code = (
        "import json, os, sys, numpy as np\n"
        "from bakeshop.cli._process import signals_as_exceptions\n"
        "from bakeshop.io import write_image\n"
        "target, image = os.path.join(sys.argv[1], 'out.hdr'), np.ones((4, 8, 3), np.float32)\n"
        "write_image(target, image)\n"  # compiled code loaded before the first signal
        "for _ in range(int(sys.argv[2])):\n"
        "    done = 0\n"
        "    with signals_as_exceptions() as received:\n"
        "        try:\n"
        "            while True:\n"
        "                write_image(target, image)\n"
        "                done += 1\n"
        "                if done == 1:\n"  # in the loop of writes: the signal lands amid them
        "                    print('ready', flush=True)\n"
        "        except BaseException:\n"  # a library may report the signal as another error
        "            pass\n"
        "    left = [n for n in os.listdir(sys.argv[1]) if n.startswith('.')]\n"
        "    print(json.dumps([received, left, done]), flush=True)\n"
    )
    rounds = 200
    child = subprocess.Popen(
        [sys.executable, "-c", code, str(tmp_path), str(rounds)],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        text=True,
    )
    rng = np.random.default_rng(5)
    try:
        # 'ready' comes after a round's first write, from inside its loop of writes: each signal
        # lands amid the writes by construction, at a random moment of one (sent 0-10 ms after a
        # 'ready' printed before the loop, it landed before the first write in most rounds on a
        # loaded CI machine: 79 writes in 200 rounds)
        for _ in range(rounds):
            assert child.stdout.readline() == "ready\n"
            time.sleep(rng.uniform(0.0, 0.01))
            child.send_signal(signal.SIGTERM)
            received, left, done = json.loads(child.stdout.readline())
            assert received == [signal.SIGTERM] and left == [] and done >= 1
    finally:
        child.kill()
        child.wait()


@pytest.mark.parametrize(
    "number", ["1e999", "-1e999", "1" + "0" * 400, "1" + "0" * 5000, "NaN", "-Infinity"]
)
def test_a_json_number_no_float64_holds_is_refused(tmp_path, number):
    path = tmp_path / "sun.json"
    path.write_text(f'{{"direction": [{number}, 0, 1], "seed": 123456789012345678901}}')
    with pytest.raises(FormatError, match="not a finite float64") as e:
        read_json(path)
    assert e.value.path == str(path) and len(str(e.value)) < 200


def test_json_numbers_in_range_are_read_as_written(tmp_path):
    path = tmp_path / "doc.json"
    path.write_text('{"a": [1e308, -2, 123456789012345678901, 0.1]}')
    assert read_json(path) == {"a": [1e308, -2, 123456789012345678901, 0.1]}
