"""Incremental bakes measured by a work counter: a second run rebuilds nothing, touching one
input rebuilds only its dependents, options and versions key their steps, corrupted outputs
are found, and a writer that saves what it cannot load fails the bake naming the file.

The engine is tested on a cheap operation (``scale``: one image times a factor, written through
bakeshop.io), registered for the test beside the real ones; tests/bake/test_recipes.py runs
the real operations."""

import dataclasses
import hashlib
import os
import time

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.bake import OPERATIONS, Operation, Option, load_recipe, plan, run
from bakeshop.bake.build import FileHashes
from bakeshop.io import pfm

RECIPE = """
[defaults.scale]
factor = 2.0

[scale.a]
input = "in/a.pfm"
output = "out/a.pfm"

[scale.b]
input = "in/b.pfm"
output = "out/b.pfm"

[scale.a2]
input = "out/a.pfm"
output = "out/a2.pfm"
factor = 0.5
"""


class Counter:
    def __init__(self):
        self.calls = []

    def __call__(self, options):
        self.calls.append(options["output"].name)
        image = bio.read_image(options["input"])
        bio.write_image(options["output"], image * np.float32(options["factor"]))
        return {"factor": options["factor"]}


@pytest.fixture
def work(monkeypatch):
    counter = Counter()
    op = Operation(
        name="scale",
        version=1,
        summary="an image times a factor",
        paths={"input": "input", "output": "output"},
        options={"factor": Option(1.0, "float", -10, 10)},
        run=counter,
    )
    monkeypatch.setitem(OPERATIONS, "scale", op)
    return counter


def image(seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((8, 16, 3), dtype=np.float32)


@pytest.fixture
def level(tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "out").mkdir()
    bio.write_image(tmp_path / "in/a.pfm", image(1))
    bio.write_image(tmp_path / "in/b.pfm", image(2))
    (tmp_path / "level.toml").write_text(RECIPE)
    return tmp_path


def bake(level, **kw):
    return run(load_recipe(level / "level.toml"), **kw)


def reasons(result):
    return {d.step: d.reasons for d in result.decisions if d.action == "build"}


def test_first_bake_builds_everything_in_dependency_order(work, level):
    result = bake(level)
    assert work.calls == ["a.pfm", "b.pfm", "a2.pfm"]
    assert result.built == ["scale.a", "scale.b", "scale.a2"] and not result.failed
    np.testing.assert_array_equal(bio.read_image(level / "out/a2.pfm"), image(1))


def test_second_bake_does_nothing(work, level):
    bake(level)
    result = bake(level)
    assert len(work.calls) == 3  # nothing ran again
    assert result.built == [] and result.up_to_date == ["scale.a", "scale.b", "scale.a2"]


def test_touching_one_input_rebuilds_only_its_dependents(work, level):
    bake(level)
    bio.write_image(level / "in/b.pfm", image(3))
    result = bake(level)
    assert work.calls[3:] == ["b.pfm"]
    assert reasons(result) == {"scale.b": ["input in/b.pfm changed"]}
    bio.write_image(level / "in/a.pfm", image(4))
    result = bake(level)
    assert work.calls[4:] == ["a.pfm", "a2.pfm"]
    assert reasons(result)["scale.a2"] == ["input out/a.pfm changed"]


def test_a_new_timestamp_on_the_same_bytes_rebuilds_nothing(work, level):
    bake(level)
    os.utime(level / "in/a.pfm")
    assert bake(level).built == [] and len(work.calls) == 3


def test_an_upstream_rebuild_giving_the_same_bytes_stops_there(work, level):
    bake(level)
    result = bake(level, force=["scale.a"])
    assert work.calls[3:] == ["a.pfm"]
    assert "scale.a2" in result.up_to_date


def test_an_option_keys_its_step_and_defaults_key_every_step(work, level):
    bake(level)
    recipe = level / "level.toml"
    recipe.write_text(RECIPE.replace("factor = 0.5", "factor = 0.25"))
    result = bake(level)
    assert work.calls[3:] == ["a2.pfm"]
    assert reasons(result) == {"scale.a2": ["option factor changed (0.5 -> 0.25)"]}
    recipe.write_text(RECIPE.replace("factor = 2.0", "factor = 3.0"))
    result = bake(level)
    # a and b take the default; a2 overrides it but reads a's new output
    assert work.calls[4:] == ["a.pfm", "b.pfm", "a2.pfm"]
    assert reasons(result)["scale.a2"] == [
        "option factor changed (0.25 -> 0.5)",
        "input out/a.pfm changed",
    ]


def test_the_algorithm_version_keys_its_steps(work, level, monkeypatch):
    bake(level)
    monkeypatch.setitem(OPERATIONS, "scale", dataclasses.replace(OPERATIONS["scale"], version=2))
    result = bake(level)
    assert len(work.calls) == 6
    assert reasons(result)["scale.b"] == ["scale's algorithm version changed (1 -> 2)"]


def test_the_bakeshop_version_keys_every_step(work, level, monkeypatch):
    import bakeshop.bake.build as build

    bake(level)
    monkeypatch.setattr(build, "__version__", "99.0")
    result = bake(level)
    assert len(work.calls) == 6
    assert reasons(result)["scale.a"][0].startswith("bakeshop version changed")


def test_a_change_of_bakeshop_code_under_the_same_version_rebuilds(work, level, monkeypatch):
    import bakeshop.bake.build as build

    bake(level)
    before = build.source_digest()
    monkeypatch.setattr(build, "source_digest", lambda: "0123456789abcdef")
    result = bake(level)
    assert len(work.calls) == 6
    assert reasons(result)["scale.b"] == [
        f"bakeshop's code changed (version {build.__version__}, source "
        f"{before} -> 0123456789abcdef)"
    ]


def test_a_second_bake_of_the_same_recipe_at_once_is_refused(work, level):
    import bakeshop.bake.build as build

    recipe = load_recipe(level / "level.toml")
    with build._lock(recipe), pytest.raises(Exception, match="another bake of this recipe"):
        run(recipe)
    assert work.calls == []


def test_a_corrupted_output_is_found_kept_and_rebuilt_once_moved_away(work, level):
    bake(level)
    path = level / "out/b.pfm"
    data = bytearray(path.read_bytes())
    data[-5] ^= 0x40  # one bit of one pixel: still a valid file
    path.write_bytes(bytes(data))
    result = bake(level)
    assert reasons(result)["scale.b"] == [
        "output out/b.pfm differs from what was baked and re-read (edited or corrupted)"
    ]
    assert "bakeshop replaces only files it wrote" in result.failed["scale.b"].reason
    assert path.read_bytes() == data  # an edit is never lost
    path.unlink()
    result = bake(level)
    assert result.built == ["scale.b"]
    np.testing.assert_array_equal(bio.read_image(path), image(2) * 2)


def test_a_deleted_output_is_rebuilt(work, level):
    bake(level)
    (level / "out/a2.pfm").unlink()
    result = bake(level)
    assert work.calls[3:] == ["a2.pfm"]
    assert reasons(result) == {"scale.a2": ["output out/a2.pfm is missing"]}


def test_the_manifest_holds_the_reload_proof_of_every_output(work, level):
    bake(level)
    manifest = bio.read_json(level / "level.bake.json")
    record = manifest["steps"]["scale.b"]
    assert record["inputs"] == {
        "in/b.pfm": hashlib.sha256((level / "in/b.pfm").read_bytes()).hexdigest()
    }
    (out,) = record["outputs"]
    assert out["file"] == "out/b.pfm"
    assert out["sha256"] == hashlib.sha256((level / "out/b.pfm").read_bytes()).hexdigest()
    assert out["bytes"] == (level / "out/b.pfm").stat().st_size
    assert out["reload"]["ok"] and out["reload"]["check"] == "exact"
    assert record["options"] == {"factor": 2.0, "input": "in/b.pfm", "output": "out/b.pfm"}
    assert len(record["key"]) == 64


def test_a_writer_that_cannot_be_read_back_fails_the_bake(work, level, monkeypatch):
    bake(level)
    bio.write_image(level / "in/a.pfm", image(5))
    bio.write_image(level / "in/b.pfm", image(6))
    before = (level / "out/a.pfm").read_bytes()
    original = pfm.write

    def truncating(path, image, **options):
        original(path, image, **options)
        if os.path.basename(path).startswith(".a."):  # the temporary of out/a.pfm
            with open(path, "r+b") as f:
                f.truncate(30)

    monkeypatch.setattr(pfm, "write", truncating)
    result = bake(level)
    error = result.failed["scale.a"]
    assert error.path == str(level / "out/a.pfm")
    assert error.reason.startswith("scale.a: the file written does not reload")
    assert [d.action for d in result.decisions] == ["build", "build", "blocked"]
    assert result.built == ["scale.b"]  # the independent step still ran
    assert (level / "out/a.pfm").read_bytes() == before  # the old output is intact
    monkeypatch.setattr(pfm, "write", original)
    result = bake(level)
    assert result.built == ["scale.a", "scale.a2"]
    assert reasons(result)["scale.a"] == [f"its last bake failed ({error})"]


def test_an_interrupted_bake_resumes_where_it_stopped(work, level, monkeypatch):
    counter = OPERATIONS["scale"].run

    def interrupt(options):
        if options["output"].name == "b.pfm":
            raise KeyboardInterrupt
        return counter(options)

    monkeypatch.setitem(
        OPERATIONS, "scale", dataclasses.replace(OPERATIONS["scale"], run=interrupt)
    )
    with pytest.raises(KeyboardInterrupt):
        bake(level)
    monkeypatch.setitem(OPERATIONS, "scale", dataclasses.replace(OPERATIONS["scale"], run=counter))
    result = bake(level)
    assert result.up_to_date == ["scale.a"]
    assert result.built == ["scale.b", "scale.a2"]


def test_a_dry_run_explains_and_writes_nothing(work, level):
    bake(level)
    bio.write_image(level / "in/a.pfm", image(7))
    manifest = (level / "level.bake.json").read_bytes()
    decisions = plan(load_recipe(level / "level.toml"))
    assert [(d.step, d.action) for d in decisions] == [
        ("scale.a", "build"),
        ("scale.b", "skip"),
        ("scale.a2", "wait"),
    ]
    assert decisions[0].reasons == ["input in/a.pfm changed"]
    assert decisions[2].reasons == ["rebuilt if scale.a changes what it reads"]
    assert len(work.calls) == 3 and (level / "level.bake.json").read_bytes() == manifest


def test_force_needs_a_step_of_the_recipe(work, level):
    with pytest.raises(Exception, match="scale.a, scale.b, scale.a2"):
        bake(level, force=["scale.c"])


def test_digests_are_cached_by_stat_and_racy_files_rehashed(tmp_path):
    path = tmp_path / "big.bin"
    path.write_bytes(b"x" * 1000)
    old = time.time() - 60
    os.utime(path, (old, old))
    hashes = FileHashes(tmp_path / "hashes.json")
    digest = hashes.digest(path)
    assert digest == hashlib.sha256(b"x" * 1000).hexdigest()
    hashes.save()
    again = FileHashes(tmp_path / "hashes.json")
    assert again.digest(path) == digest and again.hashed == 0  # one stat, no read
    path.write_bytes(b"y" * 1000)  # same size, new time: read again
    assert again.digest(path) == hashlib.sha256(b"y" * 1000).hexdigest() and again.hashed == 1
    # a file modified just before it was hashed is not trusted to the cache
    assert again.digest(path) and again.hashed == 2
    assert again.digest(tmp_path / "missing") is None


def test_a_renamed_output_is_left_in_place_and_dropped_from_the_manifest(work, level):
    bake(level)
    recipe = level / "level.toml"
    recipe.write_text(RECIPE.replace('output = "out/b.pfm"', 'output = "out/b2.pfm"'))
    result = bake(level)
    assert result.built == ["scale.b"]
    assert (level / "out/b.pfm").exists() and (level / "out/b2.pfm").exists()
    record = bio.read_json(level / "level.bake.json")["steps"]["scale.b"]
    assert record["removed"] == [] and record["left"] == ["out/b.pfm"]
    assert [o["file"] for o in record["outputs"]] == ["out/b2.pfm"]


def test_outputs_a_step_no_longer_writes_are_removed_unless_edited(work, level):
    bake(level)
    manifest = level / "level.bake.json"
    document = bio.read_json(manifest)
    for name, recorded in (("out/b.pfm.json", b"stale"), ("out/b.pfm.txt", b"as baked")):
        (level / name).write_bytes(b"stale")  # the second edited since its bake
        entry = {"bytes": 5, "sha256": hashlib.sha256(recorded).hexdigest()}
        document["steps"]["scale.b"]["outputs"].append({"file": name, **entry})
    bio.write_json(manifest, document)
    (level / "level.toml").write_text(RECIPE.replace('"out/b.pfm"', '"out/b.pfm"\nfactor = 3.0'))
    assert bake(level).built == ["scale.b"]
    assert not (level / "out/b.pfm.json").exists() and (level / "out/b.pfm.txt").exists()
    assert bio.read_json(manifest)["steps"]["scale.b"]["removed"] == ["out/b.pfm.json"]


def test_temporaries_left_by_a_killed_write_are_removed(work, level):
    bake(level)
    left = level / "out/.b.0123456789ab.pfm"
    left.write_bytes(b"half a file")
    other = level / "out/.b.notatemporary.pfm"
    other.write_bytes(b"someone else's")
    bake(level, force=["scale.b"])
    assert not left.exists() and other.exists()


def test_jobs_run_independent_steps_at_once_each_with_its_own_proofs(work, level, monkeypatch):
    import threading

    counter = OPERATIONS["scale"].run
    meet = threading.Barrier(2, timeout=20)

    def together(options):
        if options["output"].name in ("a.pfm", "b.pfm"):
            meet.wait()  # a and b are independent: with two jobs both get here, or this fails
        return counter(options)

    monkeypatch.setitem(OPERATIONS, "scale", dataclasses.replace(OPERATIONS["scale"], run=together))
    result = bake(level, jobs=2)
    assert not result.failed and sorted(result.built) == ["scale.a", "scale.a2", "scale.b"]
    # after the step it reads (b, independent, may finish before or after it)
    assert result.built.index("scale.a2") > result.built.index("scale.a")
    assert [d.step for d in result.decisions] == ["scale.a", "scale.b", "scale.a2"]
    steps = bio.read_json(level / "level.bake.json")["steps"]
    for name, out in (("scale.a", "out/a.pfm"), ("scale.b", "out/b.pfm")):
        (record,) = steps[name]["outputs"]  # only its own file, with its own proof
        assert record["file"] == out and record["reload"]["ok"]


def test_jobs_give_the_same_files_and_manifest_records_as_a_serial_bake(work, level, tmp_path):
    import shutil

    other = tmp_path / "serial"
    shutil.copytree(level, other)
    parallel = bake(level, jobs=3)
    serial = bake(other)
    assert sorted(parallel.built) == sorted(serial.built)
    a = bio.read_json(level / "level.bake.json")["steps"]
    b = bio.read_json(other / "level.bake.json")["steps"]
    for name in a:
        assert a[name]["key"] == b[name]["key"]
        assert a[name]["outputs"] == [
            {**o, "reload": {**o["reload"], "seconds": p["reload"]["seconds"]}}
            for o, p in zip(b[name]["outputs"], a[name]["outputs"], strict=True)
        ]
    assert bake(level, jobs=2).built == []


def test_a_write_from_another_thread_is_unchecked_and_fails_the_step(work, level, monkeypatch):
    import threading

    counter = OPERATIONS["scale"].run

    def elsewhere(options):
        worker = threading.Thread(target=counter, args=(options,))
        worker.start()
        worker.join()
        return {}

    monkeypatch.setitem(
        OPERATIONS, "scale", dataclasses.replace(OPERATIONS["scale"], run=elsewhere)
    )
    result = bake(level)
    assert "wrote nothing through bakeshop.io in its own thread" in result.failed["scale.a"].reason
