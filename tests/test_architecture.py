"""The plan of the house, checked on the code (ast only, no third-party tool): no import
circles, no reaching into another package's private modules, nothing below the command line
imports it, and only ``bakeshop.io`` and the command line write files."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "bakeshop"

#: packages allowed to write files: every byte goes through io; the command line writes what
#: its commands make (through io); a bake writes its outputs and its store.
WRITERS = ("bakeshop.io", "bakeshop.cli", "bakeshop.bake")

#: calls that write files.
WRITE_CALLS = {"atomic_path", "write_text", "write_bytes", "savefig", "tofile", "save", "savez"}


def modules() -> dict[str, ast.Module]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = ast.parse(path.read_text(), str(path))
    return out


MODULES = modules()


def imports(name: str, tree: ast.Module) -> list[tuple[str, int]]:
    """Every bakeshop module ``name`` imports, anywhere in it (functions too), with the line."""
    found = []
    package = (
        name
        if (PACKAGE.parent / Path(*name.split("."), "__init__.py")).exists()
        else (name.rpartition(".")[0])
    )
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names if a.name.startswith("bakeshop")]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1])
                base = f"{base}.{node.module}" if node.module else base
            if not base.startswith("bakeshop"):
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                found.append((sub if sub in MODULES else base, node.lineno))
    return [(m, line) for m, line in found if m in MODULES]


def test_there_are_modules_to_check():
    assert {"bakeshop.io", "bakeshop.sphere", "bakeshop.light", "bakeshop.cli.main"} <= set(MODULES)


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The circles of a directed graph found by depth-first search (each one once at least)."""
    found: list[list[str]] = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                found.append(stack[stack.index(dep) :] + [dep])
            elif dep not in state:
                visit(dep)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    return found


def test_no_import_circles():
    """Packages import each other one way only (a module may import its own package's
    ``__init__``, which re-exports it, so edges into a module's own package are left out)."""
    graph = {
        name: {
            dep for dep, _ in imports(name, tree) if not (name == dep or name.startswith(dep + "."))
        }
        for name, tree in MODULES.items()
    }
    found = cycles(graph)
    assert not found, "import circles:\n" + "\n".join(" -> ".join(c) for c in found)


def test_the_circle_finder_finds_circles():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set()}
    assert cycles(graph) == [["a", "b", "c", "a"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_private_module_of_another_package_is_imported():
    bad = []
    for name, tree in MODULES.items():
        for dep, line in imports(name, tree):
            parts = dep.split(".")
            for i, part in enumerate(parts[1:], 1):
                if part.startswith("_") and not part.startswith("__"):
                    owner = ".".join(parts[:i])
                    if not (name == owner or name.startswith(owner + ".")):
                        bad.append(f"{name}:{line} imports {dep}")
                    break
    assert not bad, "\n".join(bad)


def test_the_library_never_imports_the_command_line():
    bad = [
        f"{name}:{line} imports {dep}"
        for name, tree in MODULES.items()
        if not name.startswith("bakeshop.cli")
        for dep, line in imports(name, tree)
        if dep.startswith("bakeshop.cli")
    ]
    assert not bad, "\n".join(bad)


def _writes(tree: ast.Module) -> list[int]:
    lines = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
        if name in WRITE_CALLS:
            lines.append(node.lineno)
        elif name == "open":
            mode = node.args[1] if len(node.args) > 1 else None
            mode = mode or next((k.value for k in node.keywords if k.arg == "mode"), None)
            if isinstance(mode, ast.Constant) and set(str(mode.value)) & set("wax+"):
                lines.append(node.lineno)
    return lines


def test_only_io_and_the_command_line_write_files():
    bad = [
        f"{name}:{line}"
        for name, tree in MODULES.items()
        if not name.startswith(WRITERS)
        for line in _writes(tree)
    ]
    assert not bad, "file writes outside " + ", ".join(WRITERS) + ":\n" + "\n".join(bad)


#: the most lines a module may have (issue 11): past it, split it along what its parts hold.
MAX_LINES = 700


def test_no_module_is_over_the_size_limit():
    sizes = {
        path.relative_to(PACKAGE.parent): len(path.read_text().splitlines())
        for path in PACKAGE.rglob("*.py")
    }
    big = {str(p): n for p, n in sizes.items() if n > MAX_LINES}
    assert not big, f"modules over {MAX_LINES} lines (split them, docs/architecture.md): {big}"


@pytest.mark.parametrize(
    "source",
    [
        "import bakeshop.cli.main\n",
        "open(path, 'wb')\n",
        "with atomic_path(p) as tmp: pass\n",
        "fig.savefig(p)\n",
    ],
)
def test_the_checks_catch_what_they_look_for(source):
    """The detectors themselves, on code that breaks the rules."""
    tree = ast.parse(source)
    if "import" in source:
        assert imports("bakeshop.light.probe", tree) == [("bakeshop.cli.main", 1)]
    else:
        assert _writes(tree) == [1]
