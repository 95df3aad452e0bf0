"""What the preview shows: the files ``bakeshop bake-probe`` writes, read back as arrays.

A bake folder holds ``env_{face}.*`` (the environment cube), ``sun_dim.*`` and ``shadow_dim.*``
(the DIM pair, latlong E/pi), ``sun.json``, ``sh.json``, ``specular.{dds,ktx,ktx2}`` (the GGX
chain) and ``dfg.{dds,ktx,ktx2}`` (the split-sum table), in whichever float format and
container the bake chose. :func:`read_bake` finds and reads them through :mod:`bakeshop.io`;
:func:`bake_from_arrays` wraps a :class:`bakeshop.light.ProbeBake` computed in memory. Values
are kept exactly as stored (a half-float chain becomes the same numbers in float32): the
preview never re-filters a bake.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, FormatError

if TYPE_CHECKING:
    from bakeshop.light import ProbeBake

__all__ = ["Bake", "Sun", "bake_exposure", "bake_from_arrays", "find_bake_files", "read_bake"]

#: float formats bake-probe writes the faces and DIMs in, in the order they are looked for.
FLOAT_FORMATS = ("hdr", "exr", "pfm")
#: containers of the specular chain and the DFG table.
CHAIN_CONTAINERS = ("dds", "ktx", "ktx2")


class Sun(NamedTuple):
    """The sun of ``sun.json``, as the shaders take it."""

    #: (3,) unit vector towards the sun.
    direction: np.ndarray
    #: (3,) irradiance at normal incidence (E).
    irradiance: np.ndarray
    #: angular radius, radians.
    radius: float


class Bake(NamedTuple):
    """A probe bake as arrays (float32, RGB; a grey bake is repeated into three channels)."""

    #: (6, S, S, 3): the environment cube, OpenGL faces.
    cube: np.ndarray
    #: list of (6, S_m, S_m, 3): the GGX chain, level m at roughness m / (levels - 1).
    specular: list
    #: (H, 2H, 3) latlong DIMs (E/pi): with the sun, and without it.
    sun_dim: np.ndarray
    shadow_dim: np.ndarray
    #: (N, N, 2): the split-sum table (scale, bias on F0); columns n.v, rows roughness.
    dfg: np.ndarray
    #: (9, 3) float64: the DIM's SH coefficients (E/pi), windowed as sh.json exports them.
    sh: np.ndarray
    #: the sun, or None when the probe has none.
    sun: Sun | None
    #: the folder it was read from (None in memory), and each file's name in it.
    folder: Path | None = None
    files: dict | None = None


def _rgb(a: ArrayLike) -> np.ndarray:
    a = np.asarray(a, dtype=np.float32)
    if a.shape[-1] == 1:
        a = np.repeat(a, 3, axis=-1)
    return np.ascontiguousarray(a[..., :3])


def _one(folder: Path, stem: str, extensions: Sequence[str]) -> Path:
    for ext in extensions:
        path = folder / f"{stem}.{ext}"
        if path.is_file():
            return path
    names = ", ".join(f"{stem}.{e}" for e in extensions)
    raise ArgumentError(f"not a bake-probe folder: none of {names} is in it", folder)


def find_bake_files(folder: str | os.PathLike) -> dict[str, Path]:
    """The files of a bake folder by role (``cube`` is the ``{face}`` pattern); a missing one
    is an :class:`ArgumentError` naming what was looked for."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ArgumentError("not a folder (give the folder bake-probe wrote)", folder)
    files = {}
    for ext in FLOAT_FORMATS:
        if (folder / f"env_posx.{ext}").is_file():
            files["cube"] = folder / f"env_{{face}}.{ext}"
            break
    else:
        raise ArgumentError("not a bake-probe folder: no env_posx.hdr/.exr/.pfm in it", folder)
    files["sun_dim"] = _one(folder, "sun_dim", FLOAT_FORMATS)
    files["shadow_dim"] = _one(folder, "shadow_dim", FLOAT_FORMATS)
    files["specular"] = _one(folder, "specular", CHAIN_CONTAINERS)
    files["dfg"] = _one(folder, "dfg", CHAIN_CONTAINERS)
    files["sun"] = _one(folder, "sun", ("json",))
    files["sh"] = _one(folder, "sh", ("json",))
    return files


def _sun_from_document(doc: dict, path: Path | None) -> Sun | None:
    if doc.get("sun", 0) is None:
        return None
    try:
        direction = np.asarray(doc["direction"], dtype=np.float64)
        irradiance = np.asarray(doc["irradiance"], dtype=np.float64)
        radius = math.radians(float(doc["angular_radius_deg"]))
    except (KeyError, TypeError, ValueError) as e:
        raise FormatError(f"not a bakeshop sun.json ({e})", path) from None
    if direction.shape != (3,) or not np.isfinite(direction).all() or not math.isfinite(radius):
        raise FormatError("the sun's direction must be 3 finite numbers", path)
    norm = float(np.linalg.norm(direction))
    if norm == 0:
        raise FormatError("the sun's direction is zero", path)
    irradiance = np.resize(irradiance, 3) if irradiance.size in (1, 3, 4) else irradiance
    if irradiance.shape != (3,) or not np.isfinite(irradiance).all():
        raise FormatError("the sun's irradiance must be 1 or 3 finite numbers", path)
    return Sun(direction / norm, irradiance, radius)


def _sh_from_document(doc: dict, path: Path | None) -> np.ndarray:
    from bakeshop.light import sh

    if "irradiance" in doc:
        c = sh.from_document(doc["irradiance"], path)
    else:
        c = sh.from_document(doc, path)
        if doc.get("kind", "radiance") == "radiance":
            c = sh.irradiance_coefficients(c)
    if c.shape[0] < 9:
        raise FormatError("the preview needs order-2 SH (9 coefficients per channel)", path)
    c = c[:9]
    return np.repeat(c, 3, axis=1) if c.shape[1] == 1 else c[:, :3]


def _cube_levels(mips: Sequence[np.ndarray], path: Path) -> list[np.ndarray]:
    from bakeshop.sphere import faces_to_cube

    levels = [_rgb(faces_to_cube(level, convention="opengl")) for level in mips]
    for m, level in enumerate(levels):
        expected = max(1, levels[0].shape[1] >> m)
        if level.shape[1] != expected:
            raise FormatError(f"level {m} is {level.shape[1]} texels wide, not {expected}", path)
    return levels


def read_bake(folder: str | os.PathLike) -> Bake:
    """Read a ``bakeshop bake-probe`` output folder.

    Returns
    -------
    Bake
        Every array float32 RGB, as stored (nothing is filtered or resampled).
    """
    from bakeshop.io import read_container, read_environment, read_image, read_json

    files = find_bake_files(folder)
    env = read_environment(files["cube"])
    specular, meta = read_container(files["specular"])
    if not meta.get("cube"):
        raise ArgumentError("the specular chain is not a cube map", files["specular"])
    dfg, _ = read_container(files["dfg"])
    table = np.asarray(dfg[0], dtype=np.float32)
    if table.ndim != 3 or table.shape[-1] < 2:
        raise FormatError("the DFG table needs two channels (scale, bias)", files["dfg"])
    return Bake(
        cube=_rgb(env.image),
        specular=_cube_levels(specular, files["specular"]),
        sun_dim=_rgb(read_image(files["sun_dim"])),
        shadow_dim=_rgb(read_image(files["shadow_dim"])),
        dfg=np.ascontiguousarray(table[..., :2]),
        sh=_sh_from_document(read_json(files["sh"]), files["sh"]),
        sun=_sun_from_document(read_json(files["sun"]), files["sun"]),
        folder=Path(folder),
        files={role: path.name for role, path in files.items()},
    )


def bake_from_arrays(baked: ProbeBake) -> Bake:
    """A :class:`Bake` of a :class:`bakeshop.light.ProbeBake` computed in memory (no files)."""
    from bakeshop.light import sun_document

    sun_doc = sun_document(baked.sun)
    return Bake(
        cube=_rgb(baked.cube),
        specular=[_rgb(level) for level in baked.specular],
        sun_dim=_rgb(baked.sun_dim),
        shadow_dim=_rgb(baked.shadow_dim),
        dfg=np.ascontiguousarray(np.asarray(baked.dfg, np.float32)[..., :2]),
        sh=_sh_from_document(
            {"coefficients": baked.sh_irradiance.coefficients, "kind": "irradiance"}, None
        ),
        sun=_sun_from_document(sun_doc, None),
    )


def bake_exposure(bake: Bake) -> float:
    """The exposure "auto" means for a bake: the environment's log-average luminance over the
    sphere mapped to middle grey, as the contact sheet meters it
    (:func:`bakeshop.light.sheet_exposure`), so every view of one bake shares one exposure."""
    from bakeshop.light import sheet_exposure

    return float(sheet_exposure(bake.cube, "cube"))
