"""Texture containers: DDS, KTX and KTX2 files holding mip chains of 2-D textures or cube maps.

They sit beside the image codecs of :data:`bakeshop.io.CODECS` (one ``(H, W, C)`` picture per
file) because they hold more: every mip level of a texture, six faces per level for a cube.
:data:`CONTAINERS` names each module and the extensions it owns; every module exposes
``read_<name>(path) -> (mips, metadata)`` and ``write_<name>(path, mips, *, dtype)``.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

import numpy as np

#: container module -> the file extensions it owns.
CONTAINERS: dict[str, tuple[str, ...]] = {
    "dds": (".dds",),
    "ktx": (".ktx",),
    "ktx2": (".ktx2",),
}

#: largest finite float16; a chain holding a larger value (a sun) is written as float32.
HALF_MAX = 65504.0


def container_for(path: str | os.PathLike) -> str | None:
    """The container module owning ``path``'s extension, or None for any other file."""
    ext = Path(path).suffix.lower()
    for name, extensions in CONTAINERS.items():
        if ext in extensions:
            return name
    return None


def is_container(path: str | os.PathLike) -> bool:
    """True when ``path`` names a .dds, .ktx or .ktx2 file."""
    return container_for(path) is not None


def _module(path: str | os.PathLike) -> tuple[str, ModuleType]:
    name = container_for(path)
    if name is None:
        from bakeshop.errors import UnsupportedError

        known = ", ".join(e for exts in CONTAINERS.values() for e in exts)
        raise UnsupportedError(f"not a texture container; containers are {known}", path)
    return name, importlib.import_module(f"bakeshop.io.{name}")


def read_container(path: str | os.PathLike) -> tuple[list[np.ndarray], dict]:
    """``(mips, metadata)`` of a .dds, .ktx or .ktx2 file: level 0 first, each ``(H, W, C)``
    or, for a cube (``metadata["cube"]``), ``(6, S, S, C)`` float32."""
    name, module = _module(path)
    return getattr(module, f"read_{name}")(path)


def write_container(
    path: str | os.PathLike, mips: Sequence[np.ndarray], *, float32: bool = False
) -> None:
    """Write ``mips`` (level 0 first; ``(H, W, C)`` or ``(6, S, S, C)`` each) to a .dds, .ktx
    or .ktx2 file, atomically: half floats unless ``float32`` or a value would overflow them
    (above :data:`HALF_MAX`, as a sun often is)."""
    name, module = _module(path)
    peak = max(float(np.nanmax(np.abs(level))) for level in mips)
    dtype = "float16" if not float32 and peak <= HALF_MAX else "float32"
    getattr(module, f"write_{name}")(path, mips, dtype=dtype)
