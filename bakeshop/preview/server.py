"""The browser viewer's local server: the same shaders over WebGL2, the bake's own numbers.

:func:`serve` starts a standard-library HTTP server bound to 127.0.0.1 that answers a fixed set
of routes and nothing else (no file system path is ever built from a request, so ``../`` or an
absolute path is a 404 like any unknown route):

============================ =====================================================================
route                        what
============================ =====================================================================
``/``                        the page (``web/index.html``)
``/viewer.js``               the viewer (``web/viewer.js``, no library)
``/bake.json``               sizes, the chain's levels, sh.json's 9 coefficients, the sun, the
                             balls, each scene's camera, the bake's auto exposure, the golf
                             course's and the water's uniforms, the GLSL ES 3.00 sources of the
                             programs (:func:`bakeshop.preview.glsl.program_sources`, "webgl")
``/data/NAME.f32``           float32 little-endian: a texture's RGBA texels, rows in order
                             (``cube``, ``specular0`` ..., ``sun_dim``, ``shadow_dim``, ``dfg``,
                             ``water_env``, ``water_rain``, ``water_ring``), the water's normal
                             frames as they are (``water_normals``: F, N, N, C) and the golf
                             course's vertices (``golf``: V rows of 15 floats)
============================ =====================================================================

It answers only requests addressed to itself: a ``Host`` other than ``127.0.0.1:PORT``,
``localhost:PORT`` or ``[::1]:PORT`` is 421 Misdirected Request, and an ``Origin`` other than
``http://`` one of those is 403 (a page elsewhere, even one whose name a DNS rebinding points at
127.0.0.1, reads nothing); more than one ``Host`` is 400. A request line that is not
``METHOD /PATH HTTP/1.x`` is 400 (505 for another major version; a target that is not a path,
such as ``http://evil.example/bake.json``, is 400 too), with a status line and no file. At most
``connections`` connections are served at once (each by a thread; one more is answered 503 and
closed), a connection silent for ``timeout`` seconds is closed, and a request whose line and
headers have not all arrived ``headers_timeout`` seconds after its first byte is answered 408
and closed (a client trickling a byte a second holds no slot for long).

The texels are the bake's values as read by :func:`bakeshop.preview.read_bake` (a half-float
file gives the same numbers in float32): nothing is re-filtered, so the page shows exactly the
baked chain, DFG table and DIM pair, as ``bakeshop preview`` does.
"""

from __future__ import annotations

import json
import sys
import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from socket import SHUT_RDWR, socket
from typing import TYPE_CHECKING, Any, NamedTuple, Union

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError
from bakeshop.preview.glsl import program_sources
from bakeshop.preview.scene import balls, default_camera

if TYPE_CHECKING:
    from bakeshop.preview.bake import Bake
    from bakeshop.preview.scene import Golf
    from bakeshop.water.shader import WaterScene

__all__ = ["LOCALHOST", "Viewer", "serve", "viewer_payload"]

#: The only address the viewer binds to.
LOCALHOST = "127.0.0.1"
#: The names the viewer answers to, besides LOCALHOST (the port follows each in ``Host``).
LOOPBACK_NAMES = (LOCALHOST, "localhost", "[::1]")
#: Seconds a connection may stay silent before the server closes it.
IDLE_TIMEOUT = 15.0
#: Seconds from a request's first byte to the end of its headers.
HEADERS_TIMEOUT = 10.0
#: Connections served at once (a browser opens about six per server).
CONNECTIONS = 32
#: The programs the page compiles.
WEB_PROGRAMS = ("balls", "scene", "shadow", "compose")
#: The scenes the page draws.
WEB_SCENES = ("sky", "balls", "golf", "water")


def _rgba_bytes(a: ArrayLike) -> bytes:
    a = np.asarray(a, np.float32)
    out = np.ones(a.shape[:-1] + (4,), "<f4")
    out[..., : min(a.shape[-1], 4)] = a[..., :4]
    return out.tobytes()


def _uniform_json(values: dict) -> dict:
    out: dict[str, list[float] | bool | float] = {}
    for name, value in values.items():
        if isinstance(value, (tuple, list, np.ndarray)):
            out[name] = [float(v) for v in np.asarray(value, np.float64).ravel()]
        else:
            out[name] = value if isinstance(value, bool) else float(value)
    return out


def viewer_payload(
    bake: Bake, *, golf: Golf | None = None, water: WaterScene | None = None
) -> tuple[dict, dict[str, bytes]]:
    """What the page receives: the JSON document and the texel blobs by name.

    Returns
    -------
    manifest : dict
        JSON-ready (see the module's table).
    blobs : dict of str to bytes
        Float32 RGBA texels of each texture (a cube's six faces one after the other).
    """
    from bakeshop.preview.bake import bake_exposure
    from bakeshop.preview.render import (
        DIFFUSE,
        REFLECTIONS,
        SHADOW_SIZE,
        resolve_water,
        shadow_uniforms,
        water_arrays,
        water_uniforms,
    )
    from bakeshop.preview.scene import VERTEX_FLOATS, golf_course

    golf = golf if golf is not None else golf_course()
    water = resolve_water(bake, water)
    arrays = water_arrays(water)

    blobs = {"cube": _rgba_bytes(bake.cube)}
    for m, level in enumerate(bake.specular):
        blobs[f"specular{m}"] = _rgba_bytes(level)
    blobs["sun_dim"] = _rgba_bytes(bake.sun_dim)
    blobs["shadow_dim"] = _rgba_bytes(bake.shadow_dim)
    blobs["dfg"] = _rgba_bytes(np.concatenate([bake.dfg, np.zeros_like(bake.dfg[..., :1])], -1))
    blobs["golf"] = np.ascontiguousarray(golf.vertices, "<f4").tobytes()
    blobs["water_normals"] = np.ascontiguousarray(arrays["normals"], "<f4").tobytes()
    for name in ("env", "rain", "ring"):
        blobs[f"water_{name}"] = _rgba_bytes(arrays[name])
    sun = bake.sun
    manifest = {
        "cube": bake.cube.shape[1],
        "specular": [level.shape[1] for level in bake.specular],
        "sun_dim": list(bake.sun_dim.shape[:2]),
        "shadow_dim": list(bake.shadow_dim.shape[:2]),
        "dfg": list(bake.dfg.shape[:2]),
        "sh": np.asarray(bake.sh, np.float64)[:9].tolist(),
        "sun": None
        if sun is None
        else {
            "direction": [float(v) for v in sun.direction],
            "irradiance": [float(v) for v in sun.irradiance],
            "radius": float(sun.radius),
        },
        "balls": balls(len(bake.specular)),
        "cameras": {scene: default_camera(scene).to_dict() for scene in WEB_SCENES},
        "exposure": float(bake_exposure(bake)),
        "programs": {
            name: dict(zip(("vertex", "fragment"), program_sources(name, "webgl"), strict=True))
            for name in WEB_PROGRAMS
        },
        "golf": {
            "vertices": int(golf.vertices.shape[0]),
            "floats": VERTEX_FLOATS,
            "shadow_size": SHADOW_SIZE,
            "uniforms": _uniform_json(shadow_uniforms(bake, golf)),
        },
        "water": {
            "normals": list(arrays["normals"].shape),
            "env": list(arrays["env"].shape[:2]),
            "rain": list(arrays["rain"].shape[:2]),
            "ring": list(arrays["ring"].shape[:2]),
            "uniforms": _uniform_json(water_uniforms(water)),
        },
        "diffuse": DIFFUSE,
        "reflections": REFLECTIONS,
        "files": dict(bake.files or {}),
    }
    return manifest, blobs


def _web_file(name: str) -> bytes:
    return resources.files("bakeshop.preview").joinpath("web").joinpath(name).read_bytes()


#: what socketserver hands a server: a stream socket, or a datagram and its socket.
_Request = Union[socket, "tuple[bytes, socket]"]


def _socket(request: _Request) -> socket:
    """The socket of a request as socketserver hands it over."""
    return request if isinstance(request, socket) else request[1]


def _port(address: Any) -> int:
    """The port of a bound server address (host, port[, flow, scope])."""
    return int(address[1])


class Viewer(NamedTuple):
    """A running viewer: its server, the thread serving it, and its address."""

    server: ThreadingHTTPServer
    thread: threading.Thread
    url: str

    def close(self) -> None:
        """Stop serving and release the port."""
        self.server.shutdown()
        self.server.server_close()
        self.thread.join()


def _handler(
    routes: dict[str, tuple[str, bytes]], idle: float, headers_timeout: float
) -> type[BaseHTTPRequestHandler]:
    class Handler(BaseHTTPRequestHandler):
        server_version = "bakeshop-view"
        timeout = idle  # of each read and write (StreamRequestHandler)
        # An error answered before the version is known still gets a status line (the standard
        # library's default, HTTP/0.9, sends an error page without one).
        default_request_version = "HTTP/1.0"

        def handle_one_request(self) -> None:
            try:  # the next request's first byte, waited for `idle` seconds
                if not self.rfile.peek(1):  # type: ignore[attr-defined] # a BufferedReader
                    self.close_connection = True
                    return
            except OSError:
                self.close_connection = True
                return
            # taken once: by the deadline (408) or by the end of the headers (the answer)
            self._headers_pending = threading.Lock()
            deadline = threading.Timer(headers_timeout, self._too_slow)
            deadline.start()
            try:
                super().handle_one_request()
            finally:
                deadline.cancel()

        def _too_slow(self) -> None:
            if self._headers_pending.acquire(blocking=False):
                try:
                    self.connection.sendall(
                        b"HTTP/1.0 408 Request Timeout\r\nConnection: close\r\n\r\n"
                    )
                    self.connection.shutdown(SHUT_RDWR)  # the handler's read ends at once
                except OSError:
                    pass

        def parse_request(self) -> bool:
            line = getattr(self, "raw_requestline", b"")  # set by handle_one_request
            if len(line.split()) != 3:  # HTTP/0.9 ("GET /") or no request at all
                self.command, self.requestline, self.close_connection = "", "", True
                self.request_version = self.default_request_version
                ok = False
                if self._headers_pending.acquire(blocking=False):
                    self.send_error(HTTPStatus.BAD_REQUEST, "Bad request line")
            else:
                ok = super().parse_request()
                if not self._headers_pending.acquire(blocking=False):  # answered 408
                    self.close_connection = True
                    ok = False
            return ok

        def do_GET(self) -> None:  # noqa: N802 - the standard library's name
            if not self.path.startswith("/"):  # absolute-form (a proxy's) or asterisk-form
                self.send_error(HTTPStatus.BAD_REQUEST, "Only a path is served")
                return
            if len(self.headers.get_all("Host", ())) > 1:
                self.send_error(HTTPStatus.BAD_REQUEST, "More than one Host")
                return
            port = _port(self.server.server_address)
            hosts = {f"{name}:{port}" for name in LOOPBACK_NAMES}
            if port == 80:
                hosts.update(LOOPBACK_NAMES)
            if self.headers.get("Host", "").lower() not in hosts:
                self.send_error(HTTPStatus.MISDIRECTED_REQUEST)
                return
            origin = self.headers.get("Origin")
            if origin is not None and origin.lower() not in {f"http://{h}" for h in hosts}:
                self.send_error(HTTPStatus.FORBIDDEN, "Cross-origin request")
                return
            found = routes.get(self.path.partition("?")[0])
            if found is None:
                self.send_error(HTTPStatus.NOT_FOUND)
                return
            kind, body = found
            self.send_response(HTTPStatus.OK)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, format: str, *args: object) -> None:  # noqa: A002 - the standard library's name
            pass

    return Handler


class _BoundedServer(ThreadingHTTPServer):
    """A thread per connection, at most ``connections`` at once; one more is answered 503."""

    daemon_threads = True
    request_queue_size = 128  # a burst of connections waits in the kernel, not in SYN retries

    def __init__(self, address: tuple[str, int], handler: type, connections: int) -> None:
        super().__init__(address, handler)
        self._slots = threading.BoundedSemaphore(connections)

    def process_request(self, request: _Request, client_address: Any) -> None:
        if self._slots.acquire(blocking=False):
            super().process_request(request, client_address)
            return
        try:
            _socket(request).sendall(
                b"HTTP/1.0 503 Service Unavailable\r\nConnection: close\r\n\r\n"
            )
        except OSError:
            pass
        self.shutdown_request(request)

    def process_request_thread(self, request: _Request, client_address: Any) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._slots.release()

    def handle_error(self, request: _Request, client_address: Any) -> None:
        """A client gone mid-answer (a reset, a closed tab) is not the viewer's error: no
        traceback on the terminal for it; anything else is reported as before."""
        if not isinstance(sys.exc_info()[1], OSError):
            super().handle_error(request, client_address)


def serve(
    bake: Bake,
    *,
    port: int = 0,
    timeout: float = IDLE_TIMEOUT,
    headers_timeout: float = HEADERS_TIMEOUT,
    connections: int = CONNECTIONS,
) -> Viewer:
    """Serve the viewer of ``bake`` on 127.0.0.1 in a background thread.

    Parameters
    ----------
    bake : Bake
    port : int
        0..65535; 0 picks a free port.
    timeout : float
        Seconds a connection may stay silent (waiting for a request, or not reading a response)
        before it is closed.
    headers_timeout : float
        Seconds from a request's first byte to the end of its headers; a slower request is
        answered 408 Request Timeout and closed.
    connections : int
        Connections served at once; one more is answered 503 Service Unavailable.

    Returns
    -------
    Viewer
        ``url`` is the page's address; :meth:`Viewer.close` stops it.
    """
    if not (isinstance(port, int) and 0 <= port <= 65535):
        raise ArgumentError(f"a port is 0..65535, got {port!r}")
    manifest, blobs = viewer_payload(bake)
    routes = {
        "/": ("text/html; charset=utf-8", _web_file("index.html")),
        "/viewer.js": ("text/javascript; charset=utf-8", _web_file("viewer.js")),
        "/bake.json": ("application/json", json.dumps(manifest).encode()),
    }
    for name, body in blobs.items():
        routes[f"/data/{name}.f32"] = ("application/octet-stream", body)
    try:
        server = _BoundedServer(
            (LOCALHOST, port), _handler(routes, timeout, headers_timeout), connections
        )
    except OSError as e:
        hint = " (port 0 picks a free one)" if port else ""
        reason = f"cannot serve on it: {e.strerror or e}{hint}"
        raise ArgumentError(reason, f"{LOCALHOST}:{port}") from None
    thread = threading.Thread(target=server.serve_forever, name="bakeshop-view", daemon=True)
    thread.start()
    return Viewer(server, thread, f"http://{LOCALHOST}:{server.server_address[1]}/")
