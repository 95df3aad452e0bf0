"""Chunked jobs under an address-space limit far below the image, and on a two-worker
dask.distributed cluster (a worker killed mid-job)."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from bakeshop.huge import Engine, resize, resize_to_file
from bakeshop.image import resize_area
from bakeshop.io.stream import open_image, write_strips

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
    local = Engine("threads", memory="8MB")
    assert np.array_equal(resize(path, (100, 50), engine=on_cluster), resize_area(a, (100, 50)))
    assert np.array_equal(
        remap(path, "latlong", "cube", 64, filter="bilinear", engine=on_cluster),
        remap(path, "latlong", "cube", 64, filter="bilinear", engine=local),
    )
    got = dim_pair(path, "latlong", method="exact", size=(32, 16), engine=on_cluster)
    want = dim_pair(path, "latlong", method="exact", size=(32, 16), engine=local)
    assert np.allclose(got.sun_dim, want.sun_dim, rtol=1e-6, atol=0)


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
