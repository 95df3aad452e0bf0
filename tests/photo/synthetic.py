"""Synthetic photographs for the photo tests, made here without bakeshop's layout code.

- a camera: a known response ``Z = f(X)`` (a gamma-2.2 curve with a gentle shoulder, none of
  bakeshop's known curves), additive code noise, 8-bit quantisation and clipping;
- probes: the embedded default probe, and the same probe with its sun replaced by a Buie
  sunshape of known irradiance, integrated over each texel by super-sampling;
- a mirror ball photographed by an orthographic camera looking along -Z, rendered by
  ray-sphere reflection per sub-pixel.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from bakeshop.io import read_image
from bakeshop.photo.response import CameraResponse

PROBE = "bakeshop/data/default_probe.hdr"


def camera_curve(x):
    """The test camera's response ``Z = f(X)``, ``X`` clipped to [0, 1]."""
    y = np.clip(x, 0, 1) ** (1 / 2.2)
    return y * (1 + 0.1 * (1 - y))


def camera_inverse(z):
    """``f^-1`` by dense tabulation (f is strictly increasing)."""
    xs = np.linspace(0, 1, 400001)
    return np.interp(z, camera_curve(xs), xs)


def true_response(knots: int = 4096) -> CameraResponse:
    return CameraResponse(
        np.repeat(camera_inverse(np.linspace(0, 1, knots))[:, None], 3, 1), "truth"
    )


def shoot(radiance, times, *, gain=1.0, noise=0.5, seed=0, bits=8):
    """Frames of ``radiance`` at exposure ``times``: codes of ``f(gain * t * L) + noise``."""
    rng = np.random.default_rng(seed)
    top = (1 << bits) - 1
    dtype = np.uint8 if bits == 8 else np.uint16
    frames = []
    for t in times:
        z = camera_curve(np.asarray(radiance, np.float64) * gain * t)
        z = z + rng.normal(0, noise / 255, z.shape)
        frames.append(np.clip(np.rint(z * top), 0, top).astype(dtype))
    return frames


@lru_cache(maxsize=1)
def default_probe() -> np.ndarray:
    return read_image(PROBE)


def latlong_dirs(h, w, oy=0.5, ox=0.5):
    """DESIGN's latlong directions at offsets (oy, ox) inside each texel: (h, w, 3)."""
    v = (np.arange(h) + oy) / h
    u = (np.arange(w) + ox) / w
    theta = np.pi * v[:, None]
    phi = 2 * np.pi * (u[None, :] - 0.5)
    return np.stack(
        np.broadcast_arrays(
            np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)
        ),
        axis=-1,
    )


def latlong_omega(h, w):
    """Exact texel solid angles of a latlong: (h, w)."""
    edges = np.cos(np.pi * np.arange(h + 1) / h)
    return np.broadcast_to(((edges[:-1] - edges[1:]) * 2 * np.pi / w)[:, None], (h, w))


def buie(theta_mrad, chi):
    """Buie et al. 2003 sunshape relative to the disk centre (written out again here)."""
    t = np.asarray(theta_mrad, np.float64)
    gamma = 2.2 * math.log(0.52 * chi) * chi**0.43 - 0.1
    kappa = 0.9 * math.log(13.5 * chi) * chi ** (-0.3)
    disk = np.cos(0.326 * t) / np.cos(0.308 * np.minimum(t, 4.65))
    return np.where(t <= 4.65, disk, math.exp(kappa) * np.maximum(t, 4.65) ** gamma)


SUN_DIRECTION = np.array([0.5, 0.6, -0.6]) / np.linalg.norm([0.5, 0.6, -0.6])
SUN_COLOUR = np.array([1.0, 0.95, 0.85])


#: a sun low over the horizon, its aureole's ring cut by the ground.
LOW_SUN = (0.7, 0.1, -0.7)


@lru_cache(maxsize=2)
def sunny_probe(
    l0: float = 2e5, chi: float = 0.05, reach_deg: float = 15.0, direction: tuple | None = None
):
    """The default probe with its sun painted out and a Buie sun of centre radiance ``l0``
    (colour SUN_COLOUR) at ``direction`` (SUN_DIRECTION by default). Returns ``(probe, sky,
    irradiance (3,))``: the sky alone and the sun's exact irradiance at normal incidence out
    to ``reach_deg``."""
    from bakeshop.light.sun import remove_sun

    sun = SUN_DIRECTION if direction is None else np.asarray(direction) / np.linalg.norm(direction)
    sky, _ = remove_sun(default_probe(), "latlong")
    h, w = sky.shape[:2]
    centre = latlong_dirs(h, w)
    near = centre @ sun > math.cos(math.radians(reach_deg + 1))
    ys, xs = np.nonzero(near)
    n = 24
    acc = np.zeros(ys.size)
    for a in (np.arange(n) + 0.5) / n:
        for b in (np.arange(n) + 0.5) / n:
            v, u = (ys + b) / h, (xs + a) / w
            theta, phi = np.pi * v, 2 * np.pi * (u - 0.5)
            d = np.stack(
                [np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], -1
            )
            ang = np.arccos(np.clip(d @ sun, -1, 1))
            acc += np.where(ang <= math.radians(reach_deg), buie(ang * 1e3, chi), 0.0)
    acc /= n * n
    probe = sky.astype(np.float64)
    probe[ys, xs] += l0 * acc[:, None] * SUN_COLOUR
    t = np.linspace(0, math.radians(reach_deg) * 1e3, 400001)
    f = buie(t, chi) * 2 * np.pi * np.sin(t * 1e-3) * np.cos(t * 1e-3) * 1e-3
    irradiance = l0 * float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t))) * SUN_COLOUR
    return probe.astype(np.float32), sky, irradiance


def sun_irradiance(image, sky, reach_deg: float = 15.0, direction=SUN_DIRECTION) -> np.ndarray:
    """The light above ``sky`` within ``reach_deg`` of ``direction``, at normal incidence."""
    h, w = image.shape[:2]
    d = latlong_dirs(h, w)
    cos = d @ (np.asarray(direction) / np.linalg.norm(direction))
    cap = cos > math.cos(math.radians(reach_deg))
    excess = image[cap].astype(np.float64) - sky[cap]
    return (excess * (latlong_omega(h, w)[cap] * cos[cap])[:, None]).sum(0)


def smooth_probe(d):
    """A smooth environment of positive colours, as a function of direction (..., 3)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(
        [
            1 + 0.5 * x + 0.3 * y * y,
            np.exp(0.8 * z) + 0.2 * np.sin(3 * x),
            1.2 + 0.4 * y + 0.3 * x * z,
        ],
        -1,
    )


def ball_photo(h, w, cx, cy, radius, environment=smooth_probe, *, supersample=4, background=0.3,
               blocker=None):  # fmt: skip
    """A photo of a mirror ball (orthographic camera looking along -Z): each sub-pixel on the
    ball reflects its view ray off the sphere's normal and looks ``environment`` up; off the
    ball, a textured wall. ``blocker(d) -> bool`` marks directions hidden by the photographer
    (seen as black)."""
    image = np.zeros((h, w, 3))
    offsets = (np.arange(supersample) + 0.5) / supersample
    view = np.array([0.0, 0.0, -1.0])
    for oy in offsets:
        for ox in offsets:
            xs, ys = np.meshgrid(np.arange(w) + ox, np.arange(h) + oy)
            a, b = (xs - cx) / radius, (cy - ys) / radius
            inside = a * a + b * b < 1
            normal = np.stack([a, b, np.sqrt(np.clip(1 - a * a - b * b, 0, None))], -1)
            reflected = view - 2 * (normal @ view)[..., None] * normal
            colour = environment(reflected)
            if blocker is not None:
                colour = np.where(blocker(reflected)[..., None], 0.02, colour)
            wall = background * (1 + 0.5 * np.sin(xs / 7.0) * np.cos(ys / 11.0))
            image += np.where(inside[..., None], colour, wall[..., None])
    return (image / supersample**2).astype(np.float32)


def painted_sun_probe(h: int = 256, n: int = 16) -> np.ndarray:
    """A (h, 2h) latlong sky with a sun that is not Buie's: a disk of radiance 8.7e4 and radius
    0.27 degrees (smaller than a texel of a 512-wide latlong) in a power-law aureole (slope
    -2.2) flattened inside 0.5 degrees, over a sky brightening towards it (the red team's). The
    texels within 3 degrees of the sun are averaged over n x n sub-samples."""
    sun = np.array([math.cos(0.5) * math.sin(1.0), math.sin(0.5), -math.cos(0.5) * math.cos(1.0)])

    def radiance(d):
        ang = np.degrees(np.arccos(np.clip(d @ sun, -1, 1)))
        sky = 0.3 + 0.5 * np.clip(d[..., 1], 0, 1) + 0.2 * np.exp(-ang / 20)
        sky = np.where(d[..., 1] < 0, 0.15, sky)
        aureole = np.where(ang > 0.27, 40 * np.clip(ang / 0.5, 1, None) ** -2.2, 8.7e4)
        return sky + aureole

    w = 2 * h
    probe = radiance(latlong_dirs(h, w))
    near = latlong_dirs(h, w) @ sun > math.cos(math.radians(3))
    acc = np.zeros(np.count_nonzero(near))
    for oy in (np.arange(n) + 0.5) / n:
        for ox in (np.arange(n) + 0.5) / n:
            acc += radiance(latlong_dirs(h, w, oy, ox)[near])
    probe[near] = acc / n**2
    return (probe[..., None] * SUN_COLOUR).astype(np.float32)
