"""Every numerical tolerance the tests use, named once (as colour-science keeps them)."""

#: float32 round trip through a lossless float codec: bit-exact.
EXACT = 0.0

#: float32 evaluation of a closed-form transfer curve vs a float64 reference (relative).
FLOAT32_CURVE_RTOL = 2e-6
#: OpenImageIO's built-in linear -> sRGB conversion vs the exact IEC formula (absolute).
OIIO_SRGB_ATOL = 2e-5
