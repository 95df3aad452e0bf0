"""Water: tileable, time-looping ocean fields, impact ripples and underwater murk (SI units).

Import from the submodules, each named for what it holds:

- :mod:`bakeshop.water.spectra`: dispersion and the Phillips, Pierson-Moskowitz, JONSWAP and
  TMA spectra with directional spreading (:class:`~bakeshop.water.spectra.Spectrum`).
- :mod:`bakeshop.water.ocean`: FFT synthesis on a tileable patch, quantised to loop in time;
  heights, exact spectral slopes, choppy displacement, the Jacobian and normals.
"""
