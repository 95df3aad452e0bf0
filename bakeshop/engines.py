"""What each engine expects from a probe bake: files, formats, cube orientation, SH layout, and the
roughness each mip level of a prefiltered specular chain must hold.

An :class:`Engine` is plain data plus a few array functions that turn bakeshop's conventions
(DESIGN.md: world +Y up, -Z forward; cube faces in OpenGL order and orientation; real
orthonormal SH of radiance in graphics order) into the engine's:

- :func:`cube_faces` - the six faces the engine's sampler must find, for an engine whose shader
  looks a world direction ``d`` up at ``M d`` in a cube with OpenGL/Direct3D face addressing
  (``M`` a signed permutation: a mirror or an axis swap). The faces are an exact permutation of
  the texels (a symmetry of the cube maps texel centres onto texel centres), so nothing is
  resampled.
- :func:`panorama` - the latlong an engine samples as a panorama (Godot rolls bakeshop's by half
  a turn).
- :func:`mip_roughness` - the perceptual roughness of each level, inverted from the engine's own
  shader mapping from roughness to LOD, so that a chain baked with it is sampled where the
  engine expects it (or None: the engine prefilters the environment itself).
- :func:`sh_export` - the SH coefficients in the layout and scaling the engine reads.
- :func:`check_energy` - what a written level keeps of the source probe: its energy and its
  sun's integral, so that an output made from anything else (the probe with its sun painted
  out) is refused, whatever its compression error against that intermediate.

What each rule rests on (an engine's shader source, its documentation, or only its documented
axis convention) is in :data:`Engine.checked`, and ``docs/engines.md`` repeats it per engine.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, BakeshopError, validate_choice, with_article

__all__ = [
    "ENGINES",
    "Engine",
    "engine",
    "cube_faces",
    "panorama",
    "mip_roughness",
    "sh_export",
    "ENERGY_TOLERANCE",
    "SourceEnergy",
    "energy",
    "check_energy",
]

#: the constant factor of each real SH basis polynomial (graphics order): Y_k = K_k * poly_k,
#: poly = 1, y, z, x, xy, yz, 3z^2 - 1, xz, x^2 - y^2.
SH_POLY_CONSTANTS = np.array(
    [
        0.5 * math.sqrt(1 / math.pi),
        math.sqrt(3 / (4 * math.pi)),
        math.sqrt(3 / (4 * math.pi)),
        math.sqrt(3 / (4 * math.pi)),
        0.5 * math.sqrt(15 / math.pi),
        0.5 * math.sqrt(15 / math.pi),
        0.25 * math.sqrt(5 / math.pi),
        0.5 * math.sqrt(15 / math.pi),
        0.25 * math.sqrt(15 / math.pi),
    ]
)
#: the clamped-cosine convolution per coefficient (Ramamoorthi and Hanrahan 2001):
#: pi, 2 pi / 3 (three times), pi / 4 (five times).
_COSINE = np.array([math.pi] + [2 * math.pi / 3] * 3 + [math.pi / 4] * 5)


@dataclass(frozen=True)
class Engine:
    """One engine's expectations (see the module notes)."""

    #: preset name (``--engine``).
    name: str
    #: the engine's name as people write it.
    title: str
    #: ``"cube"``: the engine takes a cube map; ``"panorama"``: a latlong panorama.
    environment: str
    #: container of compressed textures: "dds", "ktx2" or "ktx".
    container: str
    #: the engine's cube lookup ``M`` (rows: engine direction components from bakeshop's
    #: x, y, z); None for panorama engines.
    lookup: tuple | None
    #: fraction of the width by which bakeshop's latlong is rolled into the engine's panorama.
    panorama_shift: float
    #: the engine's LOD of perceptual roughness r for a chain of ``levels`` levels, or None
    #: when the engine prefilters the environment itself (then bakeshop ships the environment
    #: with plain box-filtered mips and says so).
    lod_of_roughness: Callable[[float, int], float] | None
    #: number of levels the engine's mapping assumes (None: any).
    specular_levels: int | None
    #: SH layout name for :func:`sh_export`, or None (the engine computes its own).
    sh: str | None
    #: block format and green-channel convention of tangent-space normal maps.
    normal_format: str
    normal_convention: str
    #: output file name of each slot.
    files: dict = field(default_factory=dict)
    #: what bakeshop checked for this engine and how (for docs and messages).
    checked: str = ""
    #: cautions printed with the bake.
    warnings: tuple = ()


def _unity_lod(r: float, levels: int) -> float:
    """Unity (built-in, URP, HDRP): lod = r (1.7 - 0.7 r) * UNITY_SPECCUBE_LOD_STEPS (6)."""
    return r * (1.7 - 0.7 * r) * 6


def _filament_lod(r: float, levels: int) -> float:
    """Filament: lod = iblRoughnessOneLevel * r (2 - r), iblRoughnessOneLevel = levels - 1."""
    return (levels - 1) * r * (2 - r)


def _linear_lod(r: float, levels: int) -> float:
    """Bakeshop's own chain (and UE4's split-sum course notes): lod = r * (levels - 1)."""
    return r * (levels - 1)


ENGINES: dict[str, Engine] = {
    e.name: e
    for e in (
        Engine(
            name="generic",
            title="Generic OpenGL / Vulkan renderer",
            environment="cube",
            container="ktx2",
            lookup=((1, 0, 0), (0, 1, 0), (0, 0, 1)),
            panorama_shift=0.0,
            lod_of_roughness=_linear_lod,
            specular_levels=None,
            sh="bakeshop",
            normal_format="bc5",
            normal_convention="gl",
            files={
                "environment": "environment.ktx2",
                "specular": "specular.ktx2",
                "sh": "sh.json",
                "dfg": "dfg.ktx2",
            },  # fmt: skip
            checked="Faces: sampled by Mesa's OpenGL driver in bakeshop's tests (same texels "
            "as bakeshop's decoder, every face and level). SH: bakeshop's own basis.",
        ),
        Engine(
            name="unity",
            title="Unity (built-in, URP, HDRP)",
            environment="cube",
            container="dds",
            lookup=((1, 0, 0), (0, 1, 0), (0, 0, -1)),
            panorama_shift=0.0,
            lod_of_roughness=_unity_lod,
            specular_levels=7,
            sh="unity",
            normal_format="bc5",
            normal_convention="gl",
            files={
                "environment": "environment.dds",
                "specular": "specular.dds",
                "sh": "sh_unity.json",
            },  # fmt: skip
            checked="Roughness to LOD: Unity's PerceptualRoughnessToMipmapLevel (SRP core "
            "ImageBasedLighting.hlsl, UnityImageBasedLighting.cginc), r (1.7 - 0.7 r) * 6, "
            "inverted exactly. SH: the layout of unity_SHAr..unity_SHC that ShadeSH9 "
            "(UnityCG.cginc) evaluates; a test evaluates those seven vectors with ShadeSH9's "
            "formula and gets bakeshop's E/pi. Faces: Unity's world is left-handed (z "
            "forward), Direct3D cube addressing: bakeshop's directx face set, whose meaning "
            "Mesa's driver checks. Not run in Unity itself.",
            warnings=(
                "Unity convolves cube maps it imports from pictures; a DDS is taken as it is, so "
                "use specular.dds itself (not a re-import of the environment) as the reflection.",
            ),
        ),
        Engine(
            name="unreal",
            title="Unreal Engine 4 and 5",
            environment="cube",
            container="dds",
            # Unreal's frame: X forward, Y right, Z up (left-handed) -> (-z, x, y) of ours
            lookup=((0, 0, -1), (1, 0, 0), (0, 1, 0)),
            panorama_shift=0.0,
            lod_of_roughness=None,
            specular_levels=None,
            sh=None,
            normal_format="bc5",
            normal_convention="dx",
            files={"environment": "environment.dds"},
            checked="Faces: derived from Unreal's documented axes (X forward, Y right, Z up) "
            "and Direct3D cube addressing only; Unreal's source is not public, so neither "
            "the importer nor the sky light was checked here.",
            warnings=(
                "Unreal prefilters a sky light's cube map itself: bakeshop ships the "
                "environment (box-filtered mips), not its GGX chain.",
                "Unreal's cube orientation is derived, not checked: compare with a known "
                "landmark before shipping.",
            ),
        ),
        Engine(
            name="godot",
            title="Godot 4",
            environment="panorama",
            container="dds",
            lookup=None,
            panorama_shift=0.5,
            lod_of_roughness=None,
            specular_levels=None,
            sh=None,
            normal_format="bc5",
            normal_convention="gl",
            files={"environment": "panorama.dds"},
            checked="Panorama: Godot's sky shader (servers/rendering/renderer_rd/shaders/"
            "environment/sky.glsl) samples u = atan2(x, -z) / 2 pi (wrapped to [0, 1)), "
            "v = acos(y) / pi, so its panorama is bakeshop's latlong rolled by half a turn; "
            "a test checks the roll against that formula. Godot's Image has "
            "FORMAT_BPTC_RGBFU (BC6H); its DDS import was not run here.",
            warnings=(
                "Godot filters its own radiance map from the sky panorama: no specular chain "
                "or SH is shipped.",
            ),
        ),
        Engine(
            name="three",
            title="three.js",
            environment="cube",
            container="ktx2",
            # three.js samples cube textures at (flipEnvMap * x, y, z), flipEnvMap = -1
            lookup=((-1, 0, 0), (0, 1, 0), (0, 0, 1)),
            panorama_shift=0.0,
            lod_of_roughness=None,
            specular_levels=None,
            sh="three",
            normal_format="bc7",
            normal_convention="gl",
            files={"environment": "environment.ktx2", "sh": "sh_three.json"},
            checked="Faces: three.js samples a CubeTexture (not a render target) at "
            "vec3(flipEnvMap * x, y, z) with flipEnvMap = -1 (envmap shaders, PMREMGenerator); "
            "Mesa's driver checks bakeshop's faces under that lookup in a test. SH: "
            "SphericalHarmonics3 holds radiance coefficients in the same basis and frame as "
            "bakeshop (its getAt polynomials), which shGetIrradianceAt convolves; checked "
            "against those polynomials in a test.",
            warnings=(
                "three.js builds its own PMREM from scene.environment: bakeshop ships the "
                "environment, not its GGX chain. KTX2Loader reads BC6H only in recent "
                "releases (RGB_BPTC_UNSIGNED_Format); older ones need the float KTX2.",
                "three.js's standard material samples normal maps as RGB: normal maps go to "
                "BC7, not BC5.",
            ),
        ),
        Engine(
            name="filament",
            title="Filament",
            environment="cube",
            container="ktx",
            lookup=((1, 0, 0), (0, 1, 0), (0, 0, 1)),
            panorama_shift=0.0,
            lod_of_roughness=_filament_lod,
            specular_levels=None,
            sh="filament",
            normal_format="bc5",
            normal_convention="gl",
            files={"environment": "skybox.ktx", "specular": "ibl.ktx", "sh": "sh_filament.json"},
            checked="Roughness to LOD: Filament's perceptualRoughnessToLod "
            "(shaders/src/surface_light_indirect.fs), iblRoughnessOneLevel * r (2 - r), "
            "inverted exactly with iblRoughnessOneLevel = levels - 1. SH: Filament's "
            "Irradiance_SphericalHarmonics polynomial (iblSH[0..8] times 1, y, z, x, xy, yz, "
            "3z^2 - 1, xz, x^2 - y^2) gives E/pi in a test. Faces: OpenGL's, in Filament's "
            "right-handed +Y-up world; not run in Filament itself.",
        ),
    )
}


def engine(name: str) -> Engine:
    """The :class:`Engine` preset called ``name``."""
    validate_choice(name, tuple(ENGINES), "engine")
    return ENGINES[name]


def _lookup_matrix(e: Engine) -> np.ndarray:
    if e.lookup is None:
        raise ArgumentError(f"{e.title} takes a panorama, not a cube map")
    return np.asarray(e.lookup, np.float64)


def cube_faces(cube: ArrayLike, e: Engine | str) -> np.ndarray:
    """The six faces (OpenGL/Direct3D face order) the engine ``e`` must be given so that its lookup
    ``M d`` finds bakeshop's value for world direction ``d``.

    Parameters
    ----------
    cube : (6, S, S, C) array
        bakeshop's internal cube (OpenGL order and orientation).
    e : Engine or str

    Returns
    -------
    (6, S, S, C) array
        ``faces`` such that an OpenGL cube lookup of ``faces`` at ``M d`` equals the lookup of
        ``cube`` at ``d``: the internal cube of the environment ``u -> env(M^-1 u)``, built by
        permuting texels (exact; ``M`` is a signed permutation).
    """
    from bakeshop.sphere import layout

    if isinstance(e, str):
        e = engine(e)
    m = _lookup_matrix(e)
    cube = np.asarray(cube)
    if cube.ndim != 4 or cube.shape[0] != 6 or cube.shape[1] != cube.shape[2]:
        raise ArgumentError(f"a cube map must be (6, S, S, C); got {cube.shape}")
    if np.array_equal(m, np.eye(3)):
        return cube
    s = cube.shape[1]
    lay = layout("cube")
    directions, _ = lay.directions((6, s, s))
    source = directions.reshape(-1, 3) @ m  # M^-1 u = M^T u for a signed permutation
    coordinates = lay.coordinates(source, (6, s, s))
    face = np.rint(coordinates[:, 0]).astype(np.int64)
    x = np.clip(np.floor(coordinates[:, 1]).astype(np.int64), 0, s - 1)
    y = np.clip(np.floor(coordinates[:, 2]).astype(np.int64), 0, s - 1)
    return cube[face, y, x].reshape(cube.shape)


def panorama(latlong: ArrayLike, e: Engine | str) -> np.ndarray:
    """Bakeshop's latlong ``(H, W, C)`` rolled into the panorama engine ``e`` samples."""
    if isinstance(e, str):
        e = engine(e)
    a = np.asarray(latlong)
    shift = e.panorama_shift * a.shape[1]
    if shift != int(shift):
        raise ArgumentError(
            f"{with_article(a.shape[1])}-texel-wide panorama cannot be rolled by {shift}"
        )
    return np.roll(a, -int(shift), axis=1) if shift else a


def mip_roughness(e: Engine | str, levels: int) -> np.ndarray | None:
    """The perceptual roughness each level of a ``levels``-level GGX chain must hold for the
    engine's shader to sample it at the right LOD (its mapping inverted, by bisection on the
    monotone curve), or None when the engine prefilters the environment itself."""
    if isinstance(e, str):
        e = engine(e)
    lod_of = e.lod_of_roughness
    if lod_of is None:
        return None
    if levels < 1:
        raise ArgumentError(f"a chain has at least one level, got {levels}")
    if levels == 1:
        return np.zeros(1)
    top = lod_of(1.0, levels)
    out = np.empty(levels)
    out[0] = 0.0  # level 0 is the environment itself
    for m in range(1, levels):
        lod = min(float(m), top)
        lo, hi = 0.0, 1.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if lod_of(mid, levels) < lod:
                lo = mid
            else:
                hi = mid
        out[m] = 0.5 * (lo + hi)
    return out


def sh_export(coeffs: ArrayLike, e: Engine | str) -> dict:
    """Order-2 SH radiance coefficients ``(9, 3)`` (bakeshop's basis and frame) in the layout
    the engine reads.

    Layouts:

    - ``bakeshop``: the radiance coefficients as they are (``{"radiance": [[r, g, b] x 9]}``).
    - ``three``: three.js ``SphericalHarmonics3.coefficients`` - the same radiance
      coefficients (same basis polynomials, same right-handed +Y-up frame);
      ``LightProbe.sh.fromArray(flat)`` takes ``flat``.
    - ``unity``: ``SphericalHarmonicsL2`` as Unity stores it for ShadeSH9: ``sh[c, k] =
      K_k * A_k * L_k / pi`` (basis constant, cosine convolution, over pi: E/pi evaluated as a
      plain polynomial), in Unity's left-handed frame (z mirrored: the z-odd coefficients
      1-0, 2-(-1), 2-1 change sign); ``"coefficients"`` is ``[channel][k]`` and ``"flat"``
      the 27 floats channel-major, as ``sh[channel, k]`` indexes them.
    - ``filament``: ``iblSH[k] = K_k * A_k * L_k / pi`` (Filament's pre-scaled bands: E/pi as
      a plain polynomial in Filament's frame, which is bakeshop's).
    """
    if isinstance(e, str):
        e = engine(e)
    c = np.asarray(coeffs, np.float64)
    if c.shape[0] < 9 or c.ndim != 2:
        raise ArgumentError(f"need order-2 SH coefficients (9, C); got shape {c.shape}")
    c = c[:9]
    if e.sh is None:
        raise ArgumentError(f"{e.title} computes its own SH from the environment")
    if e.sh in ("bakeshop", "three"):
        key = "radiance" if e.sh == "bakeshop" else "coefficients"
        return {key: c.tolist(), "basis": "real orthonormal SH of radiance, graphics order"}
    scaled = c * (SH_POLY_CONSTANTS * _COSINE / math.pi)[:, None]
    if e.sh == "filament":
        return {"iblSH": scaled.tolist(), "meaning": "E/pi = sum iblSH[k] * poly_k(n)"}
    unity = scaled.copy()
    unity[[2, 5, 7]] *= -1  # z -> -z: Unity's world is left-handed, z forward
    return {
        "coefficients": unity.T.tolist(),
        "flat": unity.T.ravel().tolist(),
        "meaning": "SphericalHarmonicsL2 sh[channel, k]; ShadeSH9 gives E/pi",
    }


#: The largest relative error of a level's energy (per colour channel) against the source
#: probe's that :func:`check_energy` accepts beyond the block format's own (measured: a GGX
#: chain of a 128x64 sky with a 1e4-bright sun, 6x32 to 6x1, keeps it within 1.1 %).
ENERGY_TOLERANCE = 0.02


@dataclass(frozen=True)
class SourceEnergy:
    """What every output of a probe bake must keep of the source probe (colour channels).

    ``energy`` is the integral of the radiance over the sphere, ``4 pi`` times its mean (radiance
    units times sr); ``sun`` the sun's irradiance at normal incidence (``Sun.irradiance``,
    zero without a sun). A GGX filter is a normalised kernel of the angle between directions, so
    it keeps the energy at every roughness; a missing sun takes ``sun`` away from it.
    """

    energy: np.ndarray
    sun: np.ndarray

    @classmethod
    def of_bake(cls, sh: ArrayLike, sun_irradiance: ArrayLike | None) -> SourceEnergy:
        """From a bake's SH radiance coefficients of the source probe (``4 pi`` times the
        mean is ``2 sqrt(pi)`` times the first) and its sun's irradiance (None: no sun)."""
        first = np.asarray(sh, np.float64)[0]
        energy = 2 * math.sqrt(math.pi) * first[: min(3, first.size)]
        sun = np.zeros_like(energy) if sun_irradiance is None else np.asarray(sun_irradiance)
        return cls(energy, np.asarray(sun, np.float64)[: energy.size])

    def to_dict(self) -> dict:
        """The source figures of a quality sidecar."""
        return {"energy": self.energy.tolist(), "sun_irradiance": self.sun.tolist()}


def energy(level: ArrayLike, *, cube: bool) -> np.ndarray:
    """The integral of the radiance over the sphere of each colour channel of a cube level
    ``(6, S, S, C)`` or a latlong ``(H, W, C)`` (a panorama rolled about the vertical keeps it):
    sum of value times texel solid angle, float64."""
    from bakeshop.sphere import layout

    a = np.asarray(level)
    omega = layout("cube" if cube else "latlong").solid_angles(a.shape[:-1]).ravel()
    colour = a.reshape(-1, a.shape[-1])[:, : min(3, a.shape[-1])]
    return np.einsum("ic,i->c", colour, omega, dtype=np.float64)


def _worst_ratio(a: np.ndarray, b: np.ndarray) -> float:
    """The channel ratio ``a / b`` furthest from 1 (1 where both are 0: a black probe)."""
    tiny = np.finfo(np.float64).tiny
    ratio = (a + tiny) / (b + tiny)
    return float(ratio[np.argmax(np.abs(ratio - 1))])


def check_energy(
    levels: list,
    source: SourceEnergy,
    *,
    cube: bool,
    encoded: list | None = None,
) -> dict:
    """Measure each level's energy against the source probe's, and the sun's integral it holds
    (its energy less the source's energy without the sun).

    ``encoded``: the levels the decoded ``levels`` were compressed from; the format's own error
    (their energies' worst relative difference: BC6H loses a few percent of a sun sharing
    blocks with the sky, more when ``--overflow clamp`` clamps it) is allowed on top of
    :data:`ENERGY_TOLERANCE`. Raises :class:`~bakeshop.errors.BakeshopError` when a level is
    off by more: a level made from anything but the source probe (its sun painted out).

    Returns the sidecar's ``source`` figures: the source's, and per level ``energy``,
    ``energy_ratio`` (worst channel), ``format_error``, ``tolerance`` and ``sun_integral``.
    """
    rows = []
    for m, level in enumerate(levels):
        e = energy(level, cube=cube)
        worst = _worst_ratio(e, source.energy)
        lost = 0.0 if encoded is None else abs(_worst_ratio(e, energy(encoded[m], cube=cube)) - 1)
        bound = ENERGY_TOLERANCE + lost
        sun = e - (source.energy - source.sun)
        rows.append(
            {
                "level": m,
                "energy": e.tolist(),
                "energy_ratio": worst,
                "format_error": lost,
                "tolerance": bound,
                "sun_integral": sun.tolist(),
            }
        )
        if abs(worst - 1) > bound:
            kept = ""
            if np.any(source.sun > 0):
                share = float(np.sum(sun) / np.sum(source.sun))
                kept = f" and {share:.1%} of its sun's integral"
            raise BakeshopError(
                f"level {m} holds {worst:.1%} of the source probe's energy{kept} (within "
                f"{bound:.1%} expected): it was not made from the source probe; nothing written"
            )
    return {**source.to_dict(), "levels": rows}
