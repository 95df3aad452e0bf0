"""The layouts' kind numbers, by which the compiled kernels (``src/sphere/maps.hpp``) name a
layout."""

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
