"""Decompression bombs: every decoder states what a file decodes to and refuses, before it
allocates or decodes anything, what exceeds the budget max(DECODE_FLOOR, DECODE_RATIO * size).

The bombs are built here (tests/io/bombs.py), checked at a small size against OpenImageIO or the
format's own formula (so they are real files of their format, not garbage a parser rejects),
and read at full size in a child process whose address space is limited with setrlimit: a
decoder that allocated the image would fail there, one that decoded the runs first would take
a minute (the 16384^2 Radiance and zip OpenEXR bombs took 55-62 s and 8 GB in ``bakeshop info``
before the budget).
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np
import OpenImageIO as oiio
import pytest

from bakeshop.errors import ArgumentError, FormatError
from bakeshop.io import DECODE_FLOOR, DECODE_RATIO, decode_budget, read_image, write_image
from bakeshop.io.budget import check_decode, decode_limit, format_bytes
from tests.io import bombs

#: address space a child may add to what it has after importing bakeshop and reading a small
#: file of the format: far below any bomb's image (1 to 3 GiB), far above a refusal's needs.
HEADROOM = 256 << 20
#: a refusal takes a header parse: seconds here only because the machine is shared.
REFUSAL_SECONDS = 5.0

SIDE = 16384
BUILDERS = {
    "hdr": bombs.radiance_old_rle,
    "exr": bombs.exr_zip,
    "tga": bombs.tga_rle,
    "png": bombs.png_deflate,
}


def read_limited(path, warm, headroom=HEADROOM, **options) -> dict:
    """Read ``path`` in a child whose address space is limited to what it uses after reading
    ``warm`` (a small file of the same format: imports and compiled decoders) plus
    ``headroom``; return what happened: ``refused`` (the message), ``shape``, ``seconds``."""
    code = textwrap.dedent(
        f"""
        import json, resource, sys, time
        from bakeshop.errors import BakeshopError
        from bakeshop.io import read_image
        read_image({str(warm)!r})
        size = next(int(l.split()[1]) * 1024 for l in open("/proc/self/status")
                    if l.startswith("VmSize:"))
        limit = size + {headroom}
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        started = time.perf_counter()
        try:
            image = read_image({str(path)!r}, **{options!r})
            done = {{"shape": list(image.shape), "max": float(image.max())}}
        except BakeshopError as e:
            done = {{"refused": str(e)}}
        except MemoryError:
            done = {{"memory": True}}
        done["seconds"] = time.perf_counter() - started
        print(json.dumps(done))
        """
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


# --- the budget ----------------------------------------------------------------------------------


def test_the_budget_rule():
    assert DECODE_FLOOR == 1 << 30 and DECODE_RATIO == 256
    assert decode_limit(1000) == DECODE_FLOOR
    assert decode_limit(10 << 20) == 2560 << 20
    with decode_budget(12345):
        assert decode_limit(1) == decode_limit(1 << 40) == 12345
        with decode_budget(None):
            assert decode_limit(1000) == DECODE_FLOOR
        assert decode_limit(1) == 12345
    assert decode_limit(1000) == DECODE_FLOOR
    check_decode(DECODE_FLOOR, 1)
    with pytest.raises(FormatError, match=r"1 GiB from 1 bytes of file.*budget of 1 GiB"):
        check_decode(DECODE_FLOOR + 1, 1)


@pytest.mark.parametrize("bad", [0, -1, float("nan"), float("inf"), "8G", True])
def test_a_bad_budget_is_refused(bad):
    with pytest.raises(ArgumentError, match="decode budget"):
        with decode_budget(bad):
            pass


def test_format_bytes():
    assert [format_bytes(n) for n in (5, 1536, 3 << 30, 5 << 40)] == [
        "5 bytes",
        "1.5 KiB",
        "3 GiB",
        "5 TiB",
    ]


# --- every decoder applies it --------------------------------------------------------------------


@pytest.mark.parametrize(
    "name, kwargs",
    [
        ("a.hdr", {}),
        ("a.hdr", {"rle": False}),
        ("a.exr", {}),
        ("a.exr", {"compression": "none"}),
        ("a.tga", {"rle": True}),
        ("a.tga", {}),
        ("a.png", {}),
        ("a.png", {"bits": 16}),
        ("a.jpg", {}),
    ],
)
def test_every_decoder_checks_the_budget_before_decoding(tmp_path, name, kwargs):
    image = np.full((40, 64, 3), 0.5, np.float32)
    write_image(tmp_path / name, image, **kwargs)
    assert read_image(tmp_path / name).shape == (40, 64, 3)
    with pytest.raises(FormatError, match="decompression bomb.*budget of 1000 bytes"):
        read_image(tmp_path / name, max_decoded=1000)
    with decode_budget(1000), pytest.raises(FormatError, match="budget set for this run"):
        read_image(tmp_path / name)


def test_uncompressed_pfm_is_never_a_bomb(tmp_path):
    write_image(tmp_path / "a.pfm", np.ones((40, 64, 3), np.float32))
    assert read_image(tmp_path / "a.pfm", max_decoded=1).shape == (40, 64, 3)


# --- the bombs are real files of their formats -----------------------------------------------


@pytest.mark.parametrize("ext", ["exr", "tga", "png"])
def test_small_bombs_read_the_same_in_openimageio(tmp_path, ext):
    path = tmp_path / f"small.{ext}"
    path.write_bytes(BUILDERS[ext](100, 48))
    image = read_image(path)
    reference = oiio.ImageBuf(str(path)).get_pixels(oiio.FLOAT)
    assert image.shape == reference.shape and image.shape[:2] == (48, 100)
    np.testing.assert_allclose(image, reference, atol=1e-6)
    assert np.ptp(image) == 0


def test_small_radiance_bomb_is_its_pixel_everywhere(tmp_path):
    # OpenImageIO (Walter's rgbe.c) reads no old-style runs: the format's formula is the check
    path = tmp_path / "small.hdr"
    path.write_bytes(bombs.radiance_old_rle(300, 7))
    image = read_image(path)
    assert image.shape == (7, 300, 3)
    assert np.array_equal(image, np.broadcast_to(np.float32(bombs.RGBE_VALUE), image.shape))


# --- full-size bombs under a memory limit ---------------------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("ext", sorted(BUILDERS))
def test_bombs_are_refused_at_once_under_a_memory_limit(tmp_path, ext):
    path = tmp_path / f"bomb.{ext}"
    path.write_bytes(BUILDERS[ext](SIDE, SIDE))
    warm = tmp_path / f"warm.{ext}"
    warm.write_bytes(BUILDERS[ext](64, 64))
    assert path.stat().st_size < 5 << 20  # 128 KiB to 4 MiB of file ...
    done = read_limited(path, warm)
    assert "refused" in done, done  # ... for 1 to 3 GiB of float32 pixels
    assert "decompression bomb" in done["refused"] and str(path) in done["refused"]
    assert done["seconds"] < REFUSAL_SECONDS


@pytest.mark.slow
def test_a_bomb_is_read_when_the_budget_allows_it(tmp_path):
    # 4096 x 4096 RGB float32 (192 MiB) from 32 KiB: refused by default only above the floor,
    # so a smaller floor shows the rule and an explicit budget reads it, in full
    path = tmp_path / "b.hdr"
    path.write_bytes(bombs.radiance_old_rle(4096, 4096))
    with pytest.raises(FormatError, match="decompression bomb"):
        read_image(path, max_decoded=100 << 20)
    image = read_image(path, max_decoded=200 << 20)
    assert image.shape == (4096, 4096, 3)
    assert np.array_equal(image[-1, -1], np.float32(bombs.RGBE_VALUE))


@pytest.mark.slow
def test_channels_not_returned_are_never_converted_or_kept(tmp_path):
    """An OpenEXR with 120 channels besides R, G, B: reading it needs the RGB image, not the
    other 120 planes (decoding the whole file needs 123 planes of 2048 x 1024 halves, 516 MiB,
    more than the child may add)."""
    names = ("B", "G", "R", *(f"aov{i:03d}" for i in range(120)))
    path = tmp_path / "aovs.exr"
    path.write_bytes(bombs.exr_zip(2048, 1024, names))
    warm = tmp_path / "warm.exr"
    warm.write_bytes(bombs.exr_zip(64, 64, names))
    whole = 2048 * 1024 * len(names) * 2
    headroom = 160 << 20
    assert whole > 3 * headroom
    done = read_limited(path, warm, headroom=headroom)
    assert done.get("shape") == [1024, 2048, 3], done
    _, meta = read_image(warm, with_metadata=True)
    assert meta["channels"] == ["R", "G", "B"] and len(meta["ignored_channels"]) == 120
