"""Images larger than memory: chunked resize, remap, spherical harmonics, the DIM pair, the sun
and the probe bake, each bounded by a memory bound and run by dask (threads here, or a
dask.distributed cluster).
"""

from typing import TYPE_CHECKING

from bakeshop._lazy import export_lazily

# names load from their module when first read (a command that only asks whether to go chunked
# loads the memory bound, not dask and the chunked jobs)
export_lazily(
    __name__,
    {
        "Engine": "engine",
        "HugeDimPair": "light",
        "dim_pair": "light",
        "find_sun": "light",
        "sh_coefficients": "light",
        "write_shadow_probe": "light",
        "MemoryBoundError": "memory",
        "default_memory": "memory",
        "parse_memory": "memory",
        "remap": "remap",
        "as_reader": "resize",
        "latlong_row_weights": "resize",
        "resize": "resize",
        "resize_to_file": "resize",
    },
)

if TYPE_CHECKING:  # what the table loads, for type checkers (tests/test_lazy.py)
    from bakeshop.huge.engine import Engine
    from bakeshop.huge.light import (
        HugeDimPair,
        dim_pair,
        find_sun,
        sh_coefficients,
        write_shadow_probe,
    )
    from bakeshop.huge.memory import MemoryBoundError, default_memory, parse_memory
    from bakeshop.huge.remap import remap
    from bakeshop.huge.resize import as_reader, latlong_row_weights, resize, resize_to_file

__all__ = [
    "Engine",
    "HugeDimPair",
    "dim_pair",
    "find_sun",
    "sh_coefficients",
    "write_shadow_probe",
    "MemoryBoundError",
    "as_reader",
    "default_memory",
    "latlong_row_weights",
    "parse_memory",
    "remap",
    "resize",
    "resize_to_file",
]
