"""Every numerical tolerance the tests use, named once (as colour-science keeps them)."""

#: float32 round trip through a lossless float codec: bit-exact.
EXACT = 0.0

#: float32 evaluation of a closed-form transfer curve vs a float64 reference (relative).
FLOAT32_CURVE_RTOL = 2e-6
#: OpenImageIO's built-in linear -> sRGB conversion vs the exact IEC formula (absolute).
OIIO_SRGB_ATOL = 2e-5

#: one float32 rounding of a value of order 1 (relative).
FLOAT32_VALUE = 1e-6
#: the mean of an image after resampling, relative (the issue asks 1e-5; float32 gives ~1e-7).
FLOAT32_MEAN = 1e-6

#: DFG terms by 4096-sample Hammersley importance sampling vs brute-force quadrature (absolute).
DFG_QUADRATURE_ATOL = 4e-3
#: Karis' analytic fit (after Lazarov 2013) vs UE4's Schlick-Smith DFG table: RMS over the table
#: and worst texel (absolute). The fit is loose: its own author quotes it as approximate.
DFG_FIT_RMS = 0.08
DFG_FIT_MAX = 0.21

#: exact Fresnel reflectance vs the amplitude (rs, rp) equations, both float64 (absolute).
FRESNEL_AMPLITUDE_ATOL = 1e-7
