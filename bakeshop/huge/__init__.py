"""Images larger than memory: chunked resize, remap, spherical harmonics, the DIM pair, the sun
and the probe bake, each bounded by a memory bound and run by dask (threads here, or a
dask.distributed cluster).
"""

from bakeshop.huge.engine import Engine
from bakeshop.huge.light import HugeDimPair, dim_pair, find_sun, sh_coefficients, write_shadow_probe
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
