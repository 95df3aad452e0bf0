"""Recipes are validated completely before any work starts; every mistake names the file and
what is valid."""

import os

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.bake import load_recipe, starter_recipe
from bakeshop.bake.operations import number
from bakeshop.errors import BakeshopError


@pytest.fixture
def folder(tmp_path):
    bio.write_image(tmp_path / "probe.hdr", np.ones((8, 16, 3), np.float32))
    bio.write_image(tmp_path / "n.png", np.full((8, 8, 3), 0.5, np.float32))
    return tmp_path


def load(folder, text):
    (folder / "r.toml").write_text(text)
    return load_recipe(folder / "r.toml")


def error(folder, text) -> str:
    with pytest.raises(BakeshopError) as e:
        load(folder, text)
    assert e.value.path == str((folder / "r.toml").resolve())
    return e.value.reason


def test_defaults_are_shared_and_a_step_overrides_them(folder):
    recipe = load(
        folder,
        """
        [defaults.probe]
        mips = 5
        [probe.a]
        input = "probe.hdr"
        output = "a"
        [probe.b]
        input = "probe.hdr"
        output = "b"
        mips = 3
        """,
    )
    a, b = recipe.steps
    assert (a.options["mips"], b.options["mips"]) == (5, 3)
    assert a.options["specular_size"] == 256  # the command's default
    assert a.output == (folder / "a").resolve()
    assert recipe.manifest == (folder / "r.bake.json").resolve()


def test_steps_run_after_the_steps_whose_outputs_they_read(folder):
    recipe = load(
        folder,
        """
        [compress.spec]
        input = "baked/specular.dds"
        output = "spec_bc6h.dds"
        [probe.a]
        input = "probe.hdr"
        output = "baked"
        """,
    )
    assert [s.name for s in recipe.steps] == ["probe.a", "compress.spec"]
    assert recipe.steps[1].after == ("probe.a",)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "[probes.a]\n",
            "unknown table [probes]; a recipe has: bake, defaults, probe, remap, compress",
        ),
        (
            '[probe.a]\ninput = "probe.hdr"\noutput = "o"\nmip = 3\n',
            "unknown key 'mip' in [probe.a]; probe takes: input, output, layout, cube_size",
        ),
        (
            '[probe.a]\ninput = "probe.hdr"\noutput = "o"\nmips = 30\n',
            "[probe.a] mips must be in [1, 14], got 30",
        ),
        (
            '[probe.a]\ninput = "probe.hdr"\noutput = "o"\nspecular_size = 8\n',
            "[probe.a] mips = 9: an 8-texel cube has 1..4 mip levels",
        ),
        (
            '[probe.a]\ninput = "probe.hdr"\noutput = "o"\nmips = 3.5\n',
            "[probe.a] mips must be an integer, got 3.5",
        ),
        (
            '[probe.a]\ninput = "probe.hdr"\noutput = "o"\nformat = "png"\n',
            "[probe.a] format: unknown value 'png'; choose one of: hdr, exr, pfm, tif",
        ),
        ('[water.w]\noutput = "w"\nwind = nan\n', "[water.w] wind must be a finite number"),
        (
            '[water.w]\noutput = "w"\nresolution = 96\n',
            "[water.w] resolution must be a power of two, got 96",
        ),
        ('[probe.a]\noutput = "o"\n', "[probe.a] needs input (a path)"),
        (
            '[probe.a]\ninput = "nowhere.hdr"\noutput = "o"\n',
            "nowhere.hdr does not exist and no step makes it",
        ),
        (
            '[compress.c]\ninput = "probe.hdr"\noutput = "c.png"\n',
            "written to .dds, .ktx2 or .ktx, not c.png",
        ),
        (
            '[compress.c]\ninput = "probe.hdr"\noutput = "c.dds"\nformat = "bc5"\n'
            'quality = "slow"\n',
            "bc5 has the quality profiles fast, not 'slow'",
        ),
        ('[normals.n]\nmacro = "n.png"\noutput = "o.png"\n', "normals needs layers"),
        (
            '[normals.n]\nmacro = "n.png"\noutput = "o.png"\nlayers = [{ detail = "n.png", '
            "tiles = 2 }]\n",
            "unknown key 'tiles' in layers[0]; a layer takes: detail, mask, tile",
        ),
        ('[defaults.probe]\ninput = "x"\n', "inputs and outputs are set per step"),
        ("[bake]\nstore = 'x'\n", "unknown key 'store' in [bake]; valid: manifest, cache"),
        ("", "the recipe has no steps"),
        ('[water.a]\noutput = "w"\n[water.b]\noutput = "w/b"\n', "water.a and water.b both write"),
        (
            '[compress.a]\ninput = "b.dds"\noutput = "a.dds"\n[compress.b]\ninput = "a.dds"\n'
            'output = "b.dds"\n',
            "steps read each other's outputs in a circle",
        ),
        ("[probe.a\n", "not valid TOML"),
        ('[remap.r]\ninput = "probe.hdr"\noutput = "r.exr"\n', "[remap.r] needs to (the output"),
        (
            '[remap.r]\ninput = "probe.hdr"\noutput = "r.exr"\nto = "faces"\n',
            "a cube is written as six files: put {face} in the output name",
        ),
    ],
)
def test_mistakes_are_refused_before_any_work(folder, text, message):
    assert message in error(folder, text)


REMAP = '[remap.r]\ninput = "probe.hdr"\noutput = "r.exr"\nto = "latlong"\nsize = '
WATER = '[water.w]\noutput = "w"\n'


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (REMAP + "9" * 4000, "[remap.r] size must be in [1, 16384], got an integer of 4000 digits"),
        (
            WATER + "seed = " + "9" * 400,
            "[water.w] seed must be in [0, 9223372036854775807], got an integer of 400 digits",
        ),
        (
            WATER + f"seed = {2**63}",  # rounded to the bound as a float, it passed
            "[water.w] seed must be in [0, 9223372036854775807], got 9223372036854775808",
        ),
        (
            WATER + "size = " + "9" * 400,
            "[water.w] size must be in [0.01, 100000], got an integer of 400 digits",
        ),
        (REMAP + "9" * 5000, "an integer of more than 4300 digits"),
    ],
)
def test_an_integer_out_of_range_is_refused_with_the_range_however_long(folder, text, message):
    assert error(folder, text) == message


def test_a_large_integer_option_keeps_every_digit(folder):
    step = load(folder, WATER + f"seed = {2**60 + 1}\n").steps[0]
    assert step.options["seed"] == 2**60 + 1  # through a float it was 2**60


def test_a_number_beyond_floats_is_refused_without_an_overflow():
    def fail(reason):
        raise BakeshopError(reason)

    with pytest.raises(BakeshopError, match="x must be a finite number .* 401 digits"):
        number(10**400, "x", fail)


def test_a_special_file_as_an_input_is_named_for_what_it_is(folder):
    os.mkfifo(folder / "f.hdr")
    message = error(folder, '[probe.a]\ninput = "f.hdr"\noutput = "o"\n')
    assert message.endswith(
        "f.hdr is a named pipe (FIFO), not a file: bakeshop reads regular files only"
    )


def test_a_missing_recipe_is_named(tmp_path):
    with pytest.raises(BakeshopError, match="no such file"):
        load_recipe(tmp_path / "nope.toml")


def test_a_starter_recipe_bakes_the_folder_as_it_is(folder):
    (folder / "textures").mkdir()
    bio.write_image(folder / "textures/crate_n.png", np.full((8, 8, 3), 0.5, np.float32))
    bio.write_image(folder / "textures/crate_albedo.png", np.full((8, 8, 3), 0.5, np.float32))
    (folder / "baked").mkdir()
    bio.write_image(folder / "baked/old.hdr", np.ones((8, 16, 3), np.float32))  # an output
    text = starter_recipe(folder)
    (folder / "starter.toml").write_text(text)
    recipe = load_recipe(folder / "starter.toml")
    assert [s.name for s in recipe.steps] == ["probe.probe"]
    assert recipe.steps[0].output == (folder / "baked/probe").resolve()
    assert '# macro = "textures/crate_n.png"' in text and "crate_albedo" not in text
    assert '# input = "baked/probe/specular.dds"' in text
    assert recipe.manifest == (folder / "starter.bake.json").resolve()
