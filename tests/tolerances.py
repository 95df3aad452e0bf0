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
