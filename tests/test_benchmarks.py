"""The benchmarks measure their peers: no script holds a peer's timing as a literal, every
script that compares with a peer goes through benchmarks/peers.py, and that helper fails a run
in which a present peer was not measured."""

from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
SCRIPTS = sorted(BENCHMARKS.glob("bench_*.py"))

#: words that name a peer (in a variable, a dict key or a sentence).
PEER_WORDS = ("cmft", "cmgen", "hdrshop", "opencv", "cv2", "oiio", "openimageio", "pyvips",
              "vips", "py360", "pillow", "ispc")  # fmt: skip
#: modules that are peers.
PEER_MODULES = {"cv2", "OpenImageIO", "pyvips", "py360convert", "PIL", "OpenEXR"}
#: a sentence quoting a peer's time: the peer's name, then within a clause a number of seconds.
QUOTED = re.compile(
    r"\b(cmft|cmgen|hdrshop|opencv|openimageio|oiio|pyvips|py360convert|pillow)\b"
    r"[^.;\n]{0,60}?\b\d+(\.\d+)?\s*(s|ms|sec|seconds|min|minutes|h|hours)\b",
    re.IGNORECASE,
)


def peers_module():
    spec = importlib.util.spec_from_file_location("peers", BENCHMARKS / "peers.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def names_a_peer(text: str) -> bool:
    return any(word in text.lower() for word in PEER_WORDS)


def numbers_in(node: ast.AST) -> list[float]:
    return [
        n.value
        for n in ast.walk(node)
        if isinstance(n, ast.Constant)
        and isinstance(n.value, (int, float))
        and not isinstance(n.value, bool)
    ]


def literal_peer_timings(source: str) -> list[str]:
    """Assignments of numbers to a name that names a peer, dict entries keyed by a peer's name
    holding numbers, and sentences quoting a peer's seconds."""
    found = []
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names = [n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)]
            if node.value is not None and any(names_a_peer(n) for n in names):
                if numbers_in(node.value):
                    found.append(f"line {node.lineno}: {', '.join(names)} = a number")
        elif isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values, strict=True):
                is_name = isinstance(key, ast.Constant) and isinstance(key.value, str)
                if is_name and names_a_peer(key.value) and numbers_in(value):
                    found.append(f"line {node.lineno}: {key.value!r}: a number")
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            for m in QUOTED.finditer(node.value):
                found.append(f"line {node.lineno}: quotes {m.group(0)!r}")
    return found


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_no_benchmark_holds_a_literal_peer_timing(script):
    found = literal_peer_timings(script.read_text())
    assert not found, f"{script.name} quotes a peer instead of measuring it:\n" + "\n".join(found)


@pytest.mark.parametrize(
    "source",
    [
        "CMFT_PHONG = {4096: 50.0, 1024: 3.0}\n",
        "HDRSHOP_FULL_S = 229e6\n",
        "PEERS = {'cmgen': 4.75}\n",
        '"""cmft takes ~50 s on a 4096x2048 probe."""\n',
        "x = 1\n'''the cmgen figure, 3.3 s on this machine'''\n",
    ],
)
def test_the_check_catches_quoted_figures(source):
    assert literal_peer_timings(source)


def test_the_check_lets_measurements_and_sizes_through():
    source = (
        "SIZES = {'4k': (4096, 2048)}\n"
        "found = peers.Peers(['cmgen'])\n"
        "print(f'cmgen {r[\"wall\"]:.2f} s')\n"
        '"""cmgen --size=256 --ibl-ld, 6x256 faces, 9 levels."""\n'
    )
    assert literal_peer_timings(source) == []


def code_of(tree: ast.Module) -> str:
    """The script's code without its docstrings and comments (a docstring may say that a peer
    does not apply)."""
    tree = ast.parse(ast.unparse(tree))
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            if isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
                body[0] = ast.Pass()
    return ast.unparse(tree)


def uses_peers(tree: ast.Module) -> tuple[bool, bool]:
    """(constructs ``peers.Peers``, calls ``.finish()``)."""
    calls = [n.func for n in ast.walk(tree) if isinstance(n, ast.Call)]
    constructs = any(isinstance(f, ast.Attribute) and f.attr == "Peers" for f in calls)
    finishes = any(isinstance(f, ast.Attribute) and f.attr == "finish" for f in calls)
    return constructs, finishes


def compares_with_a_peer(tree: ast.Module) -> bool:
    """Whether a benchmark imports a peer's module or runs cmgen or cmft."""
    imported = {
        alias.name.split(".")[0]
        for n in ast.walk(tree)
        if isinstance(n, (ast.Import, ast.ImportFrom))
        for alias in (n.names if isinstance(n, ast.Import) else [ast.alias(n.module or "")])
    }
    return bool(imported & PEER_MODULES or re.search(r"\b(cmgen|cmft)\b", code_of(tree)))


#: the benchmarks that time a peer (the others time bakeshop alone)
PEER_SCRIPTS = [s for s in SCRIPTS if compares_with_a_peer(ast.parse(s.read_text()))]


def test_the_peer_benchmarks_are_found():
    assert len(PEER_SCRIPTS) >= 5 and len(PEER_SCRIPTS) < len(SCRIPTS)


@pytest.mark.parametrize("script", PEER_SCRIPTS, ids=lambda p: p.name)
def test_a_benchmark_that_uses_a_peer_reports_through_the_helper(script):
    assert uses_peers(ast.parse(script.read_text())) == (True, True), (
        f"{script.name} uses a peer: it must say so with peers.Peers([...]) and end with "
        ".finish() (absent peers reported as not measured, present ones measured)"
    )


def test_the_helper_fails_a_run_that_skipped_a_present_peer(monkeypatch, capsys):
    peers = peers_module()
    monkeypatch.setitem(peers.KNOWN, "here", ("module", "json"))
    monkeypatch.setitem(peers.KNOWN, "gone", ("module", "no_such_module_for_bakeshop"))
    monkeypatch.setitem(peers.KNOWN, "binary", ("env", "BAKESHOP_TEST_NO_SUCH_PEER"))
    monkeypatch.delenv("BAKESHOP_TEST_NO_SUCH_PEER", raising=False)
    run = peers.Peers(["here", "gone", "binary"])
    assert run.present("here") and not run.present("gone") and not run.present("binary")
    with pytest.raises(SystemExit) as exit_:
        run.finish()
    assert exit_.value.code == 1
    assert "present but not measured: here" in capsys.readouterr().err
    with pytest.raises(RuntimeError):
        run.measured("gone", "job")  # an absent peer has no figure
    run.measured("here", "job")
    run.finish()  # measured: no exit
    out = capsys.readouterr().out
    assert "here: measured in this run (job)" in out
    assert "gone: not measured (absent: not installed)" in out
    assert "binary: not measured (absent: set BAKESHOP_TEST_NO_SUCH_PEER=/path/to/binary)" in out


def test_alternate_runs_the_contenders_in_turn():
    peers = peers_module()
    order = []

    def contender(name):
        return lambda: (order.append(name), (1.0, 0.5))[1]

    result = peers.alternate({"a": contender("a"), "b": contender("b")}, repeats=3)
    assert order == ["a", "b"] * 3
    assert result["a"]["wall"] == 1.0 and result["b"]["cpu"] == 0.5 and result["a"]["n"] == 3
