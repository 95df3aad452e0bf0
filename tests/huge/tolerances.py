"""Tolerances of the chunked (out-of-core) engine's tests."""

#: chunked results whose arithmetic is the in-memory one's, in the same order: bit-exact.
BIT_EXACT = 0.0
#: chunked sums taken strip by strip vs the same sums in one pass (float64 partials, float32
#: results), relative to the result's largest value.
PARTIAL_SUMS = 1e-6
#: the chunked supersampled area filter vs the in-memory one, RMS relative to the image's RMS:
#: the in-memory kernel interpolates its samples' coordinates (within 0.05 texel) where a texel
#: has 3 x 3 samples or more, the tiles compute each (measured 5.7e-5 to 8.7e-5; 4e-9 when
#: both compute each).
SUPERSAMPLE_TILES_RMS = 3e-4
#: the energy of the supersampled area filter (radiance x solid angle), relative: the bright
#: texels' excess is deposited exactly, the rest is sampled (measured 3e-6 to 2.5e-5).
SUPERSAMPLE_ENERGY = 1e-4
#: energy (radiance x solid angle, or the planar sum) through a chunked resize, relative.
ENERGY = 1e-6
#: chunked DIM "auto" (bins split per strip) vs in-memory "exact", worst texel relative to the
#: DIM's largest (the in-memory auto bound, tests/light).
AUTO_VS_EXACT = 2e-3
