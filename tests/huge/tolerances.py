"""Tolerances of the chunked (out-of-core) engine's tests."""

#: chunked results whose arithmetic is the in-memory one's, in the same order: bit-exact.
BIT_EXACT = 0.0
#: chunked sums taken strip by strip vs the same sums in one pass (float64 partials, float32
#: results), relative to the result's largest value.
PARTIAL_SUMS = 1e-6
#: the solid-angle reduction vs the in-memory area filter (float32 weights) on a latlong, RMS
#: relative to the image's RMS.
AREA_LATLONG_RMS = 1e-4
#: energy (radiance x solid angle, or the planar sum) through a chunked resize, relative.
ENERGY = 1e-6
#: chunked DIM "auto" (bins split per strip) vs in-memory "exact", worst texel relative to the
#: DIM's largest (the in-memory auto bound, tests/light).
AUTO_VS_EXACT = 2e-3
