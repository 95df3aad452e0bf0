"""Scheduler addresses: checked before anything connects, and a scheduler that is not there
(nothing listening, or a listener that never answers) refused within the connect timeout."""

import socket
import time

import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.errors import ArgumentError, BakeshopError
from bakeshop.huge import Engine, engine
from bakeshop.huge.scheduler import scheduler_address
from bakeshop.io import write_image

BAD = ["tcp://", "tcp://127.0.0.1", "tls://host", "inproc://nothing", "ucx://host:8786",
       "tcp://[::1", "tcp://host:99999", "tcp://host:0", "tcp://host:x", "tcp://u@host:1",
       "tcp://host:1/path", "127.0.0.1:8786", "thread"]  # fmt: skip


@pytest.mark.parametrize("address", BAD)
def test_a_malformed_address_says_the_expected_form(address):
    with pytest.raises(ArgumentError, match=r"tcp://HOST:PORT or tls://HOST:PORT") as e:
        scheduler_address(address)
    assert e.value.path == address


@pytest.mark.parametrize(
    ("address", "parts"),
    [("tcp://10.0.0.5:8786", ("10.0.0.5", 8786)), ("TLS://Sched.Example:1", ("sched.example", 1)),
     ("tcp://[::1]:8786", ("::1", 8786))],
)  # fmt: skip
def test_a_well_formed_address_gives_host_and_port(address, parts):
    assert scheduler_address(address) == parts


@pytest.mark.parametrize("address", BAD)
def test_the_command_line_refuses_it_in_one_line(tmp_path, capsys, address):
    write_image(tmp_path / "a.hdr", np.ones((8, 16, 3), np.float32))
    args = ["-q", "resize", str(tmp_path / "a.hdr"), str(tmp_path / "b.hdr"), "--size", "8"]
    assert main([*args, "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"bakeshop: error: {address}: ") and err.count("\n") == 1
    assert not (tmp_path / "b.hdr").exists()


def test_nothing_listening_is_refused_at_once():
    with socket.socket() as s:  # a port that was free a moment ago
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    start = time.monotonic()
    with pytest.raises(BakeshopError, match="cannot reach the dask scheduler") as e:
        Engine(f"tcp://127.0.0.1:{port}")
    assert e.value.path == f"tcp://127.0.0.1:{port}" and time.monotonic() - start < 30


def test_a_listener_that_never_answers_is_refused_after_the_timeout(monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr(engine, "CONNECT_TIMEOUT", 1)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        start = time.monotonic()
        with pytest.raises(BakeshopError, match="no answer within 1 s"):
            Engine(f"tcp://127.0.0.1:{s.getsockname()[1]}")
    assert time.monotonic() - start < 30


def test_a_scheduler_at_its_address_is_reached():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  protocol="tcp", dashboard_address=None) as cluster:  # fmt: skip
        with Engine(cluster.scheduler_address, memory="64MB") as eng:
            assert eng.distributed and eng.workers == 1
            assert eng.client.submit(sum, [1, 2]).result(timeout=30) == 3
