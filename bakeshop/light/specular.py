"""Specular prefiltering: GGX and Phong cube map mip chains for glossy reflections.

A real-time renderer shades glossy surfaces from one cube map whose mip levels hold the
environment convolved with ever wider specular lobes; a shader picks the level from the
surface's roughness. Both filters here assume n = v = r (the reflection direction is the lobe's
axis), which is what makes one cube map serve every view:

- **GGX** (Karis 2013, the split-sum approximation). Level ``m`` holds

      P_m(n) = integral L(l) D(h) (n.l) dl / integral D(h) (n.l) dl,   h = normalize(n + l),

  over n.l > 0, with GGX's normal distribution D at alpha = roughness^2 (perceptual roughness,
  as UE4). By default roughness is linear in the level: ``roughness = m / (mips - 1)``, so
  level 0 is the environment itself (a mirror) and the last level has roughness 1; a shader
  reads ``textureLod(env, r, roughness * (mips - 1))``. Pass ``roughness=`` to use another map.
  Multiply by the DFG table (:mod:`bakeshop.light.dfg`) to complete the split sum.
- **Phong** (HDRShop's specular convolution; cmft's radiance filter). Level ``m`` holds

      P_m(r) = integral L(l) (e + 1) / (2 pi) max(0, r.l)^e dl

  with exponent e per level; the lobe integrates to 1, so a uniform environment stays uniform.
  The default exponents follow cmft: ``e = 2^(10 g + 1)`` with glossiness
  ``g = 1 - m / (mips - 1)`` (2048 at level 0 down to 2 at the last).

How a level is computed (accurate to about 0.5% RMS against brute-force convolution over every
source texel on a sunny probe, in a couple of seconds for a 6x256, 9-level chain):

1. The source cube is split into ``bright + rest``: the few brightest texels (above
   :data:`BRIGHT_RATIO` times the mean, at most :data:`MAX_BRIGHT` of them: the sun, lamps) and
   everything else clamped to that threshold. The bright texels are convolved exactly with the
   analytically normalised lobe, so a sun is never undersampled; a lobe narrower than an output
   texel (:data:`RESOLVED_LOBE_TEXELS`) is normalised over the output grid instead, so each
   bright texel deposits exactly its energy rather than being point-sampled.
2. The rest has a bounded contrast. Where it is cheap (the wide lobes of the coarse levels,
   at most :data:`EXACT_BUDGET` texel pairs), it is convolved exactly over a level of its mip
   pyramid whose texels are at most a sixth of the lobe's half-width (and twice as fine as
   the output). Elsewhere (the narrow lobes of the fine levels) it is estimated by filtered
   importance sampling (Colbert and Krivanek 2007): each output texel averages ``samples``
   directions drawn from the lobe (a Hammersley set, the same for every texel up to
   rotation, so the result is deterministic), each read from the rest's box-filtered mip
   pyramid at the level whose texels are as large as the solid angle the sample stands for,
   ``lod = 0.5 log2(Omega_s / Omega_p)`` (Colbert and Krivanek add a bias of 1; see
   :data:`LOD_BIAS`), with ``Omega_s = 1 / (samples pdf)`` and
   ``Omega_p`` the cube texel's solid angle where the sample lands. The pyramid's faces are
   padded with their neighbours' texels, so bilinear lookups are seamless.

Kernels are compiled (C++ with OpenMP, ``src/light/specular.hpp``), parallel over output
texels.

References
----------
B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course Physically Based Shading in
Theory and Practice. https://blog.selfshadow.com/publications/s2013-shading-course/
M. Colbert and J. Krivanek, "GPU-Based Importance Sampling", GPU Gems 3, chapter 20, 2007.
https://developer.nvidia.com/gpugems/gpugems3/part-iii-rendering/chapter-20-gpu-based-importance-sampling
B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction through Rough
Surfaces", EGSR 2007. https://doi.org/10.2312/EGWR/EGSR07/195-206
T. Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
https://jcgt.org/published/0006/01/01/
P. Debevec et al., HDRShop 3 specular convolution; M. Lazarov's cmft (radiance filter).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop import progress
from bakeshop.errors import ArgumentError, with_article
from bakeshop.light import _native
from bakeshop.resources import Cost, require, seconds_of
from bakeshop.sphere import Layout, check_environment, remap, remap_cost, sample, valid_texels
from bakeshop.sphere import layout as get_layout

#: Largest cube face accepted (a 6x4096 RGBA float32 pyramid is already 1.6 GB).
MAX_FACE = 4096
#: Largest number of samples per texel accepted.
MAX_SAMPLES = 1 << 16
#: Largest exact convolution (output texels times source texels) done instead of sampling.
EXACT_BUDGET = 3e8
#: The exact sum reads a pyramid level whose texels are at most 1/6 of the lobe's half-width
#: and which is at least twice as fine as the output.
EXACT_TEXELS_PER_LOBE = 6
EXACT_SOURCE_RATIO = 2
#: Texels brighter than this many times the environment's mean (and at most
#: :data:`MAX_BRIGHT` of them) are convolved exactly rather than sampled.
BRIGHT_RATIO = 2.0
MAX_BRIGHT = 1024
#: Peak bytes per texel of the level-0 cube while the chain is made (the source split into
#: bright and rest, its padded 4-channel pyramid, directions and solid angles, the output
#: chain): measured at 162-167, tests/test_resources.py.
CHAIN_BYTES = 180
#: Lookups per second per core (trilinear importance samples, with the exact sums of the wide
#: lobes): measured at 3.4e6 on a machine loaded 4x over its cores, docs/hostile-input.md.
LOOKUPS_PER_SECOND = 1e7
#: Lookups per call of the sampling kernel: progress (and a signal) are seen between calls.
BLOCK_LOOKUPS = 1 << 26
#: Mip level bias of filtered importance sampling. Colbert and Krivanek add 1 (each sample reads
#: a level twice as wide as its solid angle, hiding the sampling pattern at few samples); with
#: 256 samples the unbiased level is closer to the true convolution (on real probes 2-5x lower
#: RMS and worst-texel error against brute force), so none is added.
LOD_BIAS = 0.0

__all__ = [
    "check_mips",
    "hammersley",
    "ggx_half_vector",
    "mip_roughness",
    "phong_exponents",
    "prefilter_cost",
    "prefilter_ggx",
    "prefilter_phong",
    "source_cube",
]


# --- sample sets ---------------------------------------------------------------------------------


def hammersley(count: int) -> np.ndarray:
    """The Hammersley point set: ``(count, 2)`` float64 in [0, 1)^2, (i / count, radical inverse).

    A low-discrepancy set: integrals of smooth functions converge at about O(log N / N) instead
    of Monte Carlo's O(1 / sqrt(N)), deterministically.
    """
    i = np.arange(count, dtype=np.uint64)
    bits = i.copy()
    bits = (bits << np.uint64(16)) | (bits >> np.uint64(16))
    bits = ((bits & np.uint64(0x55555555)) << np.uint64(1)) | (
        (bits & np.uint64(0xAAAAAAAA)) >> np.uint64(1)
    )
    bits = ((bits & np.uint64(0x33333333)) << np.uint64(2)) | (
        (bits & np.uint64(0xCCCCCCCC)) >> np.uint64(2)
    )
    bits = ((bits & np.uint64(0x0F0F0F0F)) << np.uint64(4)) | (
        (bits & np.uint64(0xF0F0F0F0)) >> np.uint64(4)
    )
    bits = ((bits & np.uint64(0x00FF00FF)) << np.uint64(8)) | (
        (bits & np.uint64(0xFF00FF00)) >> np.uint64(8)
    )
    bits &= np.uint64(0xFFFFFFFF)
    return np.stack([i / count, bits.astype(np.float64) / 2.0**32], axis=-1)


def ggx_half_vector(u: float, v: float, alpha: float) -> tuple[float, float, float]:
    """Half vector h (tangent frame, n = +z) distributed as D(h) (n.h) for GGX's ``alpha``.

    cos^2(theta) = (1 - v) / (1 + (alpha^2 - 1) v), phi = 2 pi u (Walter et al. 2007).
    """
    a2 = alpha * alpha
    cos2 = (1.0 - v) / (1.0 + (a2 - 1.0) * v)
    cos_t = math.sqrt(cos2)
    sin_t = math.sqrt(max(0.0, 1.0 - cos2))
    phi = 2.0 * math.pi * u
    return sin_t * math.cos(phi), sin_t * math.sin(phi), cos_t


def _ggx_samples(roughness: float, count: int) -> np.ndarray:
    """Light directions for GGX with n = v: ``(K, 5)`` rows (lx, ly, lz, weight, log2 Omega_s).

    l = reflect(-n, h) with h drawn from D(h) (n.h); its pdf is D(h) (n.h) / (4 v.h) = D(h) / 4
    because n = v. Samples below the horizon are dropped; the weight is n.l (Karis 2013).
    """
    alpha = max(roughness * roughness, 1e-8)
    a2 = alpha * alpha
    h = np.array([ggx_half_vector(u, v, alpha) for u, v in hammersley(count)]).reshape(-1, 3)
    cos_t = h[:, 2]
    l = 2 * cos_t[:, None] * h
    l[:, 2] -= 1
    d = a2 / (np.pi * (cos_t**2 * (a2 - 1) + 1) ** 2)
    pdf = d / 4
    keep = l[:, 2] > 0
    log_omega = -np.log2(count * pdf)
    return np.column_stack([l, l[:, 2], log_omega])[keep]


def _phong_samples(exponent: float, count: int) -> np.ndarray:
    """Directions distributed as (e + 1) / (2 pi) cos^e about +z: ``(K, 5)`` as above, weight 1."""
    xi = hammersley(count)
    cos_t = xi[:, 1] ** (1 / (exponent + 1))
    sin_t = np.sqrt(np.maximum(0.0, 1 - cos_t**2))
    phi = 2 * np.pi * xi[:, 0]
    l = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
    with np.errstate(divide="ignore"):
        pdf = (exponent + 1) / (2 * np.pi) * cos_t**exponent
        log_omega = -np.log2(count * pdf)
    return np.column_stack([l, np.ones(count), np.minimum(log_omega, 64.0)])


# --- the source pyramid --------------------------------------------------------------------------


@functools.lru_cache(maxsize=16)
def _border_directions(size: int) -> np.ndarray:
    """Directions of the texel centres of faces padded by one texel: ``(6, S+2, S+2, 3)``.

    The padding texels lie on each face's plane extended past its edges, so they look into the
    neighbouring faces; :func:`_pyramid` fills them from there.
    """
    t = np.arange(-1, size + 1) + 0.5
    face, y, x = np.meshgrid(np.arange(6.0), t, t, indexing="ij")
    coords = np.stack([face, x, y], axis=-1)
    return get_layout("cube").directions_at(coords, (6, size, size))


def _pyramid(cube: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Box-filtered mip pyramid of a cube map, each face padded with its neighbours' texels.

    Returns the levels concatenated in one flat float32 array, each level's offset into it and
    its face size (the padded level ``k`` is ``(6, s_k + 2, s_k + 2, 4)``: channels are padded
    to four with zeros, so that the kernel reads fixed-size texels).
    """
    levels, sizes = [], []
    level: np.ndarray = np.zeros(cube.shape[:3] + (4,), np.float32)
    level[..., : cube.shape[-1]] = cube
    while True:
        s = level.shape[1]
        padded = sample(level, "cube", _border_directions(s), filter="nearest")
        padded[:, 1:-1, 1:-1] = level
        levels.append(padded.reshape(-1).astype(np.float32, copy=False))
        sizes.append(s)
        if s == 1:
            break
        if s % 2:
            level = remap(level, "cube", "cube", s // 2, filter="area")
        else:
            level = level.reshape(6, s // 2, 2, s // 2, 2, 4).mean(axis=(2, 4), dtype=np.float32)
    offsets = np.cumsum([0] + [lv.size for lv in levels])[:-1]
    return np.concatenate(levels), offsets.astype(np.int64), np.array(sizes, np.int64)


#: log2(q) for q = 1 + sc^2 + tc^2 in [1, 3] as a quartic (error < 0.0021): the per-sample lod
#: needs it, and the polynomial costs a fraction of a libm log2 call.
_q = np.linspace(1.0, 3.0, 1001)
_LOG2_FIT = np.polyfit(_q, np.log2(_q), 4)
del _q


#: A lobe whose half-width is under this many output texels is too narrow for the output grid
#: to sample (a texel centre can sit between the peak and its neighbours): the bright texels
#: are then normalised over the grid itself, so each deposits exactly its energy. Above it the
#: grid's sum of the lobe is within a fraction of a percent of the analytic integral.
RESOLVED_LOBE_TEXELS = 1.0

#: The exact sums skip directions where the lobe is below this fraction of its peak (GGX's tail
#: beyond it holds less than about 1e-5 of its energy; Phong's far less).
LOBE_CUTOFF = 1e-10


class _Lobe:
    """A filter lobe: GGX at alpha^2 = ``param`` or Phong with exponent ``param``."""

    def __init__(self, ggx: bool, param: float, samples: int):
        self.ggx, self.param = ggx, param
        #: samples asked for per texel (the unit of progress; those below the horizon drop)
        self.nominal = samples
        if ggx:
            self.samples = _ggx_samples(param**0.25, samples)
            # integral of D(h) (n.l) dl = 4 E[max(0, n.l)] over l drawn with pdf D(h) / 4, in
            # the kernel's units (without alpha^2 / pi)
            xi = (np.arange(1 << 16) + 0.5) / (1 << 16)
            cos2 = (1 - xi) / (1 + (param - 1) * xi)
            self.norm = 4 * np.mean(np.maximum(0.0, 2 * cos2 - 1)) * np.pi / param
            t = np.linspace(0.0, np.pi / 2, 4097)
            w = np.cos(t) / (0.5 * (1 + np.cos(t)) * (param - 1) + 1) ** 2
            half = w < 0.5 * w[0]
            self.half_width = float(t[np.argmax(half)]) if half.any() else np.pi / 2
            # w(n.l) = n.l / q^2 grows with n.l: bisect for w = LOBE_CUTOFF * w(1)
            lo, hi, peak = 0.0, 1.0, 1.0 / param**2
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                q = 0.5 * (1 + mid) * (param - 1) + 1
                lo, hi = (mid, hi) if mid / q**2 < LOBE_CUTOFF * peak else (lo, mid)
            self.cos_cut = lo
        else:
            self.samples = _phong_samples(param, samples)
            self.norm = 2 * np.pi / (param + 1)
            self.half_width = math.acos(0.5 ** (1.0 / param))
            self.cos_cut = LOBE_CUTOFF ** (1.0 / param)


class _Source:
    """Level 0 of the chain, split for filtering: ``cube = rest + bright``.

    ``bright`` is the part of the few brightest texels above a threshold (a sun, lamps): at most
    :data:`MAX_BRIGHT` texels, kept as directions and radiance times solid angle and convolved
    exactly. ``rest`` (everything clamped to the threshold) has a bounded contrast, which is
    what filtered importance sampling handles well; it is kept as the padded mip pyramid.
    """

    def __init__(self, cube: np.ndarray):
        cube_layout = get_layout("cube")
        s = cube.shape[1]
        self.cube, self.channels = cube, cube.shape[-1]
        omega = cube_layout.solid_angles((6, s, s))
        peak = cube.max(axis=-1)
        mean = float(np.sum(peak * omega) / (4 * np.pi))
        flat = peak.reshape(-1)
        threshold = BRIGHT_RATIO * mean
        if flat.size > MAX_BRIGHT:
            threshold = max(threshold, float(np.partition(flat, -MAX_BRIGHT - 1)[-MAX_BRIGHT - 1]))
        rest = np.minimum(cube, np.float32(threshold)) if threshold > 0 else cube
        index: np.ndarray | list[int] = (
            np.flatnonzero(flat > threshold)[:MAX_BRIGHT] if threshold > 0 else []
        )
        dirs, _ = cube_layout.directions((6, s, s))
        self.bright_dirs = np.ascontiguousarray(dirs.reshape(-1, 3)[index])
        self.bright_omega = omega.reshape(-1)[index]
        excess = cube.reshape(-1, self.channels)[index] - rest.reshape(-1, self.channels)[index]
        self.bright_values = np.ascontiguousarray(excess, dtype=np.float64)
        self.pyramid = _pyramid(rest)

    def rest_level(self, k: int) -> tuple[int, np.ndarray]:
        """Pyramid level ``k`` of the rest, unpadded: (face size, (6 s^2, C) float64 values)."""
        flat, offsets, sizes = self.pyramid
        sk = int(sizes[k])
        padded = flat[offsets[k] : offsets[k] + 6 * (sk + 2) ** 2 * 4].reshape(6, sk + 2, sk + 2, 4)
        values = padded[:, 1:-1, 1:-1, : self.channels].reshape(-1, self.channels)
        return sk, np.ascontiguousarray(values, dtype=np.float64)


def _convolve(
    source: _Source, size: int, lobe: _Lobe, task: progress.Task | None = None
) -> np.ndarray:
    """One output level: the bright texels exactly, plus the rest by exact convolution where it
    is cheap and by filtered importance sampling elsewhere.

    The exact sum over the rest runs over a pyramid level whose texels are at most a sixth of
    the lobe's half-width (and at least twice as fine as the output); it is used when it costs
    at most :data:`EXACT_BUDGET` texel pairs: the wide lobes of the coarse levels, where importance
    sampling is least accurate.
    """
    cube_layout = get_layout("cube")
    dirs, _ = cube_layout.directions((6, size, size))
    dirs = np.ascontiguousarray(dirs.reshape(-1, 3))
    n, channels = dirs.shape[0], source.channels
    sizes = source.pyramid[2]
    # a face of s texels spans pi/2: texel ~ pi / (2 s) <= half_width / EXACT_TEXELS_PER_LOBE
    need = max(
        EXACT_TEXELS_PER_LOBE * math.pi / (2 * max(lobe.half_width, 1e-6)),
        EXACT_SOURCE_RATIO * size,
    )
    k = next((i for i in range(len(sizes) - 1, -1, -1) if sizes[i] >= need), 0)
    if 36 * size**2 * int(sizes[k]) ** 2 <= EXACT_BUDGET:
        sk, values = source.rest_level(k)
        src_dirs, _ = cube_layout.directions((6, sk, sk))
        acc, total = np.zeros((n, channels)), np.zeros(n)
        _native.lobe(
            dirs,
            np.ascontiguousarray(src_dirs.reshape(-1, 3)),
            cube_layout.solid_angles((6, sk, sk)).reshape(-1),
            values,
            lobe.ggx,
            lobe.param,
            lobe.cos_cut,
            acc,
            total,
        )
        # a texel whose lobe sees only zero-solid-angle texels gets 0 (never 0 / 0)
        out = np.divide(acc, total[:, None], out=np.zeros_like(acc), where=total[:, None] > 0)
        if task is not None:
            task.advance(n * lobe.nominal)
    else:
        rgba = np.empty((n, 4))
        count = len(lobe.samples)
        step = max(1, BLOCK_LOOKUPS // max(1, count))
        for a in range(0, n, step):
            b = min(n, a + step)
            _native.filter(dirs[a:b], lobe.samples, *source.pyramid, LOD_BIAS, _LOG2_FIT, rgba[a:b])
            if task is not None:
                task.advance((b - a) * lobe.nominal)
        out = rgba[:, :channels]
    if len(source.bright_dirs):
        out += _bright_part(source, dirs, size, lobe)
    return out.reshape(6, size, size, channels).astype(np.float32)


def _bright_part(source: _Source, dirs: np.ndarray, size: int, lobe: _Lobe) -> np.ndarray:
    """The bright texels' share of each output texel, ``sum_j L_j Omega_j w(n.l_j) / N_j``.

    ``N_j`` is the lobe's integral: analytic where the output grid resolves the lobe; where it
    does not (a half-width under :data:`RESOLVED_LOBE_TEXELS` texels: a mirror-like level),
    the lobe's sum over the output texels, so texel j deposits exactly its energy
    ``L_j Omega_j`` (a point-sampled narrow lobe would multiply a sun by up to
    ``Omega_j / (pi alpha^2)``, or miss it). A texel whose lobe reaches no output centre goes
    whole to the nearest one.
    """
    count, channels = len(source.bright_dirs), source.channels
    norms = np.full(count, lobe.norm)
    if lobe.half_width < RESOLVED_LOBE_TEXELS * math.pi / (2 * size):
        omega = get_layout("cube").solid_angles((6, size, size)).reshape(-1)
        # the lobe depends on n.l alone: its sum over the output texels around each bright
        # texel is the same kernel with the roles swapped (no values, only the totals)
        nothing = np.zeros((dirs.shape[0], 0))
        _native.lobe(
            source.bright_dirs, dirs, omega, nothing, lobe.ggx, lobe.param, lobe.cos_cut,
            np.zeros((count, 0)), norms,
        )  # fmt: skip
    reached = norms > 0
    values = np.where(
        reached[:, None], source.bright_values / np.where(reached, norms, 1)[:, None], 0
    )
    acc, total = np.zeros((dirs.shape[0], channels)), np.zeros(dirs.shape[0])
    _native.lobe(
        dirs,
        source.bright_dirs,
        source.bright_omega,
        values,
        lobe.ggx,
        lobe.param,
        lobe.cos_cut,
        acc,
        total,
    )
    if not reached.all():
        missed = np.flatnonzero(~reached)
        nearest = np.argmax(source.bright_dirs[missed] @ dirs.T, axis=1)
        energy = source.bright_values[missed] * source.bright_omega[missed, None]
        np.add.at(acc, nearest, energy / omega[nearest, None])
    return acc


# --- public API ----------------------------------------------------------------------------------


def source_cube(image: ArrayLike, layout: str, *, size: int = 256) -> np.ndarray:
    """The environment as a ``(6, size, size, C)`` float32 cube: level 0 of every chain.

    A cube of the requested size is returned unchanged (as float32); anything else is remapped
    with the area filter (an average over each output texel's footprint, so a large probe's sun
    keeps its energy), or bilinear when upsampling. Always with a channel axis (this is the
    chains' working form; :func:`prefilter_ggx` returns 2-D levels for a 2-D input).
    """
    env = check_environment(image, layout)
    if not 1 <= size <= MAX_FACE:
        raise ArgumentError(f"cube face size must be in 1..{MAX_FACE}, got {size}")
    img, lay = env.layout.prepare(env.image).astype(np.float32, copy=False), env.layout.base
    if lay.name == "cube" and img.shape[1] == size:
        return img
    down = valid_texels(lay, img.shape[:-1]) >= 6 * size * size
    return remap(img, lay.name, "cube", size, filter="area" if down else "bilinear")


def prefilter_cost(
    shape: Sequence[int],
    layout: str,
    *,
    size: int = 256,
    mips: int = 9,
    samples: int = 256,
    itemsize: int = 4,
) -> Cost:
    """What :func:`prefilter_ggx` or :func:`prefilter_phong` of an environment of ``shape``
    (with its channel axis) in ``layout`` holds at its peak, and the work it does.

    The larger of: the remap of the input to the level-0 cube (:func:`bakeshop.sphere.
    remap_cost`), and :data:`CHAIN_BYTES` per level-0 texel (6 ``size``^2) for the chain.
    ``work`` counts lookups: ``samples`` per output texel of levels 1 and up (the unit of the
    progress shown; wide lobes are convolved exactly at a bounded cost instead), ``seconds``
    at :data:`LOOKUPS_PER_SECOND`.
    """
    lay = get_layout(layout)
    spatial = tuple(shape[: 3 if lay.cubic else 2])
    channels = int(shape[len(spatial)]) if len(shape) > len(spatial) else 1
    levels = [size >> m for m in range(check_mips(mips, size))]
    work = sum(6 * s * s * samples for s in levels[1:]) + 6 * size * size
    chain = CHAIN_BYTES * 6 * size * size
    what = f"{with_article(mips)}-level prefiltered chain of 6x{size}x{size} faces"
    seconds = seconds_of(work, LOOKUPS_PER_SECOND)
    if lay.name == "cube" and spatial[1] == size:
        return Cost(chain, work, what, seconds)
    texels = valid_texels(lay, spatial)
    area = "area" if texels >= 6 * size * size else "bilinear"
    to_cube = remap_cost(
        lay, spatial, "cube", size, filter=area, channels=channels, itemsize=itemsize
    )
    return Cost(max(chain, to_cube.memory), work, what, seconds)


def _source(image: ArrayLike, layout: str, size: int, samples: int) -> _Source:
    if not 1 <= samples <= MAX_SAMPLES:
        raise ArgumentError(f"samples must be in 1..{MAX_SAMPLES}, got {samples}")
    with progress.step("preparing the source cube map"):
        return _Source(source_cube(image, layout, size=size))


def check_mips(mips: int, size: int) -> int:
    """``mips`` if a cube of ``size`` texels has that many levels (1 to ``size.bit_length()``),
    else :class:`ArgumentError`."""
    top = size.bit_length()
    if not 1 <= mips <= top:
        raise ArgumentError(f"{with_article(size)}-texel cube has 1..{top} mip levels; got {mips}")
    return mips


def mip_roughness(mips: int) -> np.ndarray:
    """The default roughness of each GGX level: ``m / (mips - 1)`` (0 for a single level)."""
    return np.linspace(0.0, 1.0, mips) if mips > 1 else np.zeros(1)


def phong_exponents(mips: int, *, gloss_scale: float = 10.0, gloss_bias: float = 1.0) -> np.ndarray:
    """Cmft's Phong exponent of each level: ``2^(gloss_scale g + gloss_bias)``,
    ``g = 1 - m / (mips - 1)`` (2048 down to 2 with the defaults)."""
    g = 1 - mip_roughness(mips)
    return 2.0 ** (gloss_scale * g + gloss_bias)


def prefilter_ggx(
    image: ArrayLike,
    layout: str,
    *,
    size: int = 256,
    mips: int = 9,
    roughness: ArrayLike | None = None,
    samples: int = 256,
) -> list[np.ndarray]:
    """The GGX prefiltered cube map mip chain (split-sum approximation, n = v = r).

    Parameters
    ----------
    image : array
        The environment (linear radiance) in ``layout``: ``(H, W, C)``, or ``(6, S, S, C)`` for
        ``"cube"``; a 2-D (3-D for a cube) array is one channel. NaN and Inf are refused.
    layout : str
        The input's layout (any of :data:`bakeshop.sphere.LAYOUT_NAMES`).
    size : int
        Face size of level 0; level ``m`` is ``max(1, size >> m)``.
    mips : int
        Number of levels (at most ``log2(size) + 1``).
    roughness : sequence of float, optional
        Perceptual roughness of each level (alpha = roughness^2), in [0, 1]. Default
        :func:`mip_roughness`: ``m / (mips - 1)``. A level of roughness 0 is the source itself.
    samples : int
        Importance samples per output texel (before dropping those below the horizon).

    Returns
    -------
    list of (6, S_m, S_m, C) float32
        Level 0 first, cube faces in OpenGL order (:mod:`bakeshop.sphere.cube`).

    Notes
    -----
    Level m holds ``integral L(l) D(h) (n.l) dl / integral D(h) (n.l) dl`` (n.l > 0), estimated
    by filtered importance sampling; see the module notes. Cost: ``samples`` bilinear lookups
    (two for trilinear) per output texel of levels 1 and up, so about 1/3 of ``6 size^2
    samples`` lookups, plus one area remap of the input.
    """
    mips = check_mips(mips, size)
    rough = mip_roughness(mips) if roughness is None else np.asarray(roughness, float)
    if rough.shape != (mips,) or not np.all((rough >= 0) & (rough <= 1)):
        raise ArgumentError(f"roughness must be {mips} values in [0, 1]; got {roughness!r}")
    # alpha >= 1e-4: a smoother lobe is narrower than any texel; roughness 0 at level 0 is
    # the source itself
    lobes = [
        None if rough[m] == 0 and max(1, size >> m) == size else (True, max(rough[m], 0.01) ** 4)
        for m in range(mips)
    ]
    return _chain(image, layout, size, samples, lobes, "GGX")


def prefilter_phong(
    image: ArrayLike,
    layout: str,
    *,
    size: int = 256,
    mips: int = 9,
    exponents: ArrayLike | None = None,
    samples: int = 256,
) -> list[np.ndarray]:
    """The Phong prefiltered cube map mip chain (HDRShop's specular convolution, cmft's filter).

    Parameters
    ----------
    image, layout, size, mips, samples
        As :func:`prefilter_ggx`.
    exponents : sequence of float, optional
        Phong exponent of each level, positive; ``inf`` is a mirror (the source itself at level
        0's size). Default :func:`phong_exponents` (cmft's gloss mapping).

    Returns
    -------
    list of (6, S_m, S_m, C) float32
        Level m holds ``integral L(l) (e_m + 1) / (2 pi) max(0, r.l)^e_m dl``: the lobe
        integrates to 1, so a uniform environment stays uniform.
    """
    mips = check_mips(mips, size)
    exps = phong_exponents(mips) if exponents is None else np.asarray(exponents, float)
    if exps.shape != (mips,) or not np.all(exps > 0) or np.any(np.isnan(exps)):
        raise ArgumentError(f"exponents must be {mips} positive values; got {exponents!r}")
    # e <= 1e8: a narrower lobe is smaller than any texel; inf at level 0 is the source
    lobes = [
        None if np.isinf(exps[m]) and max(1, size >> m) == size else (False, min(exps[m], 1e8))
        for m in range(mips)
    ]
    return _chain(image, layout, size, samples, lobes, "Phong")


def _chain(
    image: ArrayLike,
    layout: str,
    size: int,
    samples: int,
    lobes: list[tuple[bool, float] | None],
    name: str,
) -> list[np.ndarray]:
    """The levels of a chain: ``lobes[m]`` is ``(ggx, param)`` of :class:`_Lobe`, or None
    for the source cube itself. Its memory is checked first (:func:`prefilter_cost`)."""
    env = check_environment(image, layout)
    cost = require(
        prefilter_cost(
            env.image.shape,
            layout,
            size=size,
            mips=len(lobes),
            samples=samples,
            itemsize=env.image.itemsize,
        )
    )
    source = _source(image, layout, size, samples)
    out = []
    with progress.task(f"{name} prefilter, {len(lobes)} levels", total=cost.work) as task:
        for m, lobe in enumerate(lobes):
            s = max(1, size >> m)
            if lobe is None:
                out.append(source.cube)
                task.advance(6 * s * s)
            else:
                out.append(_convolve(source, s, _Lobe(*lobe, samples), task))
    return _shaped(out, image, layout)


def _shaped(chain: list[np.ndarray], image: ArrayLike, layout: str | Layout) -> list[np.ndarray]:
    """The chain's levels without their channel axis when the input had none."""
    if np.ndim(image) == (3 if get_layout(layout).cubic else 2):
        return [level[..., 0] for level in chain]
    return chain
