"""The preview's GLSL programs, assembled for a host from one set of sources.

Every program is the host's header (its ``#version`` line and precision statements), then the
shared files, then the program's own shader. The files are written in the common subset of
GLSL ES 3.00 (WebGL2) and GLSL 3.30 (desktop OpenGL through moderngl): the two hosts run the
same text below the header.

========== =================================================================================
program    sources
========== =================================================================================
balls      water.vert (the full-screen triangle) | common.glsl + balls.frag
scene      mesh.vert | common.glsl + mesh.frag (the golf course, its two outputs)
shadow     mesh.vert | common.glsl + shadow.frag (depth from the sun)
compose    water.vert | water.frag (its ``main`` renamed) + common.glsl + compose.frag
========== =================================================================================

``water.vert`` and ``water.frag`` are the reference water shader of :mod:`bakeshop.water.shader`,
included as they are on disk (only their ``#version`` line is replaced): the preview's water is
that shader's surface, normals, ripples, reflection lookup and fresnel.
"""

from __future__ import annotations

from importlib import resources
from typing import Literal

from bakeshop.errors import validate_choice

__all__ = ["HOSTS", "PROGRAMS", "program_sources", "source_file"]

Host = Literal["gl", "webgl"]

#: the hosts and the lines each puts before the shared sources.
HOSTS: dict[str, str] = {
    "gl": "#version 330 core\n",
    "webgl": "#version 300 es\n",
}

#: precision statements (GLSL ES needs them in fragment shaders; GLSL 3.30 accepts and ignores
#: them), the same for both hosts.
PRECISION = (
    "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
    "precision highp samplerCube;\nprecision highp sampler2DArray;\n"
)

#: program -> (vertex files, fragment files); "water/" files are bakeshop.water's shaders.
PROGRAMS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "balls": (("water/water.vert",), ("common.glsl", "balls.frag")),
    "scene": (("mesh.vert",), ("common.glsl", "mesh.frag")),
    "shadow": (("mesh.vert",), ("common.glsl", "shadow.frag")),
    "compose": (("water/water.vert",), ("water/water.frag", "common.glsl", "compose.frag")),
}


def source_file(name: str) -> str:
    """The text of one shader file: ``NAME`` in ``bakeshop/preview/shaders`` or ``water/NAME``
    in ``bakeshop/water/shaders``, without its ``#version`` line."""
    if name.startswith("water/"):
        root, name = resources.files("bakeshop.water").joinpath("shaders"), name[6:]
    else:
        root = resources.files("bakeshop.preview").joinpath("shaders")
    text = root.joinpath(name).read_text()
    lines = text.splitlines(keepends=True)
    return "".join(line for line in lines if not line.lstrip().startswith("#version"))


def _join(files: tuple[str, ...]) -> str:
    parts = []
    for name in files:
        text = source_file(name)
        if name == "water/water.frag" and len(files) > 1:
            # its functions and uniforms serve the pass; its own main() is kept, renamed
            text = f"#define main waterReferenceMain\n{text}#undef main\n"
        parts.append(f"// ---- {name}\n{text}")
    return "".join(parts)


def program_sources(program: str, host: Host = "gl") -> tuple[str, str]:
    """``(vertex, fragment)`` GLSL of a preview program for a host ("gl": desktop GLSL 3.30 for
    moderngl; "webgl": GLSL ES 3.00 for WebGL2)."""
    validate_choice(host, tuple(HOSTS), "shader host")
    validate_choice(program, tuple(PROGRAMS), "preview program")
    vertex_files, fragment_files = PROGRAMS[program]
    head = HOSTS[host] + PRECISION
    return head + _join(vertex_files), head + _join(fragment_files)
