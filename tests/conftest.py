"""Shared fixtures: a clean progress state."""

import pytest


@pytest.fixture(autouse=True)
def _quiet_progress():
    from bakeshop import progress

    progress.disable()
    yield
    progress.disable()
