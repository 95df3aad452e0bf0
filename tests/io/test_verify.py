"""What saves must load: within verify_writes() every writer's file is re-read and compared with
what was meant, and a writer that saves what it cannot load is stopped before the file takes
its name."""

import hashlib

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.cli.main import main
from bakeshop.errors import FormatError
from bakeshop.io import pfm

RNG = np.random.default_rng(7)
HDR = (RNG.random((12, 20, 3), dtype=np.float32) * 8).astype(np.float32)
LDR = RNG.random((12, 20, 3), dtype=np.float32)


@pytest.mark.parametrize(
    ("name", "image", "check"),
    [
        ("a.pfm", HDR, "exact"),
        ("a.exr", HDR, "exact"),
        ("a.tif", HDR, "exact"),
        ("a.hdr", HDR, "within"),
        ("a.png", LDR, "exact"),
        ("a.tga", LDR, "exact"),
        ("a.jpg", LDR, "within"),
    ],
)
def test_every_image_writer_reloads_as_meant(tmp_path, name, image, check):
    with bio.verify_writes() as records:
        bio.write_image(tmp_path / name, image)
    (record,) = records
    assert record["ok"], record
    assert record["check"] == check
    assert record["file"] == str(tmp_path / name)
    assert main(["-q", "info", str(tmp_path / name)]) == 0  # and bakeshop info reads it


def test_sixteen_bit_codes_are_exact(tmp_path):
    with bio.verify_writes() as records:
        bio.write_image(tmp_path / "a.png", LDR, bits=16)
    assert records[0]["ok"] and records[0]["reason"] == "16-bit codes exact"


@pytest.mark.parametrize("ext", ["dds", "ktx", "ktx2"])
def test_mip_chains_reload_bit_exact(tmp_path, ext):
    cube = RNG.random((6, 8, 8, 3), dtype=np.float32)
    with bio.verify_writes() as records:
        bio.write_chain(tmp_path / f"c.{ext}", [cube, cube[:, :4, :4]])
    assert records[0]["ok"] and records[0]["check"] == "exact", records[0]
    assert main(["-q", "info", str(tmp_path / f"c.{ext}")]) == 0


def test_json_reloads_as_the_same_document(tmp_path):
    with bio.verify_writes() as records:
        bio.write_json(tmp_path / "a.json", {"a": np.float32(0.5), "b": [1, 2]})
    assert records[0]["ok"] and records[0]["writer"] == "json"


def _truncating(original):
    def write(path, image, **options):
        original(path, image, **options)
        with open(path, "r+b") as f:
            f.truncate(40)

    return write


def test_a_writer_that_saves_what_it_cannot_load_is_stopped(tmp_path, monkeypatch):
    target = tmp_path / "probe.pfm"
    bio.write_image(target, HDR)
    before = hashlib.sha256(target.read_bytes()).hexdigest()
    monkeypatch.setattr(pfm, "write", _truncating(pfm.write))
    with pytest.raises(FormatError) as e, bio.verify_writes() as records:
        bio.write_image(target, HDR * 2)
    assert e.value.path == str(target)
    assert "does not reload" in e.value.reason
    assert not records[0]["ok"]
    # the old file is untouched and no temporary is left beside it
    assert hashlib.sha256(target.read_bytes()).hexdigest() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["probe.pfm"]
    # without the check the same writer leaves a file nothing can read
    bio.write_image(target, HDR)
    with pytest.raises(FormatError):
        bio.read_image(target)


def test_a_writer_that_stores_other_values_is_stopped(tmp_path, monkeypatch):
    original = pfm.write

    def flipped(path, image, **options):
        original(path, np.ascontiguousarray(image[::-1]), **options)

    monkeypatch.setattr(pfm, "write", flipped)
    with pytest.raises(FormatError, match="values differ"), bio.verify_writes():
        bio.write_image(tmp_path / "a.pfm", HDR)
    assert not (tmp_path / "a.pfm").exists()


def test_rgbe_is_held_to_its_stated_bound(tmp_path, monkeypatch):
    from bakeshop.io import rgbe

    original = rgbe.write
    monkeypatch.setattr(rgbe, "write", lambda p, im, **o: original(p, im * 1.02, **o))
    with pytest.raises(FormatError, match="RGBE"), bio.verify_writes():
        bio.write_image(tmp_path / "a.hdr", HDR)


def test_nothing_is_checked_outside_a_session(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(bio.verify, "check_file", lambda *a, **k: calls.append(a))
    bio.write_image(tmp_path / "a.pfm", HDR)
    assert calls == [] and not bio.verify.verifying()
