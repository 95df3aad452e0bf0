"""A recipe and its manifest are untrusted: a bake writes and deletes only files it wrote, inside
the folder its recipe governs, never an input, the recipe or its bookkeeping; a manifest or digest
cache of the wrong shape, a special file where a file is expected, and a hostile recipe file are
each refused in one error naming the file, with nothing written or deleted."""

import dataclasses
import hashlib
import json
import os
import time

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.bake import OPERATIONS, Operation, Option, load_recipe, plan, run
from bakeshop.bake.recipe import MAX_RECIPE_BYTES
from bakeshop.errors import BakeshopError
from tests.io.test_files import no_hang

RECIPE = """
[scale.a]
input = "in/a.pfm"
output = "out/a.pfm"

[scale.b]
input = "in/b.pfm"
output = "out/b.pfm"
"""


def _scale(options):
    bio.write_image(options["output"], bio.read_image(options["input"]) * options["factor"])
    return {}


@pytest.fixture(autouse=True)
def scale(monkeypatch):
    op = Operation(
        name="scale",
        version=1,
        summary="an image times a factor",
        paths={"input": "input", "output": "output"},
        options={"factor": Option(2.0, "float", -10, 10)},
        run=_scale,
    )
    monkeypatch.setitem(OPERATIONS, "scale", op)
    return op


@pytest.fixture
def level(tmp_path):
    """A level in ``tmp_path/level``, baked once, and a victim file beside it."""
    root = tmp_path / "level"
    (root / "in").mkdir(parents=True)
    bio.write_image(root / "in/a.pfm", np.ones((4, 8, 3), np.float32))
    bio.write_image(root / "in/b.pfm", np.full((4, 8, 3), 0.5, np.float32))
    (root / "level.toml").write_text(RECIPE)
    (tmp_path / "victim.txt").write_text("precious")
    assert not bake(root).failed
    return root


def bake(root, **kw):
    return run(load_recipe(root / "level.toml"), **kw)


def snapshot(folder):
    """Every file under ``folder`` (the digest cache aside) and its bytes."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and ".bakeshop" not in p.parts
    }


def manifest(root) -> dict:
    return json.loads((root / "level.bake.json").read_text())


def entry(path) -> dict:
    data = path.read_bytes()
    return {"file": os.fspath(path), "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def forge(root, change) -> None:
    document = manifest(root)
    change(document)
    (root / "level.bake.json").write_text(json.dumps(document))


def refused(root, **kw) -> str:
    """The one error of a bake of ``root`` (or of its dry run), with nothing touched."""
    before = snapshot(root.parent)
    for attempt in (lambda: plan(load_recipe(root / "level.toml")), lambda: bake(root, **kw)):
        with no_hang(), pytest.raises(BakeshopError) as e:
            attempt()
    assert snapshot(root.parent) == before
    return str(e.value)


# -- the manifest names files to delete or replace -------------------------------------------


@pytest.mark.parametrize("name", ["../victim.txt", "ABSOLUTE", "in/../../victim.txt"])
def test_a_forged_output_outside_the_level_is_refused_and_the_victim_survives(level, name):
    victim = level.parent / "victim.txt"
    forged = entry(victim) | {"file": os.fspath(victim) if name == "ABSOLUTE" else name}
    forge(level, lambda m: m["steps"]["scale.a"]["outputs"].append(forged))
    (level / "level.toml").write_text(RECIPE.replace('"in/a.pfm"', '"in/a.pfm"\nfactor = 3.0'))
    error = refused(level)
    assert error.startswith(f"{level / 'level.bake.json'}: steps.scale.a.outputs[1].file")
    assert "is not a file inside" in error and victim.read_text() == "precious"


def test_a_forged_output_naming_an_input_never_deletes_it(level):
    forged = entry(level / "in/b.pfm") | {"file": "in/b.pfm"}
    forge(level, lambda m: m["steps"]["scale.a"]["outputs"].append(forged))
    (level / "level.toml").write_text(RECIPE.replace('"in/a.pfm"', '"in/a.pfm"\nfactor = 3.0'))
    before = (level / "in/b.pfm").read_bytes()
    result = bake(level)
    assert result.built == ["scale.a"] and not result.failed
    assert (level / "in/b.pfm").read_bytes() == before
    assert manifest(level)["steps"]["scale.a"]["removed"] == []


def test_a_forged_output_naming_a_file_no_step_makes_is_left_in_place(level):
    (level / "notes.txt").write_text("the artist's notes")
    forged = entry(level / "notes.txt") | {"file": "notes.txt"}
    forge(level, lambda m: m["steps"]["scale.a"]["outputs"].append(forged))
    (level / "level.toml").write_text(RECIPE.replace('"in/a.pfm"', '"in/a.pfm"\nfactor = 3.0'))
    result = bake(level)
    assert result.built == ["scale.a"] and not result.failed
    assert (level / "notes.txt").read_text() == "the artist's notes"
    record = manifest(level)["steps"]["scale.a"]
    assert record["removed"] == [] and record["left"] == ["notes.txt"]
    assert "notes.txt" not in {o["file"] for o in record["outputs"]}


def test_a_forged_output_naming_the_recipe_is_refused(level):
    forged = entry(level / "level.toml") | {"file": "level.toml"}
    forge(level, lambda m: m["steps"]["scale.a"]["outputs"].append(forged))
    assert "is the recipe or the bake's bookkeeping" in refused(level)


@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "link to /dev/zero"])
def test_a_special_file_named_as_an_output_is_never_read(level, kind):
    name = "out/special"
    if kind == "fifo":
        os.mkfifo(level / name)
    elif kind == "link to /dev/zero":
        (level / name).symlink_to("/dev/zero")
    else:
        name = "/dev/zero"
    forged = {"file": name, "bytes": 1 << 40, "sha256": "0" * 64}
    forge(level, lambda m: m["steps"]["scale.a"]["outputs"].append(forged))
    with no_hang():
        if kind == "fifo":  # inside the level: found changed, never opened
            (decision, _) = plan(load_recipe(level / "level.toml"))
            assert decision.reasons == ["output out/special is no longer a regular file"]
        else:  # resolves outside the level: the manifest is refused
            assert "is not a file inside" in refused(level)


def test_a_file_the_bake_did_not_write_is_never_replaced(level):
    (level / "out/b.pfm").unlink()
    bio.write_image(level / "out/b.pfm", np.zeros((4, 8, 3), np.float32))  # the user's own
    before = (level / "out/b.pfm").read_bytes()
    forge(level, lambda m: m["steps"].pop("scale.b"))
    result = bake(level)
    assert "bakeshop replaces only files it wrote" in str(result.failed["scale.b"])
    assert (level / "out/b.pfm").read_bytes() == before


# -- the recipe names where to write -----------------------------------------------------------


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('[bake]\nmanifest = "in/a.pfm"\n', "[bake] manifest must be a .json file"),
        ('[bake]\nmanifest = "level.toml"\n', "[bake] manifest must be a .json file"),
        ('[bake]\nmanifest = "out/a.pfm/m.json"\n', "scale.a would write over its manifest"),
        ('[bake]\nmanifest = "../m.json"\n', "[bake] manifest"),
        ('[bake]\ncache = "in"\n', "scale.a reads"),
        ('[bake]\ncache = "."\n', "[bake] cache"),
        ('[scale.c]\ninput = "in/a.pfm"\noutput = "../outside/x.pfm"\n', "scale.c writes"),
        ('[scale.c]\ninput = "in/a.pfm"\noutput = "ABSOLUTE"\n', "scale.c writes"),
        ('[scale.c]\ninput = "in/a.pfm"\noutput = "."\n', "scale.c writes"),
        ('[scale.c]\ninput = "in/a.pfm"\noutput = "in/\\u0000.pfm"\n', "NUL"),
        ('[water.w]\noutput = "w"\nname = "../../../outside/pwned"\n', "name must be a file"),
        ('[water.w]\noutput = "w"\nname = ".."\n', "name must be a file"),
    ],
)
def test_a_recipe_that_writes_outside_its_folder_or_over_its_bookkeeping_is_refused(
    level, table, message
):
    outside = level.parent / "outside/x.pfm"
    (level / "level.toml").write_text(RECIPE + table.replace("ABSOLUTE", os.fspath(outside)))
    assert message in refused(level)
    assert not (level.parent / "outside").exists() and not (level / "w").exists()


def test_an_output_that_is_another_steps_input_never_replaces_the_users_file(level):
    clobber = '[scale.clobber]\ninput = "in/b.pfm"\noutput = "in/a.pfm"\n'
    (level / "level.toml").write_text(clobber + RECIPE)
    before = snapshot(level)
    result = bake(level)
    error = result.failed["scale.clobber"]
    assert error.path == str(level / "in/a.pfm")
    assert "would replace in/a.pfm, which its last bake did not leave there" in error.reason
    assert snapshot(level)["in/a.pfm"] == before["in/a.pfm"]


def test_a_step_writes_only_its_own_output(level, scale, monkeypatch):
    def astray(options):
        bio.write_image(options["output"].parent.parent / "in/a.pfm", np.zeros((4, 8, 3)))
        return {}

    monkeypatch.setitem(OPERATIONS, "scale", dataclasses.replace(scale, run=astray))
    before = snapshot(level)
    result = bake(level, force=["scale.a"])
    assert "scale.a writes only its output out/a.pfm" in str(result.failed["scale.a"])
    assert snapshot(level)["in/a.pfm"] == before["in/a.pfm"]


def test_a_folder_outside_the_recipes_is_governed_only_when_confirmed(level):
    sub = level / "recipes"
    sub.mkdir()
    text = '[bake]\nfolder = ".."\n' + RECIPE.replace('"in/', '"../in/').replace('"out/', '"../o/')
    (sub / "level.toml").write_text(text)
    with pytest.raises(BakeshopError, match="confirm it"):
        load_recipe(sub / "level.toml")
    result = run(load_recipe(sub / "level.toml", allow_folder=level))
    assert result.built == ["scale.a", "scale.b"] and (level / "o/a.pfm").is_file()


# -- the manifest and the digest cache are JSON of one shape -----------------------------------

WRONG_TYPES = {
    "steps a list": lambda m: m.update(steps=[1, 2]),
    "steps a string": lambda m: m.update(steps="x"),
    "record a string": lambda m: m["steps"].update({"scale.a": "built"}),
    "record a list": lambda m: m["steps"].update({"scale.a": []}),
    "failed a number": lambda m: m["steps"]["scale.a"].update(failed=1),
    "options a list": lambda m: m["steps"]["scale.a"].update(options=[]),
    "inputs a list": lambda m: m["steps"]["scale.a"].update(inputs=["in/a.pfm"]),
    "an input digest a number": lambda m: m["steps"]["scale.a"]["inputs"].update({"in/a.pfm": 5}),
    "outputs an object": lambda m: m["steps"]["scale.a"].update(outputs={}),
    "an output a string": lambda m: m["steps"]["scale.a"].update(outputs=["out/a.pfm"]),
    "file a number": lambda m: m["steps"]["scale.a"]["outputs"][0].update(file=5),
    "file missing": lambda m: m["steps"]["scale.a"]["outputs"][0].pop("file"),
    "sha256 a number": lambda m: m["steps"]["scale.a"]["outputs"][0].update(sha256=0),
    "bytes a string": lambda m: m["steps"]["scale.a"]["outputs"][0].update(bytes="5"),
    "bytes true": lambda m: m["steps"]["scale.a"]["outputs"][0].update(bytes=True),
    "reload a list": lambda m: m["steps"]["scale.a"]["outputs"][0].update(reload=[]),
    "removed a string": lambda m: m["steps"]["scale.a"].update(removed="out/x"),
    "a removed file a number": lambda m: m["steps"]["scale.a"].update(removed=[1]),
    "a file left a number": lambda m: m["steps"]["scale.a"].update(left=[1]),
    "operation_version a string": lambda m: m["steps"]["scale.a"].update(operation_version="1"),
    "bakeshop a number": lambda m: m["steps"]["scale.a"].update(bakeshop=1),
    "facts a list": lambda m: m["steps"]["scale.a"].update(facts=[]),
    "seconds a string": lambda m: m["steps"]["scale.a"].update(seconds="1"),
    "recipe a number": lambda m: m.update(recipe=1),
}


def test_a_wrong_number_in_the_manifest_says_what_is_expected(level):
    forge(level, lambda m: m["steps"]["scale.a"].update(operation_version=1e308))
    assert refused(level).startswith(
        f"{level / 'level.bake.json'}: steps.scale.a.operation_version must be an integer, not a "
        "number with a fraction or an exponent"
    )


@pytest.mark.parametrize("change", WRONG_TYPES.values(), ids=WRONG_TYPES)
def test_a_manifest_of_the_wrong_shape_is_refused_in_one_line(level, change):
    forge(level, change)
    error = refused(level)
    assert error.startswith(f"{level / 'level.bake.json'}: ") and "\n" not in error
    assert error.endswith("(delete the manifest to bake every step again)")


@pytest.mark.parametrize(
    "text",
    [
        '{"files": [1]}',
        '{"files": {"x": 5}}',
        '{"files": {"x": [1, 2, 3]}}',
        '{"files": {"x": [1, 2, 3, "4", "d"]}}',
        '{"files": {"x": [1, 2, 3, 4, 5]}}',
        "[" * 100_000,
        '{"files": {"x": [1' + "0" * 5000 + ', 2, 3, 4, "d"]}}',
    ],
)
def test_a_digest_cache_of_the_wrong_shape_is_refused_in_one_line(level, text):
    (level / ".bakeshop/hashes.json").write_text(text)
    error = refused(level)
    assert error.startswith(f"{level / '.bakeshop/hashes.json'}: ") and "\n" not in error


def test_a_manifest_nested_too_deeply_is_one_error(level):
    (level / "level.bake.json").write_text('{"steps": ' + "[" * 100_000)
    assert "nested too deeply" in refused(level)


# -- the recipe file ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("x = 1" + "0" * 5000 + "\n", "an integer of more than 4300 digits"),
        ("a = " + "[" * 10_000 + "]" * 10_000 + "\n", "nested too deeply"),
        ("a = " + "{b = " * 10_000 + "1" + "}" * 10_000 + "\n", "nested too deeply"),
        ("# " + "x" * MAX_RECIPE_BYTES + "\n", "a recipe is at most 4 MiB"),
        ("a = '\xff'\n".encode("latin-1"), "a recipe is UTF-8 text"),
    ],
    ids=["huge integer", "nested arrays", "nested tables", "too large", "not UTF-8"],
)
def test_a_hostile_recipe_file_is_one_error(tmp_path, text, message):
    path = tmp_path / "r.toml"
    (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
    with pytest.raises(BakeshopError, match="^") as e:
        load_recipe(path)
    assert e.value.path == str(path) and message in e.value.reason


@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "NUL"])
def test_a_recipe_that_is_no_file_is_refused_at_once(tmp_path, kind):
    path = tmp_path / "r.toml"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "/dev/zero":
        path = "/dev/zero"
    else:
        path = f"{tmp_path}/r\0.toml"
    with no_hang(), pytest.raises(BakeshopError) as e:
        load_recipe(path)
    assert {"fifo": "named pipe", "/dev/zero": "character device", "NUL": "NUL"}[kind] in str(
        e.value
    )


# -- explanations and scale --------------------------------------------------------------------


def test_explain_names_the_first_differing_key_of_a_nested_option_with_both_values(tmp_path):
    flat = np.full((8, 8, 3), 0.5, np.float32)
    flat[..., 2] = 1.0  # a flat normal map: (0, 0, 1), which the normals step now checks
    bio.write_image(tmp_path / "m.png", flat, bits=16)
    text = """
    [normals.n]
    macro = "m.png"
    output = "o.png"
    layers = [{ detail = "m.png", tile = 8, strength = 0.5, convention = "dx" }]
    """
    (tmp_path / "r.toml").write_text(text)
    assert not run(load_recipe(tmp_path / "r.toml")).failed
    (tmp_path / "r.toml").write_text(text.replace("strength = 0.5", "strength = 0.75"))
    (decision,) = plan(load_recipe(tmp_path / "r.toml"))
    assert decision.reasons == ["option layers[0].strength changed (0.5 -> 0.75)"]


def test_a_long_chain_of_steps_is_validated_and_planned_in_linear_time(tmp_path):
    bio.write_image(tmp_path / "s0.pfm", np.ones((2, 2, 3), np.float32))

    def seconds(n: int) -> float:
        steps = "".join(
            f'[scale.s{i}]\ninput = "s{i}.pfm"\noutput = "s{i + 1}.pfm"\n' for i in range(n)
        )
        (tmp_path / "r.toml").write_text(steps)
        started = time.perf_counter()
        decisions = plan(load_recipe(tmp_path / "r.toml"))  # a chain: no recursion limit
        assert [d.step for d in decisions] == [f"scale.s{i}" for i in range(n)]
        return time.perf_counter() - started

    small, large = seconds(300), seconds(3000)
    assert large < 30 * small + 2.0  # linear: 10 x, quadratic: 100 x (was 180 s at 3000)
