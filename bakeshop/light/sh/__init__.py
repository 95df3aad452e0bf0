"""Real spherical harmonics: basis, projection, evaluation, zonal convolution, export, blending.

Convention (DESIGN.md): real, orthonormal on the unit sphere, graphics order. Coefficient
``k = l * (l + 1) + m`` holds ``Y(l, m)``, m = -l..l, so an expansion to order ``L`` has
``(L + 1)**2`` coefficients. The polar axis is +Z and the azimuth is measured from +X towards
+Y, without the Condon-Shortley phase, so ``Y(1, -1) = c*y``, ``Y(1, 0) = c*z``,
``Y(1, 1) = c*x`` with ``c = sqrt(3 / (4 pi))`` in bakeshop's world frame (+Y up, -Z forward).
These are the signs of Ramamoorthi and Hanrahan (2001) and of Sloan's "Stupid SH tricks" with
the phase dropped:

    Y(l, 0)  = N(l, 0) P(l, 0)(z)
    Y(l, m)  = sqrt(2) N(l, m) P(l, m)(z) cos(m phi)      m > 0
    Y(l, -m) = sqrt(2) N(l, m) P(l, m)(z) sin(m phi)      m > 0
    N(l, m)  = sqrt((2l + 1) / (4 pi) * (l - m)! / (l + m)!)

An environment's coefficient array is ``(n_coeffs, C)`` float64 (C colour channels); a
convolution kernel is a per-degree array of ``L + 1`` factors (the Funk-Hecke eigenvalues).

References
----------
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
SIGGRAPH 2001, doi:10.1145/383259.383317.
P.-P. Sloan, "Stupid spherical harmonics (SH) tricks", GDC 2008.

Modules: :mod:`~bakeshop.light.sh.harmonics` (basis, projection, evaluation, convolution,
blending), :mod:`~bakeshop.light.sh.window` (windows against ringing, the non-negative DIM),
:mod:`~bakeshop.light.sh.export` (JSON documents, shader functions); every name is
available here (``from bakeshop.light import sh; sh.project(...)``).
"""

from bakeshop.light.sh.export import (
    from_document,
    shader_snippet,
    to_document,
)
from bakeshop.light.sh.harmonics import (
    MAX_ORDER,
    RH_C1,
    RH_C2,
    RH_C3,
    RH_C4,
    RH_C5,
    basis,
    blend,
    clamped_cosine,
    convolve,
    cosine_power_kernel,
    evaluate,
    index,
    inverse_distance_weights,
    irradiance_coefficients,
    irradiance_matrices,
    n_coefficients,
    order_of,
    phong_kernel,
    project,
)
from bakeshop.light.sh.window import (
    NEGATIVE_GRID,
    WINDOWS,
    IrradianceSH,
    Window,
    minimal_window,
    minimum,
    negative_fraction,
    search_cost,
    window_factors,
    windowed_irradiance,
)

__all__ = [
    "MAX_ORDER",
    "NEGATIVE_GRID",
    "RH_C1",
    "RH_C2",
    "RH_C3",
    "RH_C4",
    "RH_C5",
    "WINDOWS",
    "IrradianceSH",
    "Window",
    "basis",
    "blend",
    "clamped_cosine",
    "convolve",
    "cosine_power_kernel",
    "evaluate",
    "from_document",
    "index",
    "inverse_distance_weights",
    "irradiance_coefficients",
    "irradiance_matrices",
    "minimal_window",
    "minimum",
    "n_coefficients",
    "negative_fraction",
    "order_of",
    "phong_kernel",
    "project",
    "search_cost",
    "shader_snippet",
    "to_document",
    "window_factors",
    "windowed_irradiance",
]
