"""bakeshop.resources: what the machine lets a process allocate, and every heavy function
refusing, with the number, a call that cannot fit, before it allocates anything.

The limits are real ones (``ulimit -v`` in a child process) where the reading of the machine
is under test, and a small budget put in place of the machine's where each heavy function is:
tracemalloc (which numpy reports to) shows that the refusal came before the allocation.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
import time
import tracemalloc

import numpy as np
import pytest

from bakeshop import light, resources, sphere
from bakeshop.buoyancy import closed_mesh
from bakeshop.buoyancy.bench import float_body
from bakeshop.image import resize_area
from bakeshop.io.compress.pipeline import compress_levels
from bakeshop.resources import Cost, MemoryLimitError, require
from bakeshop.water.ocean import ocean
from bakeshop.water.spectra import Spectrum

#: the budget the heavy functions are given (above resources.SMALL, which is never checked).
BUDGET = 100_000_000
#: most bytes a refused call may allocate on the way to its refusal (its small inputs, and
#: the Python objects of a first call's imports); each call below asks for half a gigabyte or more.
ALLOCATED = 64_000_000
#: the least that each call below asks for.
ASKED = 500_000_000
#: the refusal comes before the work: seconds. The work itself takes minutes; a first call
#: imports modules on the way (a few seconds on a loaded machine).
REFUSED_WITHIN = 60.0


def test_the_address_space_limit_is_read_and_is_real():
    """Under ``ulimit -v`` (the room left above what the process holds), require() refuses a
    cost past the room with the limit's name, and numpy cannot allocate it either."""
    child = textwrap.dedent(
        """
        import resource
        import numpy as np
        from bakeshop import resources
        used = resources._status("VmSize")
        resource.setrlimit(resource.RLIMIT_AS, (used + 300_000_000, resource.RLIM_INFINITY))
        room = resources.memory_limits()["address-space limit (ulimit -v)"]
        print(room)
        try:
            resources.require(resources.Cost(600_000_000, 1, "a test of 600 MB"))
        except resources.MemoryLimitError as e:
            print(e)
        try:
            np.ones(600_000_000, np.uint8)
            print("allocated")
        except MemoryError:
            print("numpy: MemoryError")
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", child], capture_output=True, text=True, timeout=120, check=True
    ).stdout.splitlines()
    room = int(out[0])
    assert 200_000_000 < room <= 300_000_000, room
    assert re.fullmatch(
        r"a test of 600 MB needs about 600 MB of memory; [0-9.]+ MB is left under the "
        r"address-space limit \(ulimit -v\)",
        out[1],
    ), out[1]
    assert out[2] == "numpy: MemoryError"


def test_the_machine_memory_bounds_everything(monkeypatch):
    assert 0 < resources.memory_limits()["memory available"]
    # the least bound wins (fixed numbers: two reads of a shared machine's free memory differ)
    limits = {"memory available": 5 << 30, "cgroup limit": 3 << 30, "address-space": 4 << 30}
    monkeypatch.setattr(resources, "memory_limits", lambda: limits)
    assert resources.available_memory() == 3 << 30


def test_require_returns_what_fits_and_skips_small_costs(monkeypatch):
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": BUDGET})
    fits = Cost(BUDGET, 7, "fits")
    assert require(fits) is fits
    small = Cost(resources.SMALL, 1, "small")
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": 0})
    assert require(small) is small
    with pytest.raises(MemoryLimitError) as e:
        require(Cost(resources.SMALL + 1, 1, "just past"), "in.exr")
    assert e.value.path == "in.exr" and e.value.needed == resources.SMALL + 1
    assert str(e.value) == "in.exr: just past needs about 33.6 MB of memory; 0 B is available"


def test_format_bytes():
    assert resources.format_bytes(15.7e9) == "15.7 GB"
    assert resources.format_bytes(999) == "999 B"
    assert resources.format_bytes(1_500_000) == "1.5 MB"


# --- every heavy function refuses before allocating ----------------------------------------------


def _probe():
    return np.ones((16, 32, 3), np.float32)


class _Ship:
    """A mesh of 20 million triangles, none of them stored."""

    vertices = np.zeros((3, 3))
    faces = np.broadcast_to(np.arange(3), (20_000_000, 3))


def _chain():
    """A BC6H cube chain from 6x4096x4096 (broadcast: nothing stored)."""
    return [np.broadcast_to(np.float32(1), (6, 4096 >> m, 4096 >> m, 4)) for m in range(13)]


HEAVY = {
    "remap": (lambda: sphere.remap(_probe(), "latlong", "cube", 9000), "remapping"),
    "resize_area": (lambda: resize_area(_probe(), (60000, 30000)), "60000x30000"),
    "prefilter_ggx": (
        lambda: light.prefilter_ggx(_probe(), "latlong", size=4096, mips=13, samples=65536),
        "13-level prefiltered chain of 6x4096x4096",
    ),
    "dfg_table": (lambda: light.dfg_table(4096, samples=1 << 20), "DFG table"),
    "irradiance": (lambda: light.irradiance(_probe(), "latlong", size=(30000, 15000)), ""),
    "dim_pair": (lambda: light.dim_pair(_probe(), "latlong", size=(30000, 15000)), ""),
    "bake_probe": (
        lambda: light.bake_probe(_probe(), "latlong", cube_size=4096, specular_size=4096, mips=13),
        "6x4096x4096 cube",
    ),
    "closed_mesh": (
        lambda: closed_mesh(_Ship(), path="ship.obj"),
        "closing a mesh of 20,000,000 triangles",
    ),
    "simulate": (
        lambda: float_body(
            shape="box", density=500, resolution=4, seconds=3600, fps=100, solver_hz=1300
        ),
        "simulating 3600 s",
    ),
    "ocean": (lambda: ocean(Spectrum(), size=64, resolution=4096), "4096^2 wave lattice"),
    "compress_levels": (lambda: compress_levels(_chain(), "bc6h", cube=True), "to bc6h"),
}


@pytest.fixture(scope="module", autouse=True)
def compiled():
    """The kernel every environment check runs, compiled before the calls are timed."""
    sphere.check_environment(_probe(), "latlong")


@pytest.mark.parametrize("name", list(HEAVY))
def test_a_heavy_call_past_the_budget_is_refused_before_it_allocates(name, monkeypatch):
    call, words = HEAVY[name]
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": BUDGET})
    tracemalloc.start()
    started = time.perf_counter()
    try:
        with pytest.raises(MemoryLimitError) as e:
            call()
        elapsed = time.perf_counter() - started
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    message = str(e.value)
    assert re.search(r"needs about [0-9.]+ [KMGT]?B of memory; 100 MB is available$", message)
    assert words in message, message
    assert e.value.needed > ASKED and e.value.available == BUDGET
    assert peak < ALLOCATED, f"{name} allocated {peak / 1e6:.0f} MB before refusing"
    assert elapsed < REFUSED_WITHIN, elapsed


def test_the_mesh_refusal_names_the_file(monkeypatch):
    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": BUDGET})
    with pytest.raises(MemoryLimitError) as e:
        closed_mesh(_Ship(), path="ship.obj")
    assert str(e.value).startswith("ship.obj: closing a mesh of 20,000,000 triangles needs ")


# --- the command line: one line with the number, under a real limit -----------------------------


@pytest.mark.parametrize(
    "args, words",
    [
        (
            [
                "prefilter",
                "{img}",
                "{dir}/s.dds",
                "--size",
                "4096",
                "--mips",
                "13",
                "--samples",
                "16",
            ],  # fmt: skip
            "prefiltered chain",
        ),
        (["remap", "{img}", "{dir}/f_{{face}}.exr", "--to", "faces", "--size", "9000"], "cube"),
        (["compress", "{img}", "{dir}/c.dds", "--cube", "--size", "4096"], "6x4096x4096 cube"),
    ],
)
def test_the_command_line_refuses_in_one_line_under_ulimit(tmp_path, args, words):
    """The command runs under ``ulimit -v`` a few GB above what it holds when it starts, and
    refuses in one line with exit 2 and the number instead of being killed (with a memory
    budget above it, so that the limit binds)."""
    from bakeshop.io import write_image

    img = tmp_path / "probe.hdr"
    write_image(img, _probe())
    argv = [a.format(img=img, dir=tmp_path) for a in args]
    child = textwrap.dedent(
        f"""
        import resource, sys
        from bakeshop import resources
        from bakeshop.cli.main import main
        used = resources._status("VmSize")
        resource.setrlimit(resource.RLIMIT_AS, (used + 3_000_000_000, resource.RLIM_INFINITY))
        sys.exit(main(["-q", *{argv!r}]))
        """
    )
    env = {**os.environ, "BAKESHOP_MEMORY": "1000TB"}
    done = subprocess.run(
        [sys.executable, "-c", child], capture_output=True, text=True, timeout=300, env=env
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("bakeshop: error: ")
    pattern = r"needs about [0-9.]+ GB of memory; [0-9.]+ [MG]B is left under the address-space"
    assert re.search(pattern + r" limit \(ulimit -v\)(; lower --size)?$", done.stderr), done.stderr
    assert words in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["probe.hdr"]


# --- the estimates bound what the calls hold ------------------------------------------------------

#: each case: the code that makes the inputs (and compiles the kernels on a small call), the
#: cost, and the call. Sizes are chosen for peaks of a few hundred MB.
MEASURED = {
    "remap": (
        "from bakeshop import sphere\n"
        "image = np.ones((512, 1024, 3), np.float32)\n"
        "sphere.remap(image[:8, :16], 'latlong', 'cube', 8)",
        "sphere.remap_cost('latlong', (512, 1024), 'cube', 1024)",
        "sphere.remap(image, 'latlong', 'cube', 1024)",
    ),
    "resize_area": (
        "from bakeshop.image import resize_area, resize_area_cost\n"
        "image = np.ones((2048, 4096, 3), np.float32)\n"
        "resize_area(image[:8, :8], (3, 3))",  # the kernel of non-integer factors
        "resize_area_cost(image.shape, (3000, 1500))",
        "resize_area(image, (3000, 1500))",
    ),
    "prefilter_ggx": (
        "from bakeshop import light\n"
        "image = np.ones((256, 512, 3), np.float32)\n"
        "light.prefilter_ggx(image, 'latlong', size=8, mips=2, samples=8)",
        "light.prefilter_cost(image.shape, 'latlong', size=512, mips=10)",
        "light.prefilter_ggx(image, 'latlong', size=512, mips=10, samples=8)",
    ),
    "dfg_table": (
        "from bakeshop import light\nlight.dfg_table(8, samples=16)",
        "light.dfg_table_cost(2048, samples=16)",
        "light.dfg_table(2048, samples=16)",
    ),
    "closed_mesh": (
        "import trimesh\n"
        "from bakeshop.buoyancy import closed_mesh\n"
        "from bakeshop.buoyancy.mass import make_body\n"
        "from bakeshop.buoyancy.shapes import closed_mesh_cost\n"
        "mesh = trimesh.creation.icosphere(subdivisions=7)\n"
        "make_body(closed_mesh(trimesh.creation.icosphere(subdivisions=1)), 500.0).hull_vertices",
        "closed_mesh_cost(len(mesh.faces))",
        "make_body(closed_mesh(mesh), 500.0).hull_vertices",
    ),
    **{
        name: (
            "from bakeshop import light\n"
            "def sunny(h, w):\n"
            "    a = np.random.default_rng(0).lognormal(0, 0.5, (h, w, 3)).astype(np.float32)\n"
            "    a[h // 8 : h // 8 + 4, w // 4 : w // 4 + 4] = 5e4\n"
            "    return a\n"
            "image = sunny(1024, 2048)\n"
            f"light.{call.format(image='sunny(64, 128)')}",
            f"light.{name}_cost(image.shape, 'latlong')",
            f"light.{call.format(image='image')}",
        )
        for name, call in {
            "find_sun": "find_sun({image}, 'latlong')",
            "irradiance": "irradiance({image}, 'latlong')",
            "dim_pair": "dim_pair({image}, 'latlong')",
            "bake_probe": "bake_probe({image}, 'latlong')",
        }.items()
    },
    "compress_levels": (
        "from bakeshop.io.compress.pipeline import box_mips, compress_levels, "
        "compress_levels_cost\n"
        "rng = np.random.default_rng(0)\n"
        "chain = box_mips(rng.lognormal(0, 1, (6, 256, 256, 3)).astype(np.float32), cube=True)\n"
        "compress_levels(box_mips(chain[0][:, :8, :8], cube=True), 'bc6h', cube=True)",
        "compress_levels_cost([c.shape for c in chain], 'bc6h')",
        "compress_levels(chain, 'bc6h', cube=True)",
    ),
}

MEASURE = """
import numpy as np
{setup}
cost = {cost}

def status(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith(field + ":"))

with open("/proc/self/clear_refs", "w") as f:  # the peak (VmHWM) starts again from here
    f.write("5")
base = status("VmRSS")
{call}
print(cost.memory, status("VmHWM") - base)
"""


@pytest.mark.slow
@pytest.mark.parametrize("name", list(MEASURED))
def test_an_estimate_bounds_the_measured_peak(name):
    """The call's peak resident size beyond what the process held before it (VmHWM, reset
    just before the call) is at most the estimate, and the estimate is not wildly above it."""
    setup, cost, call = MEASURED[name]
    child = MEASURE.format(setup=setup, cost=cost, call=call)
    done = subprocess.run(
        [sys.executable, "-c", child], capture_output=True, text=True, timeout=600, check=True
    )
    estimate, peak = map(int, done.stdout.split()[-2:])
    assert peak <= estimate, f"{name}: peak {peak / 1e6:.0f} MB > estimate {estimate / 1e6:.0f} MB"
    assert estimate <= 4 * peak + 64_000_000, (name, estimate, peak)
