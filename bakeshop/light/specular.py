"""Specular prefiltering: GGX and Phong cube map mip chains for glossy reflections.

(prefilter functions follow)
"""

from __future__ import annotations

import math

import numba
import numpy as np


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


@numba.njit(cache=True, inline="always")
def ggx_half_vector(u, v, alpha):
    """Half vector h (tangent frame, n = +z) distributed as D(h) (n.h) for GGX's ``alpha``.

    cos^2(theta) = (1 - v) / (1 + (alpha^2 - 1) v), phi = 2 pi u (Walter et al. 2007).
    """
    a2 = alpha * alpha
    cos2 = (1.0 - v) / (1.0 + (a2 - 1.0) * v)
    cos_t = math.sqrt(cos2)
    sin_t = math.sqrt(max(0.0, 1.0 - cos2))
    phi = 2.0 * math.pi * u
    return sin_t * math.cos(phi), sin_t * math.sin(phi), cos_t
