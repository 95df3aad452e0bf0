"""Shared inputs of the compression tests: the two CC0 probes and ISPC-encoded textures."""

from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[2] / "data"
SUNNY = Path(__file__).resolve().parents[3] / "bakeshop" / "data" / "default_probe.hdr"
DAWN = DATA / "kiara_1_dawn_1k.hdr"
NORMALS = DATA / "scratched_gold_normal_256.png"


@pytest.fixture(scope="session")
def sunny():
    from bakeshop.io import read_image

    return read_image(SUNNY)


@pytest.fixture(scope="session")
def dawn():
    from bakeshop.io import read_image

    return read_image(DAWN)


def hdr_chain(seed: int, size: int, levels: int | None = None, cube: bool = True):
    """A smooth HDR cube (or 2-D) chain with a few bright spots, down to 1x1."""
    rng = np.random.default_rng(seed)
    shape = (6, size, size, 3) if cube else (max(1, size // 2), size, 3)
    y, x = np.meshgrid(np.linspace(0, 1, shape[-3]), np.linspace(0, 1, shape[-2]), indexing="ij")
    base = np.exp(3 * np.sin(6 * x + 3 * y))[..., None] * rng.uniform(0.2, 2, 3)
    level0 = np.broadcast_to(base, shape).copy().astype(np.float32)
    level0 *= rng.uniform(0.5, 1.5, shape).astype(np.float32)
    from bakeshop.io.compress.pipeline import box_mips

    return box_mips(level0, cube=cube, levels=levels)


def ldr_chain(seed: int, size: int, channels: int = 4, cube: bool = True):
    """A chain of values in [0, 1] with edges and gradients (exercises every BC7 mode)."""
    rng = np.random.default_rng(seed)
    shape = (6, size, size, channels) if cube else (size, size, channels)
    y, x = np.meshgrid(np.linspace(0, 1, size), np.linspace(0, 1, size), indexing="ij")
    smooth = 0.5 + 0.5 * np.sin(9 * x * rng.uniform(0.5, 2, (channels, 1, 1)) + 5 * y)
    level0 = np.moveaxis(smooth, 0, -1) * (rng.random(shape) > 0.1)
    level0 = np.clip(level0 + 0.05 * rng.standard_normal(shape), 0, 1).astype(np.float32)
    from bakeshop.io.compress.pipeline import box_mips

    return box_mips(level0, cube=cube)
