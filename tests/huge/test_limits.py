"""Chunked jobs under an address-space limit far below the image (resize; remap to a latlong and
to cube faces; the DIM pair with its sun), and on a two-worker dask.distributed cluster (a worker
killed mid-job)."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from bakeshop.huge import Engine, resize, resize_to_file
from bakeshop.image import resize_area
from bakeshop.io.stream import open_image, write_strips
from tests.huge.tolerances import (
    AUTO_VS_EXACT,
    PARTIAL_SUMS,
    SUPERSAMPLE_ENERGY,
    SUPERSAMPLE_TILES_RMS,
)

#: the image of the address-space test: 8192 x 8192 grey float32, 256 MB on disk.
SIDE = 8192
#: address space allowed beyond what the interpreter holds once warmed up: 64 MB, a quarter of
#: the image.
HEADROOM = 64 << 20

_CHILD = textwrap.dedent(
    """
    import resource, sys
    import numpy as np
    from bakeshop.huge import Engine, resize
    path, side, headroom = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    engine = Engine("threads", memory="24MB")
    resize(np.ones((64, 64, 1), np.float32), (16, 16), engine=engine)  # compile, start threads
    resize(np.ones((64, 64, 1), np.float32), (17, 15), engine=engine)
    with open("/proc/self/status") as f:
        vm = next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:"))
    resource.setrlimit(resource.RLIMIT_AS, (vm + headroom, vm + headroom))
    try:
        np.empty(side * side, np.float32)
    except MemoryError:
        print("the whole image cannot be allocated")
    out = resize(path, (side // 64, side // 64), engine=engine)
    np.save(sys.stdout.buffer, out)
    """
)


@pytest.mark.slow
def test_resize_under_an_address_space_limit_a_quarter_of_the_image(tmp_path):
    path = tmp_path / "big.pfm"
    ramp = np.arange(SIDE, dtype=np.float32)[:, None, None]  # row y holds y
    write_strips(path, (SIDE, SIDE, 1), (np.broadcast_to(ramp[y : y + 512], (512, SIDE, 1))
                                          for y in range(0, SIDE, 512)))  # fmt: skip
    run = subprocess.run(
        [sys.executable, "-c", _CHILD, str(path), str(SIDE), str(HEADROOM)],
        capture_output=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stderr.decode()[-2000:]
    head, _, data = run.stdout.partition(b"\n")
    assert head == b"the whole image cannot be allocated"
    import io

    out = np.load(io.BytesIO(data))
    # each output row averages 64 input rows y .. y + 63: their mean, y + 31.5
    expected = (np.arange(SIDE // 64) * 64 + 31.5).astype(np.float32)[:, None, None]
    assert np.array_equal(out, np.broadcast_to(expected, out.shape))


#: the panorama of the remap and DIM-pair test: 4096 x 2048 float RGB, 100 MB on disk, under
#: an address space of 24 MB beyond the warmed-up interpreter and an engine bound of 16 MB: the
#: benchmark's 6.4 GB under 1 GB, scaled down.
PANORAMA = (2048, 4096, 3)
PANORAMA_HEADROOM = 24 << 20
PANORAMA_MEMORY = "16MB"
#: the DIMs' size: small, so that the in-memory exact reference takes seconds.
DIM_SIZE = (16, 8)

_PANORAMA_CHILD = textwrap.dedent(
    """
    import resource, sys
    import numpy as np
    from bakeshop.huge import Engine, dim_pair, remap
    path, headroom, memory, target = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    size, elements = (16, 8), 2048 * 4096 * 3
    engine = Engine("threads", memory=memory)
    small = np.ones((128, 256, 3), np.float32)
    small[40:42, 100:103] = 5000.0
    for _ in range(2):  # compile, start the threads, let their memory arenas settle
        remap(small, "latlong", "latlong", (64, 32), filter="area", engine=engine)
        remap(small, "latlong", "cube", 16, filter="area", engine=engine)
        for method in ("exact", "auto"):
            dim_pair(small, "latlong", method=method, size=size, engine=engine)
    with open("/proc/self/status") as f:
        vm = next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:"))
    resource.setrlimit(resource.RLIMIT_AS, (vm + headroom, vm + headroom))
    try:
        np.empty(elements, np.float32)
    except MemoryError:
        print("the whole image cannot be allocated", flush=True)
    out = {
        "latlong": remap(path, "latlong", "latlong", (512, 256), filter="area", engine=engine),
        "cube": remap(path, "latlong", "cube", 256, filter="area", engine=engine),
    }
    for method in ("exact", "auto"):
        pair = dim_pair(path, "latlong", method=method, size=size, engine=engine)
        out[method + "_sun_dim"], out[method + "_shadow_dim"] = pair.sun_dim, pair.shadow_dim
        out[method + "_sun"] = pair.sun.direction
    np.savez(target, **out)
    """
)


def _panorama():
    """A sky of soft bands with a sun of 2 x 3 texels (50 000 times the sky)."""
    h, w, _ = PANORAMA
    y, x = np.ogrid[0:h, 0:w]
    sky = 1 + 0.5 * np.sin(x / 97.0) * np.cos(y / 53.0) + 0.25 * np.cos(x * 2 * np.pi / w)
    a = np.stack([sky, 0.9 * sky, 0.7 * sky], -1).astype(np.float32)
    a[h // 5 : h // 5 + 2, w // 3 : w // 3 + 3] = 50000.0
    return a


def _solid_angle_means(a, factor):
    """The exact solid-angle-weighted means of ``factor`` x ``factor`` blocks of a latlong, in
    float64: each row's solid angle is proportional to cos(theta_top) - cos(theta_bottom)."""
    h, w, c = a.shape
    edges = np.cos(np.pi * np.arange(h + 1) / h)
    omega = edges[:-1] - edges[1:]
    sums = (a * omega[:, None, None]).reshape(h // factor, factor, w // factor, factor, c)
    return sums.sum((1, 3)) / (factor * omega.reshape(-1, factor).sum(1))[:, None, None]


@pytest.fixture(scope="module")
def panorama_under_a_limit(tmp_path_factory):
    """The panorama, and what the chunked remaps and DIM pairs made of it in a process whose
    address space is a quarter of it (see _PANORAMA_CHILD)."""
    folder = tmp_path_factory.mktemp("panorama")
    a = _panorama()
    path, target = folder / "pano.pfm", folder / "out.npz"
    write_strips(path, a.shape, (a[y : y + 256] for y in range(0, a.shape[0], 256)))
    child = [sys.executable, "-c", _PANORAMA_CHILD, str(path), str(PANORAMA_HEADROOM),
             PANORAMA_MEMORY, str(target)]  # fmt: skip
    run = subprocess.run(child, capture_output=True, timeout=900)
    assert run.returncode == 0, run.stderr.decode()[-2000:]
    assert run.stdout.decode().startswith("the whole image cannot be allocated")
    with np.load(target) as out:
        return a, dict(out)


@pytest.mark.slow
def test_remap_to_latlong_under_an_address_space_limit_is_the_exact_reduction(
    panorama_under_a_limit,
):
    a, out = panorama_under_a_limit
    ref = _solid_angle_means(a.astype(np.float64), 8)
    assert out["latlong"].shape == ref.shape
    assert np.abs(out["latlong"] - ref).max() <= PARTIAL_SUMS * np.abs(ref).max()
    assert np.allclose(out["latlong"], ref, rtol=PARTIAL_SUMS, atol=0)


@pytest.mark.slow
def test_remap_to_cube_faces_under_an_address_space_limit_is_the_in_memory_filter(
    panorama_under_a_limit,
):
    from bakeshop import sphere

    a, out = panorama_under_a_limit
    ref = sphere.remap(a, "latlong", "cube", 256, filter="area")  # supersampled in memory too
    got = out["cube"]
    assert got.shape == ref.shape
    assert np.sqrt(np.mean((got - ref) ** 2) / np.mean(ref**2)) < SUPERSAMPLE_TILES_RMS
    energy = [
        (image.astype(np.float64) * sphere.layout(name).solid_angles(image.shape[:-1])[..., None])
        .reshape(-1, 3)
        .sum(0)
        for image, name in ((got, "cube"), (a, "latlong"))
    ]
    assert np.allclose(energy[0], energy[1], rtol=SUPERSAMPLE_ENERGY, atol=0)


@pytest.mark.slow
def test_the_dim_pair_under_an_address_space_limit_is_the_in_memory_one(panorama_under_a_limit):
    from bakeshop import light

    a, out = panorama_under_a_limit
    ref = light.dim_pair(a, "latlong", method="exact", size=DIM_SIZE)
    assert ref.sun is not None
    assert np.array_equal(out["exact_sun"], ref.sun.direction)
    assert np.array_equal(out["auto_sun"], ref.sun.direction)
    for method, tolerance in (("exact", PARTIAL_SUMS), ("auto", AUTO_VS_EXACT)):
        for got, want in ((out[method + "_sun_dim"], ref.sun_dim),
                          (out[method + "_shadow_dim"], ref.shadow_dim)):  # fmt: skip
            assert np.abs(got - want).max() <= tolerance * np.abs(want).max()


@pytest.fixture(scope="module")
def cluster():
    import distributed  # the huge extra, in the test extra

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None, memory_limit="1GB") as c:  # fmt: skip
        with distributed.Client(c) as client:
            yield c, client


def _zarr_image(tmp_path):
    a = (np.random.default_rng(3).random((512, 1024, 3)) ** 3 * 50).astype(np.float32)
    path = tmp_path / "pano.zarr"
    write_strips(path, a.shape, (a[y : y + 128] for y in range(0, 512, 128)))
    return a, path


@pytest.mark.slow
def test_a_two_worker_cluster_gives_the_local_results(tmp_path, cluster):
    from bakeshop.huge import dim_pair, remap

    _, client = cluster
    a, path = _zarr_image(tmp_path)
    on_cluster = Engine(client, memory="8MB")
    local = Engine("synchronous", memory="8MB")  # threads: a chunk each, over 8 MB at 6 cores
    assert np.array_equal(resize(path, (100, 50), engine=on_cluster), resize_area(a, (100, 50)))
    assert np.array_equal(
        remap(path, "latlong", "cube", 64, filter="bilinear", engine=on_cluster),
        remap(path, "latlong", "cube", 64, filter="bilinear", engine=local),
    )
    got = dim_pair(path, "latlong", method="exact", size=(32, 16), engine=on_cluster)
    want = dim_pair(path, "latlong", method="exact", size=(32, 16), engine=local)
    assert np.allclose(got.sun_dim, want.sun_dim, rtol=1e-6, atol=0)


@pytest.mark.slow
def test_a_corrupt_radiance_file_is_refused_with_its_error_before_a_cluster_job(tmp_path, cluster):
    """Opening a .hdr reads its header; the scanlines are walked when the reader is sent to
    the workers, and a truncated file is refused there with its own error (not as dask's
    failure to serialise the graph)."""
    from bakeshop.errors import FormatError
    from bakeshop.io import write_image

    _, client = cluster
    path = tmp_path / "short.hdr"
    write_image(path, np.ones((64, 128, 3), np.float32))
    path.write_bytes(path.read_bytes()[:-200])
    with pytest.raises(FormatError, match="truncated"):
        resize(path, (32, 16), engine=Engine(client, memory="8MB"))


def _die_once(marker):
    """A worker plugin: the first worker to start one of the job's tasks exits on the spot.

    The marker file makes it once for the whole cluster (the nanny restarts the dead worker
    and the scheduler installs the plugin on it again), and the kill happens inside the job, on
    a task it needs, whatever the machine's speed. Defined here so that it travels by value.
    """
    from distributed import WorkerPlugin

    class DieOnce(WorkerPlugin):
        name = "die-once"

        def transition(self, key, start, finish, **kwargs):
            import os

            if finish == "executing" and not os.path.exists(marker):
                open(marker, "w").close()
                os._exit(1)

    return DieOnce()


@pytest.mark.slow
def test_a_worker_killed_mid_job_is_retried_and_the_output_is_complete(tmp_path, cluster):
    _, client = cluster
    a, path = _zarr_image(tmp_path)
    target = tmp_path / "small.zarr"
    engine = Engine(client, memory="5MB")
    marker = tmp_path / "a-worker-died"
    client.register_plugin(_die_once(str(marker)))
    try:
        resize_to_file(path, target, (1000, 500), engine=engine)
    finally:
        client.unregister_worker_plugin("die-once")
    assert marker.exists()  # a worker died on one of the job's tasks
    out = open_image(target).read()
    assert np.array_equal(out, resize_area(a, (1000, 500)))
