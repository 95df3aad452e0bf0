"""Types, checked on the package: mypy passes with the configuration in pyproject.toml, and
that configuration annotates every function and exempts no module.

mypy runs in-process (``mypy.api``), with the repository's ``[tool.mypy]`` settings:
``disallow_untyped_defs`` and ``disallow_incomplete_defs`` for the whole package (public and
private functions and click callbacks alike; the compiled kernels through their ``.pyi``
stubs), ``check_untyped_defs`` and ``strict_equality``. Only third-party modules get overrides
(missing stubs).
"""

import sys
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # the test extra installs tomli on 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]

#: settings an override must not loosen for a bakeshop module.
STRICT = ("disallow_untyped_defs", "disallow_incomplete_defs")


@pytest.mark.slow
def test_mypy_passes_on_the_package(monkeypatch):
    from mypy import api  # in the test extra

    monkeypatch.chdir(ROOT)  # mypy reads [tool.mypy] from ./pyproject.toml
    out, err, status = api.run(["--cache-dir", str(ROOT / ".mypy_cache")])
    assert status == 0, out + err


def test_every_function_is_annotated_and_no_module_is_exempt():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]
    assert all(config.get(key) is True for key in STRICT), config
    for override in config.get("overrides", []):
        modules = override["module"]
        modules = [modules] if isinstance(modules, str) else modules
        ours = [m for m in modules if m == "bakeshop" or m.startswith("bakeshop.")]
        if ours:
            assert override.get("ignore_errors") is not True, ours
            assert all(override.get(key) is not False for key in STRICT), ours
