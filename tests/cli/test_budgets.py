"""Issue 28: every job estimates its memory and time from its arguments before it allocates,
and refuses in one line (the number it needs, the budget, the option that lowers it) when it
is over its budget: memory (--memory, else BAKESHOP_MEMORY, else half the memory available)
and time (bakeshop --max-time, an hour by default). The documented cases are refused at once,
with the process's peak memory unchanged."""

from __future__ import annotations

import resource
import time

import click
import numpy as np
import pytest

from bakeshop import progress
from bakeshop.cli._budget import check
from bakeshop.cli.main import main
from bakeshop.io import write_image
from bakeshop.resources import Cost
from tests.cli.test_process import one_error_line

#: seconds a refusal may take: it comes before anything is allocated or computed, but the
#: command's modules load first (seconds on a loaded machine).
REFUSAL_SECONDS = 20.0
#: growth of the process's peak resident size a refusal may cause, bytes.
REFUSAL_BYTES = 200 << 20


@pytest.fixture()
def probe(tmp_path, monkeypatch):
    """A small latlong probe, under a 64 MB memory budget (below what any machine has free)."""
    monkeypatch.setenv("BAKESHOP_MEMORY", "64MB")
    path = tmp_path / "probe.hdr"
    write_image(path, np.random.default_rng(3).lognormal(0, 1, (16, 32, 3)).astype(np.float32))
    return path


def refused(args: list[str], capfd) -> str:
    """The error line of ``args``, checked to come at once, in one line, exit 2, with the
    peak memory unchanged."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    started = time.perf_counter()
    status = main(["-q", *args])
    assert time.perf_counter() - started < REFUSAL_SECONDS
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - peak < REFUSAL_BYTES
    assert status == 2
    return one_error_line(capfd)


@pytest.mark.parametrize(
    "args, words",
    [
        # a 13-level chain of 65536 samples: about 2e12 lookups
        (["--size", "4096", "--mips", "13", "--samples", "65536"], ["(estimated)", "--samples"]),
        # one level: the 6x4096^2 cube and its pyramid, 18 GB
        (["--size", "4096", "--mips", "1"], ["18.1 GB of memory", "64 MB is the budget", "--size"]),
    ],
)
def test_prefilter_at_documented_sizes_is_refused(probe, tmp_path, capfd, args, words):
    err = refused(["prefilter", str(probe), str(tmp_path / "s.dds"), *args], capfd)
    assert err.startswith(f"bakeshop: error: {probe}: ")
    assert all(w in err for w in words), err
    assert not (tmp_path / "s.dds").exists()


def test_remap_to_a_9000_cube_is_refused(probe, tmp_path, capfd):
    target = tmp_path / "c.dds"
    err = refused(["remap", str(probe), str(target), "--to", "cube", "--size", "9000"], capfd)
    assert "GB of memory; 64 MB is the budget (BAKESHOP_MEMORY); lower --size" in err, err
    assert not target.exists()


def test_dfg_of_a_million_samples_is_refused_with_the_time(tmp_path, capfd):
    target = tmp_path / "dfg.exr"
    err = refused(["dfg", str(target), "--size", "4096", "--samples", "1048576"], capfd)
    assert "would take about" in err and "days (estimated), more than the limit of 1 h" in err
    assert "lower --samples or --size, or allow it with bakeshop --max-time " in err
    assert not target.exists()


def test_max_time_allows_a_long_job_and_a_normal_one_runs(tmp_path, capfd):
    # refused under a limit of one second, run with the limit lifted
    args = ["dfg", str(tmp_path / "dfg.exr"), "--size", "64", "--samples", "65536"]
    assert "more than the limit of 1 s" in refused(["--max-time", "1", *args], capfd)
    assert main(["-q", "--max-time", "inf", "dfg", str(tmp_path / "d.exr"), "--size", "8"]) == 0
    assert (tmp_path / "d.exr").exists()


def test_an_ocean_of_4096_frames_at_4096_is_refused(tmp_path, capfd):
    out = tmp_path / "ocean"
    args = ["water", "ocean", str(out), "--resolution", "4096", "--frames", "4096"]
    err = refused([*args, "--no-preview"], capfd)
    assert "4096 ocean frames of 4096x4096 would take about" in err, err
    assert "lower --frames or --resolution" in err
    assert not out.exists()


def test_irradiance_at_sh_order_64_is_refused(probe, tmp_path, capfd):
    """The minimal window's search at order 64 once tried to allocate 136 GiB (its basis at
    1024 * 65^2 directions); it goes by chunks now and needs 7.2 GB, refused under 64 MB."""
    target = tmp_path / "dim.hdr"
    args = ["irradiance", str(probe), str(target), "--method", "sh", "--order", "64"]
    err = refused(args, capfd)
    assert "search at SH order 64 needs about 7.23 GB of memory; 64 MB is the budget" in err
    assert "lower --order" in err
    assert not target.exists()


def test_a_long_estimate_is_said_before_the_job_starts(capfd):
    progress.enable()
    try:
        with click.Context(click.Command("x")):
            check(Cost(0, 1, "a long job", 125.0), None, "--size", "--size")
    finally:
        progress.disable()
    assert capfd.readouterr().err == "bakeshop: a long job: about 2.08 min (estimated)\n"


def test_bake_probe_with_a_4096_chain_is_refused(probe, tmp_path, capfd):
    args = ["bake-probe", str(probe), "-o", str(tmp_path / "baked"), "--specular-size", "4096"]
    err = refused([*args, "--mips", "13"], capfd)
    assert "a 13-level 6x4096x4096 chain) needs about" in err, err
    assert "64 MB is the budget (BAKESHOP_MEMORY); lower --cube-size or --specular-size" in err
