"""What is computed from an environment: spherical harmonics, diffuse irradiance (DIMs and the
DIM pair), the sun, specular prefiltering and the DFG table, fresnel bakes, and the whole
probe bake.

>>> from bakeshop.light import bake_probe, dim_pair, irradiance
>>> dim = irradiance(probe, "latlong")                 # E / pi, latlong 360x180
>>> pair = dim_pair(probe, "latlong")                  # sun DIM, shadow DIM, shadow probe, sun

Modules: :mod:`~bakeshop.light.sh`, :mod:`~bakeshop.light.diffuse` (the cosine convolution),
:mod:`~bakeshop.light.sun`, :mod:`~bakeshop.light.dims`, :mod:`~bakeshop.light.specular`,
:mod:`~bakeshop.light.dfg`, :mod:`~bakeshop.light.fresnel`, :mod:`~bakeshop.light.probe`.
"""

from typing import TYPE_CHECKING

from bakeshop._lazy import export_lazily

# names load from their module when first read (`irradiance` loads the cosine convolution, not
# the specular prefilter, its area filter and scipy.sparse)
export_lazily(
    __name__,
    {
        "dfg_table": "dfg",
        "dfg_table_cost": "dfg",
        "METHODS": "diffuse",
        "cosine_sum": "diffuse",
        "irradiance": "diffuse",
        "irradiance_cost": "diffuse",
        "sh_coefficients": "diffuse",
        "DimPair": "dims",
        "dim_pair": "dims",
        "dim_pair_cost": "dims",
        "WATER_IOR": "fresnel",
        "bake_fresnel": "fresnel",
        "fresnel_dielectric": "fresnel",
        "ProbeBake": "probe",
        "bake_probe": "probe",
        "bake_probe_cost": "probe",
        "contact_sheet": "probe",
        "sheet_exposure": "probe",
        "prefilter_cost": "specular",
        "prefilter_ggx": "specular",
        "prefilter_phong": "specular",
        "source_cube": "specular",
        "Sun": "sun",
        "find_sun": "sun",
        "find_sun_cost": "sun",
        "remove_sun": "sun",
        "sun_document": "sun",
    },
)

if TYPE_CHECKING:  # what the table loads, for type checkers (tests/test_lazy.py)
    from bakeshop.light.dfg import dfg_table, dfg_table_cost
    from bakeshop.light.diffuse import (
        METHODS,
        cosine_sum,
        irradiance,
        irradiance_cost,
        sh_coefficients,
    )
    from bakeshop.light.dims import DimPair, dim_pair, dim_pair_cost
    from bakeshop.light.fresnel import WATER_IOR, bake_fresnel, fresnel_dielectric
    from bakeshop.light.probe import (
        ProbeBake,
        bake_probe,
        bake_probe_cost,
        contact_sheet,
        sheet_exposure,
    )
    from bakeshop.light.specular import prefilter_cost, prefilter_ggx, prefilter_phong, source_cube
    from bakeshop.light.sun import Sun, find_sun, find_sun_cost, remove_sun, sun_document

__all__ = [
    "METHODS",
    "WATER_IOR",
    "DimPair",
    "ProbeBake",
    "Sun",
    "bake_fresnel",
    "bake_probe",
    "bake_probe_cost",
    "contact_sheet",
    "cosine_sum",
    "dfg_table",
    "dfg_table_cost",
    "dim_pair",
    "dim_pair_cost",
    "find_sun",
    "find_sun_cost",
    "fresnel_dielectric",
    "irradiance",
    "irradiance_cost",
    "prefilter_cost",
    "prefilter_ggx",
    "prefilter_phong",
    "remove_sun",
    "sh_coefficients",
    "sheet_exposure",
    "source_cube",
    "sun_document",
]
