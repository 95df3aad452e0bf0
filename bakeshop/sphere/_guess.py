"""The layouts an image's shape can be (no geometry: the command line's ``info`` reads it
without loading the sampling kernels)."""

from __future__ import annotations

from bakeshop.sphere.cube import VIEWS


def guess_layout(height: int, width: int) -> list[str]:
    """Layouts whose images have this shape, the likely one first.

    A 2:1 image is taken for a latlong (a dual-paraboloid map and OpenEXR's latlong have the
    same shape: name them, or let an .exr's envmap attribute say); a square is ambiguous
    (angular, mirror ball, octahedral, or a probe's physical variant) and every candidate is
    returned, so that the caller can ask; 3:4, 4:3, 6:1 and 1:6 are the cube's crosses and
    strips (1:6 is also OpenEXR's cube, which its envmap attribute names). An empty list means
    no layout has that shape.
    """
    h, w = int(height), int(width)
    if h < 1 or w < 1:
        return []
    if w == 2 * h:
        return ["latlong"]
    if w == h:
        disks = ["angular", "mirrorball"]
        physical = ["angular-physical", "mirrorball-physical"]
        return disks + (["octahedral"] if h % 2 == 0 else []) + physical
    for name, (cols, rows, _) in VIEWS.items():
        if h * cols == w * rows and h % rows == 0:
            return [name]
    return []
