"""The viewer's server: 127.0.0.1 only, a fixed set of routes, the bake's own texels."""

import http.client
import json

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
