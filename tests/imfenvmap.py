"""OpenEXR's environment mappings read from ``ImfEnvmap.h`` (OpenEXR 3.x), for tests.

Written from the header's definitions (and ImfEnvmap.cpp's) in numpy, independently of bakeshop's
layouts, in OpenEXR's own terms: *pixel positions* in the data window (pixel ``(x, y)``'s centre
is at ``(x, y)``; the data window's origin is 0 here) and directions in OpenEXR's frame
(right-handed, +Y up, which is bakeshop's); and exrenvmap's bilinear point lookup.
"""

import numpy as np

# --- latitude-longitude -------------------------------------------------------------------------


def latlong_direction(w, h, x, y):
    """``LatLongMap::direction``: pixel (x, y) of a w x h map. Pixel (0, 0) has latitude +pi/2
    and longitude +pi, pixel (w - 1, h - 1) latitude -pi/2 and longitude -pi; latitude 0,
    longitude 0 is +z and longitude pi/2 is +x."""
    lat = -np.pi * (np.asarray(y, float) / (h - 1) - 0.5)
    lon = -2 * np.pi * (np.asarray(x, float) / (w - 1) - 0.5)
    return np.stack([np.sin(lon) * np.cos(lat), np.sin(lat), np.cos(lon) * np.cos(lat)], -1)


def latlong_position(w, h, d):
    """``LatLongMap::pixelPosition`` of directions d (..., 3): (x, y)."""
    d = np.asarray(d, float)
    length = np.linalg.norm(d, axis=-1)
    r = np.hypot(d[..., 2], d[..., 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        lat = np.where(
            r < np.abs(d[..., 1]),
            np.arccos(np.clip(r / length, -1, 1)) * np.sign(d[..., 1]),
            np.arcsin(np.clip(d[..., 1] / length, -1, 1)),
        )
    lon = np.where((d[..., 2] == 0) & (d[..., 0] == 0), 0.0, np.arctan2(d[..., 0], d[..., 2]))
    x = lon / (-2 * np.pi) + 0.5
    y = lat / -np.pi + 0.5
    return np.stack([x * (w - 1), y * (h - 1)], -1)


# --- cube ---------------------------------------------------------------------------------------

#: ``CubeMapFace``: +X, -X, +Y, -Y, +Z, -Z, stacked top to bottom.
FACES = 6


def cube_direction(s, face, px, py):
    """``CubeMap::direction`` of position (px, py) in face ``face`` of an s x s face (not
    normalised): the face's axis, and the two other coordinates ``p / (s - 1) * 2 - 1``."""
    a = np.asarray(px, float) / (s - 1) * 2 - 1
    b = np.asarray(py, float) / (s - 1) * 2 - 1
    one = np.ones_like(a)
    axis, sign = divmod(face, 2)
    sign = -1.0 if sign else 1.0
    if axis == 0:  # x faces: (+-1, a, b)
        return np.stack([sign * one, a, b], -1)
    if axis == 1:  # y faces: (a, +-1, b)
        return np.stack([a, sign * one, b], -1)
    return np.stack([a, b, sign * one], -1)  # z faces: (a, b, +-1)


def cube_pixel_position(s, face, px, py):
    """``CubeMap::pixelPosition``: where position (px, py) of face ``face`` is stored in the
    stacked s x 6s image, (x, y). Face ``f`` occupies rows f s .. f s + s - 1."""
    px, py = np.asarray(px, float), np.asarray(py, float)
    top, bottom, left, right = face * s, face * s + s - 1, 0, s - 1
    x, y = {
        0: (left + py, bottom - px),  # +X
        1: (right - py, bottom - px),  # -X
        2: (left + px, bottom - py),  # +Y
        3: (left + px, top + py),  # -Y
        4: (right - px, bottom - py),  # +Z
        5: (left + px, bottom - py),  # -Z
    }[face]
    return np.stack([x, y], -1)


def cube_face_and_position(s, d):
    """``CubeMap::faceAndPixelPosition``: (face, px, py) of directions d (..., 3); the major
    axis picks the face (ties: x, then y)."""
    d = np.asarray(d, float)
    ax, ay, az = np.abs(d[..., 0]), np.abs(d[..., 1]), np.abs(d[..., 2])
    use_x = (ax >= ay) & (ax >= az)
    use_y = ~use_x & (ay >= az)
    face = np.where(use_x, np.where(d[..., 0] > 0, 0, 1),
                    np.where(use_y, np.where(d[..., 1] > 0, 2, 3),
                             np.where(d[..., 2] > 0, 4, 5)))  # fmt: skip
    m = np.where(use_x, ax, np.where(use_y, ay, az))
    u = np.where(use_x, d[..., 1], d[..., 0]) / m
    v = np.where(use_x | use_y, d[..., 2], d[..., 1]) / m
    return face, (u + 1) / 2 * (s - 1), (v + 1) / 2 * (s - 1)


def cube_position(s, d):
    """``faceAndPixelPosition`` then ``pixelPosition``: (x, y) in the stacked image."""
    face, px, py = cube_face_and_position(s, d)
    out = np.empty(face.shape + (2,))
    for f in range(FACES):
        sel = face == f
        out[sel] = cube_pixel_position(s, f, px[sel], py[sel])
    return out


def cube_directions(s):
    """The (unit) direction of every pixel of a stacked (6 s, s) cube image, by ImfEnvmap."""
    out = np.empty((6 * s, s, 3))
    py, px = np.meshgrid(np.arange(s), np.arange(s), indexing="ij")
    for f in range(FACES):
        d = cube_direction(s, f, px, py)
        x, y = np.moveaxis(cube_pixel_position(s, f, px, py), -1, 0).astype(int)
        out[y, x] = d / np.linalg.norm(d, axis=-1, keepdims=True)
    return out


# --- exrenvmap's lookup -------------------------------------------------------------------------


def sample(image, pos):
    """``EnvmapImage::sample``: bilinear at pixel positions (..., 2), neighbours clamped to the
    image (no wrapping)."""
    h, w = image.shape[:2]
    x, y = pos[..., 0], pos[..., 1]
    x1, y1 = np.floor(x).astype(int), np.floor(y).astype(int)
    tx, ty = (x - x1)[..., None], (y - y1)[..., None]
    xa, xb = np.clip(x1, 0, w - 1), np.clip(x1 + 1, 0, w - 1)
    ya, yb = np.clip(y1, 0, h - 1), np.clip(y1 + 1, 0, h - 1)
    top = image[ya, xa] * (1 - tx) + image[ya, xb] * tx
    bottom = image[yb, xa] * (1 - tx) + image[yb, xb] * tx
    return top * (1 - ty) + bottom * ty
