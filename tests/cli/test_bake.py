"""``bakeshop bake``: what a user sees (through bakeshop.cli.main.main)."""

import hashlib
import json
import os

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.bake import OPERATIONS, Operation, Option
from bakeshop.cli.main import main
from bakeshop.io import pfm
from tests.io.test_files import no_hang

RECIPE = """
[copy.a]
input = "a.pfm"
output = "out/a.pfm"

[copy.b]
input = "out/a.pfm"
output = "out/b.pfm"
gain = 2.0
"""


def _copy(options):
    bio.write_image(options["output"], bio.read_image(options["input"]) * options["gain"])
    return {}


@pytest.fixture
def level(tmp_path, monkeypatch):
    op = Operation(
        name="copy",
        version=1,
        summary="an image, times a gain",
        paths={"input": "input", "output": "output"},
        options={"gain": Option(1.0, "float", 0, 10)},
        run=_copy,
    )
    monkeypatch.setitem(OPERATIONS, "copy", op)
    (tmp_path / "out").mkdir()
    bio.write_image(tmp_path / "a.pfm", np.ones((4, 8, 3), np.float32))
    (tmp_path / "level.toml").write_text(RECIPE)
    return tmp_path / "level.toml"


def run(capsys, *args):
    status = main(["-q", *map(str, args)])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_help_teaches_with_an_example(capsys):
    status, out, _ = run(capsys, "bake", "--help")
    assert status == 0 and "Example:" in out and "docs/recipes.md" in out


def test_operations_lists_every_key_with_its_range_and_default(capsys):
    status, out, _ = run(capsys, "bake", "--operations")
    assert status == 0
    assert "[probe.NAME]" in out and "[water.NAME]" in out
    assert "mips           int in [1, 14] (default 9)" in out
    assert "zstd           bool (default false)" in out


def test_bake_explain_and_nothing_to_do(capsys, level):
    status, out, err = run(capsys, "bake", level, "--explain")
    assert status == 0 and err == ""
    lines = out.splitlines()
    assert lines[0] == "rebuild    copy.a: never built"
    assert lines[1].startswith("built      copy.a in ") and "1 re-read and checked" in lines[1]
    assert lines[-1].startswith("baked 2 of 2 steps in ")
    status, out, _ = run(capsys, "bake", level)
    assert status == 0 and out.startswith("nothing to do: all 2 steps are up to date")


def test_dry_run_says_what_would_change_and_why(capsys, level):
    run(capsys, "bake", level)
    level.write_text(RECIPE.replace("gain = 2.0", "gain = 3.0"))
    status, out, _ = run(capsys, "bake", level, "--dry-run")
    assert status == 0
    assert out.splitlines() == [
        "up to date copy.a",
        "rebuild    copy.b: option gain changed (2.0 -> 3.0)",
        "would rebuild 1 of 2 steps (dry run: nothing written)",
    ]
    status, out, _ = run(capsys, "bake", level, "--dry-run", "--force", "copy.a")
    assert "rebuild    copy.a: forced" in out
    assert "rebuild    copy.b: option gain changed" in out


def test_a_bad_recipe_is_one_error_line(capsys, level):
    level.write_text(RECIPE.replace("gain = 2.0", "gian = 2.0"))
    status, out, err = run(capsys, "bake", level)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"bakeshop: error: {level}: unknown key 'gian'")


def test_an_output_that_does_not_reload_fails_the_bake_naming_it(capsys, level, monkeypatch):
    original = pfm.write

    def truncating(path, image, **options):
        original(path, image, **options)
        with open(path, "r+b") as f:
            f.truncate(20)

    monkeypatch.setattr(pfm, "write", truncating)
    status, out, err = run(capsys, "bake", level)
    assert status == 2
    assert "not run    copy.b: copy.a failed" in out
    target = level.parent / "out" / "a.pfm"
    assert err.startswith(f"bakeshop: error: {target}: copy.a: the file written does not reload")
    assert not target.exists()


def test_init_writes_a_starter_recipe_and_never_replaces_one(capsys, tmp_path):
    bio.write_image(tmp_path / "atrium.hdr", np.ones((8, 16, 3), np.float32))
    recipe = tmp_path / "level.toml"
    status, out, _ = run(capsys, "bake", "--init", recipe)
    assert status == 0 and out.startswith(f"wrote {recipe}: 1 probe step(s)")
    assert "[probe.atrium]" in recipe.read_text()
    status, out, err = run(capsys, "bake", recipe, "--dry-run")
    assert status == 0 and out.splitlines()[0] == "rebuild    probe.atrium: never built"
    status, _, err = run(capsys, "bake", "--init", recipe)
    assert (
        status == 2
        and err == f"bakeshop: error: {recipe}: already exists; --init never replaces a recipe\n"
    )


def one_line(capsys, *args) -> str:
    """The one error line of ``bakeshop bake ARGS``: exit 2, nothing on stdout."""
    status, out, err = run(capsys, "bake", *args)
    assert status == 2 and out == "" and err.count("\n") == 1, (status, out, err)
    assert err.startswith("bakeshop: error: ")
    return err.removeprefix("bakeshop: error: ").rstrip("\n")


def test_a_forged_manifest_never_deletes_a_file_outside_the_level(capsys, level):
    victim = level.parent.parent / f"{level.parent.name}-victim.txt"
    victim.write_text("precious")
    run(capsys, "bake", level)
    manifest = level.parent / "level.bake.json"
    document = json.loads(manifest.read_text())
    sha = hashlib.sha256(b"precious").hexdigest()
    forged = {"file": f"../{victim.name}", "bytes": 8, "sha256": sha}
    document["steps"]["copy.b"]["outputs"].append(forged)
    manifest.write_text(json.dumps(document))
    level.write_text(RECIPE.replace("gain = 2.0", "gain = 3.0"))
    line = one_line(capsys, level)
    assert line.startswith(f"{manifest}: steps.copy.b.outputs[1].file '../{victim.name}'")
    assert victim.read_text() == "precious"
    victim.unlink()


def test_a_forged_entry_for_a_file_no_step_makes_is_left_in_place_and_said(capsys, level):
    notes = level.parent / "notes.txt"
    notes.write_text("precious")
    run(capsys, "bake", level)
    manifest = level.parent / "level.bake.json"
    document = json.loads(manifest.read_text())
    sha = hashlib.sha256(b"precious").hexdigest()
    document["steps"]["copy.b"]["outputs"].append({"file": "notes.txt", "bytes": 8, "sha256": sha})
    manifest.write_text(json.dumps(document))
    level.write_text(RECIPE.replace("gain = 2.0", "gain = 3.0"))
    status, out, err = run(capsys, "bake", level)
    assert status == 0 and err == "" and notes.read_text() == "precious"
    assert out.splitlines()[1] == (
        "left in place: notes.txt (no step of the recipe makes it any more; delete it yourself)"
    )
    record = json.loads(manifest.read_text())["steps"]["copy.b"]
    assert record["removed"] == [] and record["left"] == ["notes.txt"]
    assert "notes.txt" not in {o["file"] for o in record["outputs"]}


@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "nested", "outside"])
def test_a_hostile_recipe_is_one_error_line(capsys, tmp_path, kind):
    path = tmp_path / "level.toml"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "/dev/zero":
        path = "/dev/zero"
    elif kind == "nested":
        path.write_text("a = " + "[" * 10_000 + "]" * 10_000 + "\n")
    else:
        path.write_text('[water.w]\noutput = "../w"\n')
    with no_hang():
        line = one_line(capsys, path)
    reason = {
        "fifo": "named pipe",
        "/dev/zero": "character device",
        "nested": "nested too deeply",
        "outside": "water.w writes",
    }[kind]
    assert reason in line and os.listdir(tmp_path) == (
        [] if kind == "/dev/zero" else ["level.toml"]
    )


def test_a_folder_outside_the_recipes_needs_allow_folder(capsys, level):
    sub = level.parent / "recipes"
    sub.mkdir()
    text = '[bake]\nfolder = ".."\n' + RECIPE.replace('"a.pfm"', '"../a.pfm"')
    (sub / "level.toml").write_text(text.replace('"out/', '"../out/'))
    line = one_line(capsys, sub / "level.toml")
    assert f"confirm it (--allow-folder {level.parent})" in line
    status, out, _ = run(capsys, "bake", sub / "level.toml", "--allow-folder", level.parent)
    assert status == 0 and out.splitlines()[-1].startswith("baked 2 of 2 steps")
