"""Tolerances of the water tests, named once (units in each comment)."""

#: float64 FFT fields vs brute-force float64 sums over the same modes (relative to the field's
#: largest value).
FFT_VS_SUM_RTOL = 1e-12
#: loop closure and tile seams in float32 output: |difference| relative to the field's largest
#: value (the issue's bound).
FLOAT32_FIELD = 1e-6
#: angle between normals, radians: loop closure in float32 (the issue's bound).
LOOP_ANGLE_RAD = 1e-6
#: spectral normals vs central differences of the height (step 1e-4 m) of one mode, radians.
SLOPE_ANGLE_RAD = 1e-4
#: angle after 8-bit (xyz) or two-channel 8-bit (xy, z rebuilt) encoding, degrees.
ENCODED_SEAM_DEG = 0.5
#: measured directional band power vs the target spectrum, relative (the issue's 5 %).
BAND_POWER_RTOL = 0.05
#: Hs measured over seeds vs 4 sqrt(m0) of the closed form (sampling of a finite patch).
HS_RTOL = 0.03
#: imaginary part of a single field's inverse FFT, relative to its largest real value.
IMAGINARY_RESIDUE = 1e-6
#: Gerstner normal vs the cross product of finite-difference tangents (step 1e-5 m), radians.
GERSTNER_FD_RAD = 1e-6
#: analytic ring (Hankel quadrature) vs a 1024^2 FFT solution of the same problem (relative to
#: the ring's largest height; the FFT grid's bicubic sampling dominates).
RING_VS_FFT_RTOL = 2e-3
#: wave equation, crest speed vs c (the crest of a 12-cell dent, 20 to 40 dent widths out).
WAVE_SPEED_RTOL = 0.01
#: crest travel along the diagonal vs along the axis (the issue's 1 %).
WAVE_ISOTROPY_RTOL = 0.01
#: crest amplitude times sqrt(r) from 20 to 40 dent widths out (damping off).
WAVE_AMPLITUDE_RTOL = 0.05
#: wave equation vs the continuous equation's exact solution, relative to its largest value
#: (leapfrog dispersion at 12 cells per dent width, Courant 0.3, after 40 dent widths).
WAVE_EXACT_RTOL = 0.06
#: Wyman-Sloan-Shirley multi-lobe CMF fit vs the CIE 1931 2-degree table (absolute; the
#: functions peak at 1.06, 1.00 and 1.78).
CMF_FIT_ATOL = 0.03
#: the refracted underwater path vs a brute-force minimum of the optical path on a 1e-6 grid.
PATH_RTOL = 1e-6
#: shader-decoded normals from a two-channel 8-bit array vs brute-force sums, degrees (8-bit
#: quantisation with z rebuilt, float32 texture sampling).
SHADER_NORMAL_DEG = 0.6
#: shader's refracted underwater path vs Fermat's principle (float32 in the driver).
SHADER_PATH_RTOL = 1e-4
#: shader's ripple slope from the 512x512 ring LUT vs the analytic ring (bilinear in r and t),
#: relative to the largest slope.
SHADER_RIPPLE_RTOL = 0.03
