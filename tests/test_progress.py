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


def test_a_log_gets_periodic_lines_and_a_closing_line_but_nothing_from_a_short_step(monkeypatch):
    import time

    monkeypatch.setenv("BAKESHOP_LOG_INTERVAL", "0.5")
    out = io.StringIO()
    progress.enable(Console(file=out, force_terminal=False, width=200))
    try:
        with progress.step("short"):
            pass
        with progress.task("long job", total=4) as t:
            for _ in range(4):
                time.sleep(0.4)
                t.advance()
    finally:
        progress.disable()
    lines = out.getvalue().splitlines()
    assert not any("short" in line for line in lines)
    assert all(line.startswith("bakeshop: long job: ") for line in lines), lines
    assert any("% (" in line and "elapsed" in line for line in lines[:-1]), lines
    assert lines[-1].startswith("bakeshop: long job: done in ")
    assert "\x1b" not in out.getvalue()  # plain text: no bar, no colour codes


def test_the_command_line_prints_progress_lines_into_a_log(monkeypatch, tmp_path, capfd):
    """stderr not a terminal (pytest captures it): lines, not bars, from steps longer than the
    interval; ``-q`` silences them."""
    import numpy as np

    from bakeshop.cli.main import main
    from bakeshop.io import write_image

    probe = tmp_path / "probe.pfm"
    write_image(probe, np.ones((32, 64, 3), np.float32))
    monkeypatch.setenv("BAKESHOP_LOG_INTERVAL", "0.001")
    assert main(["bake-probe", str(probe), "-o", str(tmp_path / "a"), "--format", "pfm"]) == 0
    err = capfd.readouterr().err
    assert "bakeshop: DFG table: done in " in err and "\x1b" not in err, err
    assert main(["-q", "bake-probe", str(probe), "-o", str(tmp_path / "b"), "--format", "pfm"]) == 0
    assert capfd.readouterr().err == ""
