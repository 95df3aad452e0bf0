"""Every number the command line takes, for every command: finite, within a range its --help
states, and refused in one line (exit 2, no traceback) when NaN, infinite, or far outside it.

The options are found by walking the click tree, so an option or a command added later is held
to the same rules without touching these tests: it must use one of the shared types of
``bakeshop.cli._common`` (which is what gives it the checks).
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import click
import numpy as np
import pytest

from bakeshop.cli import _numbers
from bakeshop.cli._process import ByteSize
from bakeshop.cli.main import cli, main
from bakeshop.io import write_image
from tests.cli.test_process import commands
from tests.io.test_files import no_hang
from tests.photo import synthetic

#: the shared types that hold numbers (bakeshop.cli._common, and the root's --max-decoded).
SHARED = (
    _numbers.Number,
    _numbers.Integer,
    _numbers.Size,
    _numbers.Fields,
    _numbers.MemorySize,
    ByteSize,
)
#: seconds one run may take on the small inputs below before it counts as a hang (a first call
#: compiles its kernels: 69 s for merge on a loaded 2-core machine).
RUN_SECONDS = 300


def is_numeric(param: click.Parameter) -> bool:
    """True when the parameter holds numbers: a click number type, or a shared type."""
    kinds = (click.types.IntParamType, click.types.FloatParamType, *SHARED)
    return isinstance(param.type, kinds)


def numeric_params(group: click.Group = cli):
    """(words that run the command, its numeric parameter) for every command of the tree, and
    the root group's own options (words ``()``)."""
    for param in group.params:
        if is_numeric(param):
            yield (), param
    for words, command in commands(group):
        for param in command.params:
            if is_numeric(param):
                yield words, param


NUMERIC = list(numeric_params())
IDS = [f"{' '.join(w) or 'bakeshop'}:{p.opts[0]}" for w, p in NUMERIC]

#: words in a metavar that promise a number.
NUMBER_METAVARS = ("N", "WxH", "EV", "DEG", "PX", "S", "SIZE", "M", "KG", "M/S", "DB", "J", "L")


def promises_numbers(token: str) -> bool:
    """A metavar word that stands for numbers: a unit or N, letters separated by commas
    (X,Y,R; T1,T2,...) or an ``x`` (WxH, DxZ)."""
    return (
        token in NUMBER_METAVARS
        or re.fullmatch(r"[A-Z][A-Z0-9]?(,([A-Z][A-Z0-9]?|\.\.\.))+", token) is not None
        or re.fullmatch(r"[A-Z]+x[A-Z]+", token) is not None
    )


def test_the_walk_finds_the_numbers():
    found = {(" ".join(w), p.name) for w, p in NUMERIC}
    assert {
        ("resize", "size"),
        ("convert", "picture_exposure"),
        ("float", "seconds"),
        ("float", "solver_hz"),
        ("float", "size"),
        ("float", "waves"),
        ("remap", "size_text"),
        ("remap", "rotate"),
        ("fresnel", "up"),
        ("prefilter", "samples"),
        ("dfg", "samples"),
        ("normals combine", "tile"),
        ("", "max_decoded"),
        # the commands main gained in the integration (compress, photo, water)
        ("compress", "size"),
        ("compress", "min_psnr"),
        ("bake-probe", "min_psnr"),
        ("merge", "times"),
        ("merge", "samples"),
        ("unwrap", "circles"),
        ("unwrap", "reflectance"),
        ("unwrap", "card"),
        ("water ocean", "wind"),
        ("water ocean", "frames"),
        ("water ripples", "impacts"),
        ("water murk", "lut_size"),
    } <= found


@pytest.mark.parametrize("words, param", NUMERIC, ids=IDS)
def test_every_number_has_a_shared_type_whose_range_the_help_states(words, param):
    assert isinstance(param.type, SHARED), (
        f"{param.opts[0]} is a {type(param.type).__name__}: use a type of bakeshop.cli._common "
        "(Number, Integer, Size, Numbers, Fields, Exposure, ...), which refuse NaN and the "
        "infinities and carry the range"
    )
    if isinstance(param, click.Option):
        command = cli if not words else dict(commands())[words]
        ctx = click.Context(command)
        _, text = param.get_help_record(ctx)
        assert param.type.describe_range() in " ".join(text.split()), text


def test_no_option_parses_numbers_as_text():
    """An option whose metavar promises numbers (N, WxH, EV|auto, DEG ...) must not be a
    plain string that the command parses later, unchecked."""
    bad = []
    for words, command in [((), cli), *commands()]:
        for param in command.params:
            if not isinstance(param, click.Option) or is_numeric(param):
                continue
            if param.type is not click.STRING or param.metavar is None:
                continue
            tokens = param.metavar.replace("|", " ").replace("[", " ").replace("]", " ").split()
            if any(promises_numbers(t) for t in tokens):
                bad.append(f"{' '.join(words)} {param.opts[0]} ({param.metavar})")
    assert not bad, "options that hold numbers as text: " + ", ".join(bad)


# --- hostile values on every numeric option --------------------------------------------------


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> dict[str, Path]:
    """Small inputs every command can run on in a fraction of a second."""
    folder = tmp_path_factory.mktemp("limits")
    rng = np.random.default_rng(5)
    made = {"dir": folder}
    made["img"] = folder / "probe.hdr"
    write_image(made["img"], rng.lognormal(0, 1, (16, 32, 3)).astype(np.float32))
    flat = np.zeros((16, 16, 3), np.float32)
    flat[..., 2] = 1
    made["n"] = folder / "n.png"
    write_image(made["n"], (flat + 1) / 2)
    made["h"] = folder / "h.png"
    write_image(made["h"], rng.random((16, 16, 1)).astype(np.float32))
    made["mesh"] = folder / "quad.obj"
    made["mesh"].write_text(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
    )
    for k in range(3):  # a bracket of three 8-bit frames (their times given by --times)
        made[f"b{k}"] = folder / f"bracket_{k}.png"
        codes = np.clip(rng.lognormal(-2, 1, (16, 32, 3)) * 4.0**k, 0, 1)
        write_image(made[f"b{k}"], (codes * 255).round().astype(np.uint8))
    made["ball"] = folder / "ball.exr"  # a photo of a mirror ball, centre (32, 32), radius 24
    write_image(made["ball"], synthetic.ball_photo(64, 64, 32.0, 32.0, 24.0, supersample=1))
    return made


#: a cheap run of each command (its numeric options take these unless the test sets them).
BASE = {
    "info": ["{img}"],
    "convert": ["{img}", "{dir}/o.hdr"],
    "resize": ["{img}", "{dir}/o.hdr", "--size", "8"],
    "remap": ["{img}", "{dir}/o.hdr", "--to", "latlong", "--size", "8x4"],
    "irradiance": ["{img}", "{dir}/o.hdr", "--size", "8x4"],
    "sun": ["{img}"],
    "dims": ["{img}", "-o", "{dir}/dims", "--size", "8x4"],
    "prefilter": ["{img}", "{dir}/o.dds", "--size", "8", "--mips", "2", "--samples", "16"],
    "dfg": ["{dir}/o.exr", "--size", "8", "--samples", "16"],
    "bake-probe": [
        "{img}",
        "-o",
        "{dir}/bake",
        "--cube-size",
        "8",
        "--specular-size",
        "8",
        "--mips",
        "2",
    ],
    "fresnel": ["{img}", "{dir}/o.exr", "--size", "8"],
    "tonemap": ["{img}", "{dir}/o.png"],
    "normals combine": ["{n}", "{n}", "{dir}/o.png"],
    "normals transfer": [
        "{mesh}",
        "{n}",
        "{dir}/o.png",
        "--size",
        "8",
        "--projection",
        "triplanar",
    ],
    "normals from-height": ["{h}", "{dir}/o.png"],
    "normals check": ["{n}"],
    "normals convert": ["{n}", "{dir}/o.png", "--from", "gl", "--to", "dx"],
    "float": ["--shape", "box", "--seconds", "0.5", "--resolution", "4"],
    "compress": ["{img}", "{dir}/o.dds", "--format", "bc6h", "--mips", "1"],
    "merge": [
        "{b0}",
        "{b1}",
        "{b2}",
        "-o",
        "{dir}/m.exr",
        "--times",
        "1/100,1/25,1/6",
        "--response",
        "srgb",
        "--sun",
        "off",
        "--samples",
        "16",
    ],
    "unwrap": ["{ball}", "-o", "{dir}/u.exr", "--size", "8", "--circle", "32,32,24"],
    "water ocean": [
        "{dir}/ocean",
        "--size",
        "8",
        "--resolution",
        "32",
        "--frames",
        "8",
        "--alias",
        "drop",
        "--no-preview",
    ],
    "water ripples": ["{dir}/ripples", "--resolution", "64", "--frames", "2", "--no-preview"],
    "water murk": ["{dir}/murk", "--lut-size", "8x4", "--no-preview"],
}


def run_with(words, param, value: str, inputs) -> list[str]:
    """The arguments of a cheap run of ``words`` with ``value`` for ``param``."""
    option = param.opts[0]
    if not words:  # a root option: in front of a command that reads a file
        return [option, value, "info", str(inputs["img"])]
    base = BASE.get(" ".join(words))
    if base is None:  # a command added later: its required arguments, placeholders
        from tests.cli.test_process import argv

        base = argv(words, None, "", inputs["dir"])[len(words) :]
    else:
        base = [a.format(**{k: str(v) for k, v in inputs.items()}) for a in base]
    args = list(base)
    if option in args:
        at = args.index(option)
        del args[at : at + 2]
    return [*words, *args, option, value]


BIG_INTEGER = str(2**64)
#: commands that run until they are interrupted (a local server): their edges are not run.
SERVES = {"view"}
#: always refused: not numbers, or far outside any range.
REFUSED = ["nan", "inf", "-inf", "1e308", "-1e308", BIG_INTEGER, "1e300x1e300"]
#: maybe inside a range: accepted (and then run in time) or refused in one line.
EDGES = ["0", "-1", "1e-300"]


def run(args, capfd) -> tuple[int, str, float]:
    started = time.perf_counter()
    with no_hang(RUN_SECONDS):
        status = main(["-q", *args])
    elapsed = time.perf_counter() - started
    return status, capfd.readouterr().err, elapsed


@pytest.mark.parametrize("words, param", NUMERIC, ids=IDS)
def test_hostile_numbers_are_refused_in_one_line(words, param, inputs, capfd):
    for value in REFUSED:
        if getattr(param.type, "allow_inf", False) and value in ("inf", "1e308", BIG_INTEGER):
            continue  # no upper bound: infinity means something (deep water)
        args = run_with(words, param, value, inputs)
        status, err, _ = run(args, capfd)
        assert status == 2 and err.count("\n") == 1, (args, err)
        assert err.startswith("bakeshop: error: ") and "Traceback" not in err, (args, err)
        # refused for this value, not for something else in the run
        named = [*param.opts, param.human_readable_name]
        assert any(f"'{name}'" in err for name in named), (args, err)


#: the numeric options of the commands that run to an end (a server serves until interrupted)
RUNS = [(w, p) for w, p in NUMERIC if not (w and w[0] in SERVES)]


@pytest.mark.slow
@pytest.mark.parametrize(
    "words, param", RUNS, ids=[f"{' '.join(w) or 'bakeshop'}:{p.opts[0]}" for w, p in RUNS]
)
def test_edge_numbers_run_or_are_refused_in_one_line(words, param, inputs, capfd):
    for value in EDGES:
        args = run_with(words, param, value, inputs)
        status, err, elapsed = run(args, capfd)
        assert elapsed < RUN_SECONDS, (args, elapsed)
        assert "Traceback" not in err, (args, err)
        if status == 2:
            assert err.count("\n") == 1 and err.startswith("bakeshop: error: "), (args, err)
        else:
            # normals check exits 1 when it flags texels; warnings may follow a success
            assert status in (0, 1), (args, status, err)
            assert all(line.startswith("bakeshop: warning: ") for line in err.splitlines())


def test_the_issue_cases_are_one_line(inputs, capfd):
    """The cases found in issue 12, each now refused when parsed, with the range."""
    img, d = str(inputs["img"]), str(inputs["dir"])
    cases = {
        ("resize", img, f"{d}/o.hdr", "--size", "100000x100000"): "1<=x<=65536",
        ("convert", img, f"{d}/o.hdr", "--exposure", "1e6"): "-64<=x<=64",
        ("convert", img, f"{d}/o.hdr", "--exposure", "1e308"): "-64<=x<=64",
        ("float", "--shape", "box", "--seconds", "1e308"): "0<x<=3600",
        ("float", "--shape", "box", "--solver-hz", "1e308"): "1<=x<=10000",
        ("float", "--shape", "box", "--size", "1e300"): "0.001<=x<=1000",
        ("float", "--shape", "box", "--fps", "1e6"): "1<=x<=1000",
        ("dfg", f"{d}/o.exr", "--samples", "1e6"): "not a valid integer",
        ("resize", img, f"{d}/o.hdr", "--size", "1e300"): "is not a size",
    }
    for args, words in cases.items():
        status, err, _ = run(list(args), capfd)
        assert status == 2 and words in one_line(err), (args, err)


def one_line(err: str) -> str:
    assert err.count("\n") == 1 and err.startswith("bakeshop: error: "), err
    return err


# --- braces in output names -----------------------------------------------------------------


@pytest.mark.parametrize(
    "args, words",
    [
        (["convert", "{img}", "{dir}/o{.hdr"], "an unmatched '{' or '}'"),
        (["convert", "{img}", "{dir}/o}.hdr"], "an unmatched '{' or '}'"),
        (["convert", "{img}", "{dir}/o_{face}.hdr"], "{face} is not a pattern this command"),
        (["convert", "{img}", "{dir}/o{{x}}.hdr"], "a doubled brace"),
        (["remap", "{img}", "{dir}/f_{face}}.hdr", "--to", "faces"], "unmatched"),
        (["remap", "{img}", "{dir}/f_{face}{.hdr", "--to", "faces"], "unmatched"),
        (["remap", "{img}", "{dir}/f_{mip}.hdr", "--to", "faces"], "{mip} is not a pattern"),
        (["remap", "{img}", "{dir}/f_{face:>9}.hdr", "--to", "faces"], "{face:>9} is not"),
        (["prefilter", "{img}", "{dir}/s_{mip}_{face}{.hdr"], "unmatched"),
        (["prefilter", "{img}", "{dir}/s_{level}.hdr"], "{level} is not a pattern"),
        (["fresnel", "{img}", "{dir}/w_{face}}.exr", "--layout", "cube"], "unmatched"),
        (["tonemap", "{img}", "{dir}/o{frame.png"], "unmatched"),
        (["tonemap", "{img}", "{dir}/o{frame:q}.png"], "{frame:q}"),
        (["tonemap", "{img}", "{dir}/o{frame!r}.png"], "{frame!r} is not a pattern"),
        (["irradiance", "{img}", "{dir}/o.hdr", "--sh-json", "{dir}/sh{.json"], "unmatched"),
        (["bake-probe", "{img}", "-o", "{dir}/out{x}"], "{x} is not a pattern"),
        (["dims", "{img}", "-o", "{dir}/out_{face}"], "{face} is not a pattern"),
        (["float", "--matrix", "--out", "{dir}/m{"], "unmatched"),
    ],
)
def test_a_brace_in_an_output_name_is_one_line_naming_it(inputs, tmp_path, capfd, args, words):
    # only the {img} and {dir} placeholders are the test's: the rest is the name under test
    args = [a.replace("{img}", str(inputs["img"])).replace("{dir}", str(tmp_path)) for a in args]
    status, err, _ = run(args, capfd)
    name = next(a for a in args[2:] if "{" in a or "}" in a)
    assert status == 2, err
    assert one_line(err).startswith(f"bakeshop: error: {name}: ") and words in err, err
    assert list(tmp_path.iterdir()) == []
