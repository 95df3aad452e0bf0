"""FFT ocean synthesis on a tileable patch, looping in time (Tessendorf 2001).

A patch of ``size`` metres is sampled by ``resolution`` x ``resolution`` texels. Its wave vectors
lie on the patch lattice k = 2 pi (m_x, m_y) / size, so every field is periodic with the patch:
the texture tiles by construction. Each lattice mode gets a complex amplitude from a seed
(deterministic: a counter-based hash of the seed and the mode's integer indices, so the same
seed gives the same waves at any resolution and on any machine), and the elevation is

    h(x, t) = sum_k  h_hat(k, t) exp(i k . x),
    h_hat(k, t) = h0(k) exp(-i w(k) t) + conj(h0(-k)) exp(+i w(k) t),
    h0(k) = (xi_r + i xi_i) sqrt(F(k) dk^2 / 2)

with xi standard normal, F the wave-vector density of :class:`~bakeshop.water.spectra.Spectrum`
and dk = 2 pi / size. The first term travels towards k, the second is the Hermitian partner of
the wave travelling towards -k, so h is real and E[h^2] = sum F dk^2. The zero mode and the
Nyquist row and column (whose wave vector is ambiguous, and whose derivatives cannot be real)
are zero.

Derived fields are exact spectral derivatives (Tessendorf eqs. 36, 44 and the Jacobian):

    slope        d h / dx = sum i kx h_hat e^{ik.x}   (and y)
    displacement D = sum i (k / |k|) h_hat e^{ik.x}   (points move towards the crests)
    Jacobian     J = (1 + l Dxx)(1 + l Dyy) - (l Dxy)^2,  Dxx = -sum kx^2 / |k| h_hat e^{ik.x} ...

with choppiness l >= 0 (Tessendorf writes D with -i and a negative lambda; the surface is the
same). The normal of the displaced surface P = (x + l Dx, y + l Dy, h) is dP/dx x dP/dy:

    n ~ (-hx (1 + l Dyy) + l Dxy hy,  -hy (1 + l Dxx) + l Dxy hx,  J)

evaluated at the texel's own (undisplaced) position, which is where an engine that displaces
its vertices by the displacement map samples the normal map.

**Looping**: with ``loop_period`` T, every frequency is rounded to a whole number of turns per
loop, w_q = 2 pi n / T, n = round(w T / 2 pi), so h(x, t + T) = h(x, t) exactly. Modes with
w < pi / T get n = 0 and freeze (they stop moving); :attr:`Ocean.report` says how many and what
variance they carry, and ``frozen="drop"`` removes them instead. On a frame grid t_f = f T / F
the phase is looked up from an F-entry table at (n f mod F), so frame F *is* frame 0, bit for
bit.

Texel (i, j) (column, row; row 0 at the top) holds the field at its centre,
x = (i + 1/2) dx, y = size - (j + 1/2) dx: +x along u (world +X), +y up the picture (world -Z),
the tangent frame of bakeshop's normal maps (+X along u, +Y along v up, +Z out).

References
----------
J. Tessendorf, "Simulating Ocean Water", SIGGRAPH 2001 course notes, sec. 3.3-3.5.
G. L. Steele, D. Lea and C. H. Flood, "Fast splittable pseudorandom number generators",
OOPSLA 2014, doi:10.1145/2660193.2660195 (SplitMix64, the hash behind the amplitudes).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import scipy.fft
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, validate_choice, with_article
from bakeshop.resources import Cost, require
from bakeshop.water import _native
from bakeshop.water.amplitudes import _check_seed, mode_normals
from bakeshop.water.spectra import Spectrum

#: Fields that :func:`ocean_frames` can produce, with their channels and units.
FIELDS = {
    "height": (1, "m"),
    "slope": (2, "m/m (dh/dx, dh/dy)"),
    "displacement": (2, "m (choppiness * Dx, choppiness * Dy)"),
    "jacobian": (1, "1"),
    "normal": (3, "unit vector, tangent frame (x along u, y along v up, z out)"),
}
FieldName = Literal["height", "slope", "displacement", "jacobian", "normal"]
FROZEN_MODES = ("keep", "drop")
ALIAS_MODES = ("refuse", "drop")
DTYPES = ("float32", "float64")
#: A folded texel (J <= 0, the surface passes through itself) has no outward normal; its
#: normal's z is clamped to this before normalising (such texels are foam).
FOLD_FLOOR: float = _native.FOLD_FLOOR


#: Bytes of working memory one frame batch may take (complex spectra, FFT buffers, outputs).
BATCH_BYTES = 256 << 20
#: Most frames per batch: the spectra of a batch are written mode by mode for every frame, and
#: more than a few output streams at once defeat the caches.
BATCH_FRAMES = 8
#: Largest texture side accepted (a 8192^2 frame of 4 complex pairs is 2 GiB).
MAX_RESOLUTION = 8192
#: Bytes per lattice mode that :func:`ocean` holds while seeding (wave vectors, amplitudes,
#: partners, frequencies, variances, turns and their temporaries), and the most it may take.
SEED_BYTES_PER_MODE = 160
SEED_BYTES_LIMIT = 8 << 30


@dataclass(eq=False)
class Ocean:
    """A seeded wave field on a tileable patch; make one with :func:`ocean`.

    Attributes
    ----------
    spectrum : Spectrum
    size : float
        Patch side, m.
    resolution : int
        Texels per side (even).
    seed : int
    loop_period : float or None
        T, s; None for an ocean that does not loop.
    kx, ky : (N, N) float64
        Wave vector of each entry of the FFT-ordered spectra, rad/m (ky along +v, up).
    amplitude : (N, N) complex128
        h0(k) times the half-texel phase of the texel centres.
    partner : (N, N) complex128
        conj(h0(-k)) times the same phase.
    omega : (N, N) float64
        Angular frequency of each mode, rad/s (quantised when looping).
    mode_variance : (N, N) float64
        F(k) dk^2, m^2: the expected variance of the wave travelling towards each k (zero where
        the mode is not used). Sums to the field's expected variance.
    cycles : (N, N) int64 or None
        Whole turns per loop of each mode (looping only).
    report : dict
        What the lattice keeps of the spectrum and what looping changed (see :func:`ocean`).
    """

    spectrum: Spectrum
    size: float
    resolution: int
    seed: int
    loop_period: float | None
    kx: np.ndarray = field(repr=False)
    ky: np.ndarray = field(repr=False)
    amplitude: np.ndarray = field(repr=False)
    partner: np.ndarray = field(repr=False)
    omega: np.ndarray = field(repr=False)
    mode_variance: np.ndarray = field(repr=False)
    cycles: np.ndarray | None = field(repr=False)
    report: dict = field(default_factory=dict)

    @property
    def texel(self) -> float:
        """Texel size, m."""
        return self.size / self.resolution

    @property
    def max_cycles(self) -> int:
        """The most turns any mode makes per loop (0 without a loop)."""
        if self.cycles is None:
            return 0
        live = (self.amplitude != 0) | (self.partner != 0)
        return int(np.abs(self.cycles[live]).max(initial=0))

    def minimum_frames(self) -> int:
        """The fewest frames per loop that sample the fastest mode without aliasing:
        2 n_max + 1, where n_max is the largest number of turns a mode makes per loop (a mode
        sampled with fewer than two frames per turn appears to turn the other way)."""
        if self.cycles is None:
            raise ArgumentError("this ocean does not loop (no loop_period)")
        return 2 * self.max_cycles + 1

    def spectrum_at(self, t: float) -> np.ndarray:
        """h_hat(k, t) on the FFT grid, complex128 (N, N) (Hermitian: h_hat(-k) = conj h_hat(k)).

        ``scipy.fft.ifft2(h_hat, norm="forward")`` is the height field at time ``t`` (s).
        """
        phase = np.exp(-1j * self.omega * float(t))
        return self.amplitude * phase + self.partner * np.conj(phase)

    def positions(self) -> tuple[np.ndarray, np.ndarray]:
        """Texel centres (x, y), m, each (N, N): x = (i + 1/2) dx, y = size - (j + 1/2) dx."""
        c = (np.arange(self.resolution) + 0.5) * self.texel
        return np.meshgrid(c, self.size - c)

    def frame_times(self, frames: int) -> np.ndarray:
        """t_f = f T / F for f = 0..F-1, s (looping oceans)."""
        if self.cycles is None or self.loop_period is None:
            raise ArgumentError("frame times need a loop period; pass times for a free ocean")
        return np.arange(frames) * (self.loop_period / frames)

    def without(self, mask: np.ndarray) -> Ocean:
        """A copy with the modes at ``mask`` (N, N) bool, and their partners, set to zero."""
        n = self.resolution
        rows, cols = np.nonzero(mask)
        mask = mask.copy()
        mask[(-rows) % n, (-cols) % n] = True
        amplitude = np.where(mask, 0, self.amplitude)
        partner = np.where(mask, 0, self.partner)
        variance = np.where(mask, 0.0, self.mode_variance)
        return Ocean(
            self.spectrum, self.size, self.resolution, self.seed, self.loop_period, self.kx,
            self.ky, amplitude, partner, self.omega, variance, self.cycles, dict(self.report),
        )  # fmt: skip


def lattice(size: float, resolution: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The patch lattice in FFT order: (kx, ky, mx, my), each (N, N).

    Entry [p, q] holds the wave vector (kx, ky) = 2 pi (mx, my) / size with mx = q' and
    my = -p' (p', q' the signed FFT frequencies), so that an inverse FFT over (rows, columns)
    evaluates sum h_hat exp(i k . x) at texel centres with y up the picture (row 0 at the top).
    """
    f = np.fft.fftfreq(resolution, 1.0 / resolution).astype(np.int64)
    my, mx = np.meshgrid(-f, f, indexing="ij")
    dk = 2 * math.pi / size
    return mx * dk, my * dk, mx, my


def ocean(
    spectrum: Spectrum,
    *,
    size: float,
    resolution: int,
    seed: int = 0,
    loop_period: float | None = None,
    frozen: str = "keep",
    k_range: tuple[float, float] = (0.0, math.inf),
) -> Ocean:
    """Seed the wave field of a tileable patch.

    Parameters
    ----------
    spectrum : Spectrum
        The sea state (SI units).
    size : float
        Patch side, m (> 0). The lattice holds wavelengths from ``size`` down to two texels.
    resolution : int
        Texels per side: even, 4 to 8192 (powers of two are fastest).
    seed : int
        Amplitudes and phases; the same seed gives the same waves at any resolution.
    loop_period : float or None
        T, s (> 0): quantise frequencies so the animation loops with this period.
    frozen : {"keep", "drop"}
        What to do with modes that loop quantisation freezes (w < pi / T): keep them as a static
        relief, or remove them. Either way :attr:`Ocean.report` says what they carry.
    k_range : (float, float)
        Keep only wave numbers in [k_min, k_max), rad/m (cascades split the spectrum by this).

    Returns
    -------
    Ocean
        With ``report``: ``modes`` (non-zero modes), ``variance`` (m^2, of the lattice),
        ``hs`` (m, 4 sqrt(variance)), ``spectrum_variance`` and ``spectrum_hs`` (the spectrum's
        own over k_range and the lattice's disc |k| < pi n / size), ``captured`` (the
        lattice's variance within that disc over the spectrum's; nan when the spectrum holds
        nothing there), and when looping ``frozen_modes``, ``frozen_variance`` (m^2),
        ``frozen_fraction``, ``max_cycles``,
        ``max_frequency_shift`` (largest |w_q - w| / w of a moving mode) and
        ``minimum_frames``.
    """
    if not isinstance(spectrum, Spectrum):
        raise ArgumentError("spectrum must be a bakeshop.water.spectra.Spectrum")
    size = _positive(size, "patch size (m)")
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)):
        raise ArgumentError(f"resolution must be an integer, got {resolution!r}")
    resolution = int(resolution)
    if not (4 <= resolution <= MAX_RESOLUTION and resolution % 2 == 0):
        raise ArgumentError(
            f"resolution must be even, from 4 to {MAX_RESOLUTION}; got {resolution}"
        )
    seed = _check_seed(seed)
    needed = resolution * resolution * SEED_BYTES_PER_MODE
    if needed > SEED_BYTES_LIMIT:
        raise ArgumentError(
            f"{with_article(resolution)}^2 lattice needs about {needed / 2**30:.1f} GiB to seed "
            "(limit "
            f"{SEED_BYTES_LIMIT / 2**30:.0f} GiB); use a lower resolution or cascades"
        )
    what = f"seeding {with_article(resolution)}^2 wave lattice"
    require(Cost(needed, resolution * resolution, what))
    if loop_period is not None:
        loop_period = _positive(loop_period, "loop period (s)")
    validate_choice(frozen, FROZEN_MODES, "frozen-mode policy")
    k_min, k_max = (float(v) for v in k_range)
    if not (k_min >= 0 and k_max > k_min) or math.isnan(k_min + k_max):
        raise ArgumentError(f"k_range must be 0 <= k_min < k_max, got {k_range!r}")

    n = resolution
    kx, ky, mx, my = lattice(size, n)
    k = np.hypot(kx, ky)
    dk = 2 * math.pi / size
    f = spectrum.density(kx, ky)
    nyquist = (np.abs(mx) == n // 2) | (np.abs(my) == n // 2)
    keep = (k > 0) & ~nyquist & (k >= k_min) & (k < k_max)
    f = np.where(keep, f, 0.0)
    xi = mode_normals(seed, mx, my)
    h0 = (xi[..., 0] + 1j * xi[..., 1]) * np.sqrt(f * dk * dk / 4)  # E|h0|^2 = F dk^2 / 2
    omega = spectrum.omega(k)
    report: dict = {}
    cycles = None
    variance_all = float((f * dk * dk).sum())
    if loop_period is not None:
        cycles = np.rint(omega * loop_period / (2 * math.pi)).astype(np.int64)
        quantised = cycles * (2 * math.pi / loop_period)
        still = (cycles == 0) & (f > 0)
        moving = (cycles != 0) & (f > 0)
        report["frozen_modes"] = int(still.sum())
        report["frozen_variance"] = float((f[still] * dk * dk).sum())
        shift = np.abs(quantised[moving] - omega[moving]) / omega[moving]
        report["max_frequency_shift"] = float(shift.max(initial=0.0))
        omega = quantised
        if frozen == "drop":
            h0 = np.where(still, 0, h0)
            f = np.where(still, 0.0, f)
    # the half-texel phase of the texel centres: x0 = dx / 2, y0 = size - dx / 2
    shift_phase = np.exp(0.5j * (kx - ky) * (size / n))
    partner = np.conj(h0[(-np.arange(n)) % n][:, (-np.arange(n)) % n])
    o = Ocean(
        spectrum, size, n, seed, loop_period, kx, ky, h0 * shift_phase,
        partner * shift_phase, omega, f * dk * dk, cycles, report,
    )  # fmt: skip
    variance = float((f * dk * dk).sum())
    report["modes"] = int((f > 0).sum())
    report["variance"] = variance
    report["hs"] = 4 * math.sqrt(variance)
    # both sides of the ratio over the disc dk / 2 <= |k| < pi n / size (the lattice's
    # corners reach sqrt(2) times further: where the spectrum's tail rises towards them, a
    # light wind's whole lattice variance can sit there)
    k_top = min(k_max, math.pi * n / size)
    total = spectrum.variance(max(k_min, dk / 2), k_top)
    report["spectrum_variance"] = total
    report["spectrum_hs"] = 4 * math.sqrt(total)
    in_band = float((f * dk * dk)[k < k_top].sum())
    report["captured"] = in_band / total if total > 0 else float("nan")
    if loop_period is not None:
        report["frozen_fraction"] = (
            report["frozen_variance"] / variance_all if variance_all > 0 else 0.0
        )
        report["max_cycles"] = o.max_cycles
        report["minimum_frames"] = o.minimum_frames()
    return o


def _positive(value: float, what: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ArgumentError(f"{what} must be a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise ArgumentError(f"{what} must be a finite number > 0, got {value!r}")
    return v


# --- frames -------------------------------------------------------------------------------------

# Field pairs packed into one complex inverse FFT each: (real part, imaginary part).
_PAIRS = {
    "slope": ("hx", "hy"),
    "stretch": ("dxx", "dyy"),
    "height": ("h", "dxy"),
    "shift": ("dx", "dy"),
}


def _multipliers(o: Ocean, pairs: Sequence[str]) -> np.ndarray:
    """M[p] such that h_hat * M[p] is the spectrum of pair p (real field + i * real field)."""
    kx, ky = o.kx, o.ky
    k = np.hypot(kx, ky)
    inv_k = np.divide(1.0, k, out=np.zeros_like(k), where=k > 0)
    table = {
        "slope": 1j * kx - ky,  # i kx h + i (i ky h)
        "stretch": -(kx * kx + 1j * ky * ky) * inv_k,  # -kx^2/k h + i (-ky^2/k h)
        "height": 1 - 1j * kx * ky * inv_k,  # h + i (-kx ky / k h)
        "shift": (1j * kx - ky) * inv_k,  # i kx/k h + i (i ky/k h)
    }
    return np.stack([table[p] for p in pairs]).astype(np.complex128)


def _pairs_for(fields: Sequence[str], choppiness: float) -> list[str]:
    pairs = []
    if "slope" in fields or "normal" in fields:
        pairs.append("slope")
    if "jacobian" in fields or ("normal" in fields and choppiness > 0):
        pairs += ["stretch", "height"]
    if "height" in fields and "height" not in pairs:
        pairs.append("height")
    if "displacement" in fields:
        pairs.append("shift")
    return pairs


def frame_bytes(resolution: int, fields: Sequence[str], choppiness: float, dtype: str) -> int:
    """Working memory of one frame, bytes: the complex spectra (and their FFTs, in place) plus
    the requested output channels."""
    pairs = len(_pairs_for(fields, choppiness))
    item = 8 if dtype == "float32" else 16
    channels = sum(FIELDS[f][0] for f in fields)
    return resolution * resolution * (pairs * item + channels * item // 2)


def ocean_frames(
    o: Ocean,
    *,
    frames: int | None = None,
    times: ArrayLike | None = None,
    fields: Sequence[FieldName] = ("normal",),
    choppiness: float = 0.0,
    dtype: str = "float32",
    batch: int | None = None,
    alias: str = "refuse",
    workers: int | None = None,
) -> Iterator[tuple[np.ndarray, dict[str, np.ndarray]]]:
    """Synthesise fields frame by frame, a batch at a time (memory bounded by one batch).

    Parameters
    ----------
    o : Ocean
    frames : int, optional
        F frames over one loop (t_f = f T / F; looping oceans). F must be at least
        :meth:`Ocean.minimum_frames` (or ``alias="drop"``).
    times : array_like, optional
        Explicit times, s (instead of ``frames``).
    fields : sequence of {"height", "slope", "displacement", "jacobian", "normal"}
        What to make (:data:`FIELDS` gives channels and units).
    choppiness : float
        lambda >= 0, the horizontal displacement scale (0: no displacement; about 1 sharpens
        crests; the surface folds where J < 0).
    dtype : {"float32", "float64"}
        Precision of the FFTs and of the fields.
    batch : int, optional
        Frames per batch; by default as many as fit in :data:`BATCH_BYTES`.
    alias : {"refuse", "drop"}
        When ``frames`` is too few for the fastest mode: refuse with the reason, or remove the
        modes that would alias (see :func:`fit_to_frames`, which says what they carried).
    workers : int, optional
        FFT threads (default: all cores).

    Yields
    ------
    indices : (B,) int
        Frame indices (or indices into ``times``) of this batch.
    fields : dict of str to float array
        ``(B, N, N)`` for one-channel fields, ``(B, N, N, C)`` for the others.
    """
    fields = list(fields)
    for name in fields:
        validate_choice(name, tuple(FIELDS), "ocean field")
    if not fields:
        raise ArgumentError("ask for at least one field")
    validate_choice(dtype, DTYPES, "precision")
    validate_choice(alias, ALIAS_MODES, "aliasing policy")
    choppiness = float(choppiness)
    if not (math.isfinite(choppiness) and choppiness >= 0):
        raise ArgumentError(f"choppiness must be a finite number >= 0, got {choppiness!r}")
    if (frames is None) == (times is None):
        raise ArgumentError("give either frames= (a looping ocean) or times=")
    if frames is not None:
        if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 1:
            raise ArgumentError(f"frames must be a positive integer, got {frames!r}")
        frames = int(frames)
        if o.cycles is None:
            raise ArgumentError("frames= needs an ocean with a loop period; pass times= instead")
        o = fit_to_frames(o, frames, alias=alias)
        count = frames
        index = np.arange(frames, dtype=np.int64)
    else:
        t = np.asarray(times, dtype=np.float64).ravel()
        if not np.isfinite(t).all():
            raise ArgumentError("times must be finite")
        count = t.size
        index = np.arange(count, dtype=np.int64)
    pairs = _pairs_for(fields, choppiness)
    mult = _multipliers(o, pairs)
    per_frame = frame_bytes(o.resolution, fields, choppiness, dtype)
    if batch is None:
        batch = max(1, min(count, BATCH_FRAMES, BATCH_BYTES // max(per_frame, 1)))
    elif isinstance(batch, bool) or not isinstance(batch, (int, np.integer)) or batch < 1:
        raise ArgumentError(f"batch must be a positive integer, got {batch!r}")
    n = o.resolution
    require(Cost(batch * per_frame, count, f"synthesising {batch} ocean frames of {n}x{n} at once"))
    complex_type = np.complex64 if dtype == "float32" else np.complex128
    real_type = np.float32 if dtype == "float32" else np.float64
    workers = workers or os.cpu_count() or 1
    a = o.amplitude.astype(complex_type)
    b = o.partner.astype(complex_type)
    if frames is not None:
        table = np.exp(-2j * np.pi * np.arange(frames) / frames).astype(complex_type)
    m = mult.astype(complex_type)
    for start in range(0, count, batch):
        sel = index[start : start + batch]
        spectra = np.empty((sel.size, len(pairs), n, n), complex_type)
        if frames is not None:
            assert o.cycles is not None  # a looping ocean: checked above
            _native.loop_spectra(a, b, o.cycles, sel, table, m, spectra)
        else:
            _native.free_spectra(a, b, o.omega, t[sel], m, spectra)
        scipy.fft.ifft2(spectra, axes=(-2, -1), norm="forward", overwrite_x=True, workers=workers)
        yield sel, _unpack(spectra, pairs, fields, choppiness, real_type)


def fit_to_frames(o: Ocean, frames: int, *, alias: str = "refuse") -> Ocean:
    """``o`` itself when ``frames`` per loop sample its fastest mode, else refuse with the
    reason (``alias="refuse"``) or return a copy without the modes that would alias
    (``alias="drop"``: |n| >= frames / 2 turns per loop), whose report gains
    ``aliased_modes`` and ``aliased_variance`` (m^2)."""
    validate_choice(alias, ALIAS_MODES, "aliasing policy")
    needed = o.minimum_frames()
    assert o.cycles is not None  # minimum_frames refuses an ocean that does not loop
    if frames >= needed:
        return o
    if alias == "refuse":
        raise ArgumentError(
            f"{frames} frames per {o.loop_period:g} s loop alias the fastest waves, which turn "
            f"{o.max_cycles} times per loop (wavelength {_fastest_wavelength(o):.3g} m); use at "
            f"least {needed} frames, a shorter loop, a coarser resolution, a "
            "small-wave cut-off, or alias='drop' to remove those waves"
        )
    bad = (np.abs(o.cycles) * 2 >= frames) & (o.mode_variance > 0)
    report = dict(o.report)
    reduced = o.without(bad)
    report["aliased_modes"] = int(bad.sum())
    report["aliased_variance"] = float(o.mode_variance[bad].sum())
    report["aliased_fraction"] = report["aliased_variance"] / max(report["variance"], 1e-300)
    reduced.report = report
    return reduced


def _unpack(
    spectra: np.ndarray,
    pairs: Sequence[str],
    fields: Sequence[str],
    choppiness: float,
    real_type: type[np.floating],
) -> dict[str, np.ndarray]:
    index = {p: i for i, p in enumerate(pairs)}
    got = {p: spectra[:, i] for i, p in enumerate(pairs)}
    out: dict[str, np.ndarray] = {}
    lam = choppiness
    if "height" in fields:
        out["height"] = got["height"].real.astype(real_type)
    if "slope" in fields:
        s = got["slope"]
        out["slope"] = np.stack([s.real, s.imag], axis=-1).astype(real_type)
    if "displacement" in fields:
        s = got["shift"]
        out["displacement"] = (np.stack([s.real, s.imag], axis=-1) * lam).astype(real_type)
    if "jacobian" in fields:
        st, hd = got["stretch"], got["height"]
        out["jacobian"] = ((1 + lam * st.real) * (1 + lam * st.imag) - (lam * hd.imag) ** 2).astype(
            real_type
        )
    if "normal" in fields:
        normals = np.empty(got["slope"].shape + (3,), real_type)
        if choppiness > 0:
            _native.normals(spectra, index["slope"], index["stretch"], index["height"], lam,
                            normals)  # fmt: skip
        else:
            _native.flat_normals(spectra, index["slope"], normals)
        out["normal"] = normals
    return out


def _fastest_wavelength(o: Ocean) -> float:
    live = (o.amplitude != 0) | (o.partner != 0)
    if o.cycles is None or not live.any():
        return float("nan")
    k = np.hypot(o.kx, o.ky)
    i = np.argmax(np.where(live, np.abs(o.cycles), -1))
    return 2 * math.pi / float(k.flat[i])


def ocean_fields(o: Ocean, **options: Any) -> dict[str, np.ndarray]:
    """All frames of :func:`ocean_frames` at once: each field ``(F, N, N[, C])``.

    Takes the same keyword options; mind the memory (F frames of every field).
    """
    parts: dict[str, list] = {}
    for _, batch in ocean_frames(o, **options):
        for name, value in batch.items():
            parts.setdefault(name, []).append(value)
    return {name: np.concatenate(values) for name, values in parts.items()}


def evaluate(
    o: Ocean, x: ArrayLike, y: ArrayLike, t: float, *, choppiness: float = 0.0
) -> dict[str, np.ndarray]:
    """Brute-force sums at arbitrary points: height, slope, displacement and normal at (x, y)
    (m) and time ``t`` (s), float64, straight from the modes (no FFT).

    Costs O(points x modes): a reference for tests and for a few probe points (buoyancy).
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    shape = np.broadcast(x, y).shape
    x, y = np.broadcast_to(x, shape).ravel(), np.broadcast_to(y, shape).ravel()
    hk = o.spectrum_at(t)
    # undo the half-texel phase: spectrum_at is relative to the texel-centre grid
    hk = hk * np.exp(-0.5j * (o.kx - o.ky) * o.texel)
    live = hk != 0
    kx, ky, hk = o.kx[live], o.ky[live], hk[live]
    k = np.hypot(kx, ky)
    out = {name: np.zeros(x.size) for name in ("h", "hx", "hy", "dx", "dy", "dxx", "dyy", "dxy")}
    step = max(1, (1 << 22) // max(kx.size, 1))
    for s in range(0, x.size, step):
        e = hk[None, :] * np.exp(1j * (x[s : s + step, None] * kx + y[s : s + step, None] * ky))
        out["h"][s : s + step] = e.real.sum(1)
        out["hx"][s : s + step] = (e * (1j * kx)).real.sum(1)
        out["hy"][s : s + step] = (e * (1j * ky)).real.sum(1)
        out["dx"][s : s + step] = (e * (1j * kx / k)).real.sum(1)
        out["dy"][s : s + step] = (e * (1j * ky / k)).real.sum(1)
        out["dxx"][s : s + step] = (e * (-kx * kx / k)).real.sum(1)
        out["dyy"][s : s + step] = (e * (-ky * ky / k)).real.sum(1)
        out["dxy"][s : s + step] = (e * (-kx * ky / k)).real.sum(1)
    lam = float(choppiness)
    hx, hy = out["hx"], out["hy"]
    dxx, dyy, dxy = lam * out["dxx"], lam * out["dyy"], lam * out["dxy"]
    n = np.stack(
        [-hx * (1 + dyy) + dxy * hy, -hy * (1 + dxx) + dxy * hx, (1 + dxx) * (1 + dyy) - dxy**2],
        axis=-1,
    )
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return {
        "height": out["h"].reshape(shape),
        "slope": np.stack([hx, hy], -1).reshape(shape + (2,)),
        "displacement": (lam * np.stack([out["dx"], out["dy"]], -1)).reshape(shape + (2,)),
        "jacobian": ((1 + dxx) * (1 + dyy) - dxy**2).reshape(shape),
        "normal": n.reshape(shape + (3,)),
    }
