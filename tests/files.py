"""The third-party files the tests read, all in the repository (tests/data, its README lists the
source and licence of each), so a clone alone runs every test."""

from pathlib import Path

from bakeshop.data import default_probe_path

DATA = Path(__file__).resolve().parent / "data"

#: Poly Haven's 1k latlong probes (CC0), by name: clear skies with a sun of 1-2 texels
#: (quarry_01, rooitou_park), a sun on the horizon (venice_sunset), an interior with bright
#: windows, soft dawn light, an overcast forest, and studio softboxes.
PROBES = (
    "forest_slope",
    "kiara_1_dawn",
    "quarry_01",
    "rooitou_park",
    "st_fagans_interior",
    "studio_small_03",
    "venice_sunset",
)


def probe_path(name: str) -> Path:
    """The 1024x512 Radiance file of a probe of :data:`PROBES`; Rooitou Park is the embedded
    default probe (the same file, byte for byte), so it is not stored twice."""
    if name not in PROBES:
        raise KeyError(name)
    return default_probe_path() if name == "rooitou_park" else DATA / f"{name}_1k.hdr"
