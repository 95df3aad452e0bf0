"""The internal cube ``(6, S, S, C)`` and its pictures (crosses and strips)."""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import ArgumentError, with_article
from bakeshop.sphere import _kinds
from bakeshop.sphere import cube as _cube
from bakeshop.sphere.layouts.base import (
    Layout,
    power_of_two_edge,
)


def _cube_corner(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.arctan2(x * y, np.sqrt(x * x + y * y + 1))


@functools.lru_cache(maxsize=8)
def _cube_face_solid_angles(s: int) -> np.ndarray:
    # exact: the solid angle of [0,x] x [0,y] on the plane at distance 1 is atan(xy/sqrt(1+x^2+y^2))
    e = 2 * np.arange(s + 1) / s - 1
    x, y = e[None, :], e[:, None]
    c = _cube_corner(x, y)
    omega = c[1:, 1:] - c[:-1, 1:] - c[1:, :-1] + c[:-1, :-1]
    omega.setflags(write=False)
    return omega


class Cube(Layout):
    """The internal cube map ``(6, S, S)``: OpenGL order and orientation (see
    :mod:`bakeshop.sphere.cube`). Coordinates are ``(face, x, y)``. Texel solid angles are
    exact: ``atan(xy / sqrt(1 + x^2 + y^2))`` differenced over the texel's corners."""

    name = "cube"
    kind = _kinds.CUBE
    cubic = True

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            if w != h:
                raise ArgumentError(f"cube faces are square; got size {w}x{h}")
            size = w
        n = int(size)
        return self.check_shape((6, n, n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if len(shape) != 3 or shape[0] != 6 or shape[1] != shape[2]:
            raise ArgumentError(f"a cube map is (6, S, S); got spatial shape {shape}")

    def default_size(self, texels: int) -> int:
        return power_of_two_edge(texels / 6)

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        _, s, _ = self.check_shape(shape)
        return np.broadcast_to(_cube_face_solid_angles(s), shape).copy()

    def grid(self, shape: Sequence[int]) -> tuple[int, int, int]:
        _, s, _ = self.check_shape(shape)
        return s, s, 6


class CubeView(Layout):
    """A cube map drawn as one picture: a cross or a strip (see :data:`bakeshop.sphere.cube.VIEWS`).

    Slot F shows face F of the left-handed (directx) face set, as HDRShop and cmft draw them:
    the picture is the world seen from inside the cube, unmirrored, and the centre of a cross
    looks forward (-Z). Texels of the unused squares of a cross are invalid (solid angle 0).
    """

    cubic = False

    def __init__(self, name: str):
        self.name = name
        self.cols, self.rows, _ = _cube.VIEWS[name]

    def shape(self, size: int | tuple[int, int] | list[int]) -> tuple[int, ...]:
        if isinstance(size, (tuple, list)):
            w, h = size
            if w * self.rows != h * self.cols:
                raise ArgumentError(
                    f"{with_article(self.name)} is {self.cols}:{self.rows} (width:height); "
                    f"got size {w}x{h}"
                )
            size = w // self.cols
        n = int(size)
        return self.check_shape((self.rows * n, self.cols * n))

    def _check(self, shape: tuple[int, ...]) -> None:
        if (
            len(shape) != 2
            or shape[0] % self.rows
            or shape[1] % self.cols
            or shape[0] // self.rows != shape[1] // self.cols
        ):
            raise ArgumentError(
                f"{with_article(self.name)} image is {self.rows} x {self.cols} square faces "
                f"(H = {self.rows} S, W = {self.cols} S); got (H, W) = {shape}"
            )

    def face_size(self, shape: Sequence[int]) -> int:
        return self.check_shape(shape)[0] // self.rows

    def default_size(self, texels: int) -> int:
        return power_of_two_edge(texels / 6)

    def directions(self, shape: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        s = self.face_size(shape)
        d = _cube.cube_to_view(CUBE.directions((6, s, s))[0], self.name)
        valid = _cube.cube_to_view(np.ones((6, s, s), bool), self.name, fill=False)
        d[~valid] = (0.0, 0.0, -1.0)
        return d, valid

    def directions_at(self, coords: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        c = np.asarray(coords, dtype=np.float64)
        col = np.clip(np.floor(c[..., 0] / s), 0, self.cols - 1).astype(np.int64)
        row = np.clip(np.floor(c[..., 1] / s), 0, self.rows - 1).astype(np.int64)
        # slot (row, col) -> (internal face or -1, flip x, flip y)
        table = np.full((self.rows, self.cols, 3), -1, dtype=np.int64)
        for g, (sc, sr, fx, fy) in enumerate(_cube.view_slots(self.name)):
            table[sr, sc] = (g, fx, fy)
        face, fx, fy = (table[row, col, k] for k in range(3))
        x, y = c[..., 0] - col * s, c[..., 1] - row * s
        x = np.where(fx == 1, s - x, x)
        y = np.where(fy == 1, s - y, y)
        d = CUBE.directions_at(np.stack([np.maximum(face, 0), x, y], axis=-1), (6, s, s))
        return np.where((face < 0)[..., None], np.array([0.0, 0.0, -1.0]), d)

    def solid_angles(self, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        return _cube.cube_to_view(CUBE.solid_angles((6, s, s)), self.name)

    def coordinates(self, dirs: ArrayLike, shape: Sequence[int]) -> np.ndarray:
        s = self.face_size(shape)
        c = CUBE.coordinates(dirs, (6, s, s))
        face, x, y = c[..., 0].astype(np.int64), c[..., 1], c[..., 2]
        slots = np.array(_cube.view_slots(self.name), dtype=np.int64)[face]
        col, row, fx, fy = (slots[..., k] for k in range(4))
        x = np.where(fx == 1, s - x, x) + col * s
        y = np.where(fy == 1, s - y, y) + row * s
        return np.stack([x, y], axis=-1)

    @property
    def base(self) -> Layout:
        return CUBE

    def prepare(self, image: np.ndarray) -> np.ndarray:
        return _cube.view_to_cube(image, self.name)

    def base_shape(self, shape: Sequence[int]) -> tuple[int, ...]:
        return CUBE.shape(self.face_size(shape))


CUBE = Cube()
