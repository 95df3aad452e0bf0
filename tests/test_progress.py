"""Progress reporting: silent and transparent by default, a bar on a console when enabled."""

import io

from rich.console import Console

from bakeshop import progress


def test_track_is_transparent_when_disabled():
    assert list(progress.track(range(5), "counting")) == [0, 1, 2, 3, 4]
    with progress.step("working"):
        pass


def test_track_draws_on_an_enabled_console():
    out = io.StringIO()
    progress.enable(Console(file=out, force_terminal=True, width=80))
    try:
        items = list(progress.track(iter(range(3)), "counting", total=3))
        with progress.step("one long step"):
            pass
    finally:
        progress.disable()
    assert items == [0, 1, 2]
    assert "counting" in out.getvalue()
