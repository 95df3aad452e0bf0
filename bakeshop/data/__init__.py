"""Small embedded defaults: the default light probe (see README.md in this folder)."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

__all__ = ["default_probe", "default_probe_path"]


def default_probe_path() -> Path:
    """The path of the embedded default probe: Poly Haven's "Rooitou Park" (CC0), a 1024x512
    Radiance latlong with a visible sun."""
    return Path(str(files("bakeshop.data") / "default_probe.hdr"))


def default_probe() -> np.ndarray:
    """The embedded default probe as a float32 ``(512, 1024, 3)`` latlong of linear radiance."""
    from bakeshop.io import read_image

    return read_image(default_probe_path())
