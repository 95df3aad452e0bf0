"""Water: tileable, time-looping ocean fields, impact ripples and underwater murk (SI units).

The submodules, each named for what it holds:

- :mod:`bakeshop.water.spectra`: dispersion and the Phillips, Pierson-Moskowitz, JONSWAP and
  TMA spectra with directional spreading (:class:`~bakeshop.water.spectra.Spectrum`).
- :mod:`bakeshop.water.ocean`: FFT synthesis on a tileable patch, quantised to loop in time;
  heights, exact spectral slopes, choppy displacement, the Jacobian and normals.
- :mod:`bakeshop.water.amplitudes`: the seeded, resolution-independent amplitudes of the modes.
- :mod:`bakeshop.water.cascades`: patches of several sizes splitting one spectrum.
- :mod:`bakeshop.water.gerstner`: the lattice's waves summed directly (Gerstner waves).
- :mod:`bakeshop.water.textures`: engine textures (packed and BC5-ready normals, foam, flipbook
  atlases, mips, previews, the JSON sidecar's contents).
- :mod:`bakeshop.water.ripples`: the analytic ring of a drop, its shader tables, and a wave
  equation for many impacts.
- :mod:`bakeshop.water.murk`: beam and diffuse attenuation per sRGB channel from measured
  spectra (Pope & Fry, Jerlov), paths under water, LUTs and engine constants.
- :mod:`bakeshop.water.shader`: the reference GLSL water shader and an offscreen renderer.

The compiled kernels of these modules are in ``_native`` (C++, ``src/water/``).

The most used names are re-exported here.
"""

from bakeshop.water.murk import water
from bakeshop.water.ocean import Ocean, ocean, ocean_fields, ocean_frames
from bakeshop.water.ripples import Crater, WaveEquation, drop_crater, ring
from bakeshop.water.spectra import Spectrum, dispersion

__all__ = [
    "Spectrum",
    "dispersion",
    "Ocean",
    "ocean",
    "ocean_frames",
    "ocean_fields",
    "Crater",
    "drop_crater",
    "ring",
    "WaveEquation",
    "water",
]
