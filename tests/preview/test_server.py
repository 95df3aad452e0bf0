"""The viewer's server: 127.0.0.1 only, a fixed set of routes, the bake's own texels."""

import http.client
import json
import select
import socket
import time

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.preview.server import LOCALHOST, serve
from tests.preview.bakes import synthetic_bake


@pytest.fixture(scope="module")
def viewer():
    bake = synthetic_bake()
    v = serve(bake)
    yield bake, v
    v.close()


def get(viewer, path):
    _, v = viewer
    conn = http.client.HTTPConnection(LOCALHOST, v.server.server_address[1], timeout=10)
    conn.request("GET", path)  # sent as given: no client-side normalisation of ../
    response = conn.getresponse()
    body = response.read()
    conn.close()
    return response.status, body


def test_binds_only_to_loopback(viewer):
    _, v = viewer
    assert v.server.server_address[0] == "127.0.0.1"
    assert v.url.startswith("http://127.0.0.1:")


@pytest.mark.parametrize(
    "path",
    ["/../sun.json", "/..%2fsun.json", "/data/../bake.json/x", "//etc/passwd", "/etc/passwd",
     "/data/cube.f32/..", "/web/index.html", "/shaders/common.glsl", "/data/nothing.f32"],
)  # fmt: skip
def test_anything_but_its_routes_is_404(viewer, path):
    status, _ = get(viewer, path)
    assert status == 404


def test_the_page_gets_the_bakes_own_texels(viewer):
    bake, _ = viewer
    status, page = get(viewer, "/")
    assert status == 200 and b"viewer.js" in page
    status, body = get(viewer, "/bake.json")
    manifest = json.loads(body)
    assert manifest["specular"] == [level.shape[1] for level in bake.specular]
    assert "#version 300 es" in manifest["programs"]["balls"]["fragment"]
    for m, level in enumerate(bake.specular):
        status, body = get(viewer, f"/data/specular{m}.f32")
        texels = np.frombuffer(body, "<f4").reshape(level.shape[:-1] + (4,))
        np.testing.assert_array_equal(texels[..., :3], level)
    status, body = get(viewer, "/data/dfg.f32")
    texels = np.frombuffer(body, "<f4").reshape(bake.dfg.shape[:-1] + (4,))
    np.testing.assert_array_equal(texels[..., :2], bake.dfg)


def test_a_bad_port_is_refused():
    with pytest.raises(ArgumentError, match="0..65535"):
        serve(synthetic_bake(), port=70000)


def raw(port, request, *, timeout=10):
    """What the server answers to ``request`` sent as bytes, until it closes the connection."""
    with socket.create_connection((LOCALHOST, port), timeout=timeout) as s:
        s.sendall(request)
        answer = b""
        while chunk := s.recv(1 << 16):
            answer += chunk
    return answer


@pytest.mark.parametrize(
    "host", ["evil.example:{port}", "127.0.0.1:1", "localhost", "127.0.0.1:{port}.evil.example", ""]
)
def test_a_request_for_another_host_is_misdirected(viewer, host):
    port = viewer[1].server.server_address[1]
    header = f"Host: {host.format(port=port)}\r\n" if host else ""
    answer = raw(port, f"GET /bake.json HTTP/1.1\r\n{header}\r\n".encode())
    assert answer.startswith(b"HTTP/1.0 421 ") and b'"specular"' not in answer


@pytest.mark.parametrize("name", ["127.0.0.1", "localhost", "LOCALHOST", "[::1]"])
def test_each_loopback_name_is_served(viewer, name):
    port = viewer[1].server.server_address[1]
    origin = f"Origin: http://{name}:{port}\r\n"
    answer = raw(port, f"GET /bake.json HTTP/1.0\r\nHost: {name}:{port}\r\n{origin}\r\n".encode())
    assert answer.startswith(b"HTTP/1.0 200 ") and b'"specular"' in answer


@pytest.mark.parametrize("origin", ["http://evil.example", "null", "https://127.0.0.1:{port}"])
def test_a_cross_origin_request_is_forbidden(viewer, origin):
    port = viewer[1].server.server_address[1]
    request = f"GET /data/cube.f32 HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: {origin}\r\n\r\n"
    answer = raw(port, request.format(port=port).encode())
    assert answer.startswith(b"HTTP/1.0 403 ") and len(answer) < 2000


@pytest.mark.parametrize(
    ("line", "status"),
    [(b"GET /bake.json", b"400"), (b"GET", b"400"), (b"", b"400"), (b"GET / HTTP/x", b"400"),
     (b"GET /bake.json HTTP/9.9", b"505"), (b"GET /bake.json HTTP/2.0", b"505"),
     (b"GET /bake.json HTTP/1.1 x", b"400")],
)  # fmt: skip
def test_a_malformed_request_line_gets_a_status_and_no_file(viewer, line, status):
    port = viewer[1].server.server_address[1]
    answer = raw(port, line + f"\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
    assert answer.startswith(b"HTTP/1.0 " + status + b" ") and b'"specular"' not in answer


def test_connections_are_bounded_and_idle_ones_closed():
    v = serve(synthetic_bake(), timeout=0.5, connections=3)
    port = v.server.server_address[1]
    try:
        idle = [socket.create_connection((LOCALHOST, port), timeout=10) for _ in range(3)]
        time.sleep(0.1)
        assert raw(port, b"").startswith(b"HTTP/1.0 503 ")
        start = time.monotonic()
        assert all(s.recv(1) == b"" for s in idle)  # closed by the server, not by us
        assert time.monotonic() - start < 5
        for s in idle:
            s.close()
        time.sleep(0.2)  # the threads release their slots just after closing
        request = f"GET / HTTP/1.0\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode()
        assert raw(port, request).startswith(b"HTTP/1.0 200 ")
    finally:
        v.close()


def test_a_request_trickled_past_its_deadline_is_answered_408_and_closed():
    v = serve(synthetic_bake(), timeout=0.5, headers_timeout=1.0, connections=1)
    port = v.server.server_address[1]
    request = f"GET /bake.json HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode()
    try:
        with socket.create_connection((LOCALHOST, port), timeout=10) as s:
            start = time.monotonic()
            answer = b""
            for byte in request[:-1]:  # each byte well inside the idle timeout
                s.sendall(bytes([byte]))
                if select.select([s], [], [], 0.1)[0]:  # answered
                    break
            while chunk := s.recv(1 << 16):
                answer += chunk
            assert answer.startswith(b"HTTP/1.0 408 ") and b'"specular"' not in answer
            assert time.monotonic() - start < 3
        time.sleep(0.2)  # the thread releases its slot just after closing
        assert raw(port, request).startswith(b"HTTP/1.0 200 ")  # the slot is free again
    finally:
        v.close()


@pytest.mark.parametrize(
    ("target", "headers", "status"),
    [("/bake.json", "Host: {host}\r\nHost: {host}\r\n", b"400"),
     ("/bake.json", "Host: {host}\r\nHost: evil.example\r\n", b"400"),
     ("http://evil.example/bake.json", "Host: {host}\r\n", b"400"),
     ("http://{host}/bake.json", "Host: {host}\r\n", b"400"),
     ("*", "Host: {host}\r\n", b"400")],
)  # fmt: skip
def test_only_one_host_and_only_a_path_are_served(viewer, target, headers, status):
    port = viewer[1].server.server_address[1]
    host = f"127.0.0.1:{port}"
    request = f"GET {target} HTTP/1.1\r\n{headers}\r\n".format(host=host)
    answer = raw(port, request.encode())
    assert answer.startswith(b"HTTP/1.0 " + status + b" ") and b'"specular"' not in answer
