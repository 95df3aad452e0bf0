"""Shared fixtures: the shared third-party data folder and a clean progress state."""

import os
from pathlib import Path

import pytest

# The command line keeps area-filter matrices in the user's cache directory; tests build their
# own (and never write into the home directory) unless a test points it somewhere itself.
os.environ.setdefault("BAKESHOP_CACHE_BYTES", "0")

#: ``shared/`` lies beside the project's checkout, here and in CI.
SHARED_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data``: real third-party probes, EXRs, normal maps and meshes (read-only)."""
    if not SHARED_DATA.is_dir():
        pytest.skip("../shared/data is not present")
    return SHARED_DATA


@pytest.fixture(autouse=True)
def _quiet_progress():
    from bakeshop import progress

    progress.disable()
    yield
    progress.disable()
