"""The layouts' kind numbers, by which the kernels of :mod:`bakeshop.sphere._maps` name a layout,
apart from those kernels so that the layout classes load without numba."""

(
    LATLONG,
    ANGULAR,
    MIRRORBALL,
    DUAL_PARABOLOID,
    OCTAHEDRAL,
    CUBE,
    ANGULAR_PHYSICAL,
    MIRRORBALL_PHYSICAL,
    OPENEXR_LATLONG,
    OPENEXR_CUBE,
) = range(10)

#: a disk texel is valid when it reaches this far (in r^2) into the disk: texels that only
#: touch the rim (solid angle below ~1e-13 of the texel's) are left out.
DISK_OVERLAP_EPS = 1e-9
