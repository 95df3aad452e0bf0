"""Voxelisation of a closed mesh into buoyancy sample points.

The mesh's bounding box is cut into cubic cells; each cell that holds some of the solid becomes
one sample point at the centroid of its inside part, carrying the inside volume. Inside volume
is integrated by casting vertical rays through a grid of ``subsamples x subsamples`` columns per
cell: along each ray the solid's extent is exact (the crossings of the ray with the triangles,
signed by the triangle's facing, give a winding number), so only the horizontal integral is
sampled (midpoint rule). Volumes therefore converge quickly to the mesh volume and are exact for
boxes aligned with the grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    import trimesh

#: Upper bound on cells (points before culling) so a typo cannot allocate gigabytes.
MAX_CELLS = 4_000_000


@dataclass(frozen=True)
class SamplePoints:
    """Buoyancy sample points of one body, in the mesh's frame.

    Attributes
    ----------
    positions : (N, 3) float64
        Centroid of the inside part of each cell, metres.
    volumes : (N,) float64
        Inside volume of each cell, m^3; sums to the mesh volume (within the sampling error).
    heights : (N,) float64
        Height of the vertical column each point stands for, metres: its volume divided by the
        horizontal area of its cell that holds some solid (the cell side for a full cell, less
        where the solid ends inside the cell, e.g. at the bottom of a sphere).
    cell : float
        Cell side, metres.
    """

    positions: np.ndarray
    volumes: np.ndarray
    heights: np.ndarray
    cell: float

    def __len__(self) -> int:
        return len(self.volumes)


def sample_points(
    mesh: trimesh.Trimesh, *, resolution: int = 10, subsamples: int = 4
) -> SamplePoints:
    """Voxelise a closed mesh into sample points with the volume of their cell's inside.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Closed, outward-oriented mesh (as :func:`bakeshop.buoyancy.shapes.load_mesh` returns).
    resolution : int
        Cells along the longest side of the bounding box; the cell side is
        ``max(extents) / resolution``.
    subsamples : int
        Vertical rays per cell along X and along Z (``subsamples**2`` rays per cell).

    Returns
    -------
    SamplePoints
    """
    if not (isinstance(resolution, int | np.integer) and 1 <= resolution <= 1000):
        raise ArgumentError(f"resolution must be an integer in 1..1000, got {resolution!r}")
    if not (isinstance(subsamples, int | np.integer) and 1 <= subsamples <= 64):
        raise ArgumentError(f"subsamples must be an integer in 1..64, got {subsamples!r}")
    lo, hi = mesh.bounds
    cell = float((hi - lo).max()) / resolution
    shape = np.maximum(np.ceil((hi - lo) / cell - 1e-9).astype(np.int64), 1)
    if int(np.prod(shape)) > MAX_CELLS:
        raise ArgumentError(f"{int(np.prod(shape))} cells exceed the limit of {MAX_CELLS}")
    triangles = np.ascontiguousarray(mesh.triangles, dtype=np.float64)
    # A tiny irrational offset keeps rays off vertices and edges that sit on grid lines.
    jitter = cell * np.array([1.2345678e-7, 0.0, 2.7182818e-7])
    volume, moment, area = _voxelise(triangles, lo + jitter, cell, shape, subsamples)
    keep = volume > 1e-12 * cell**3
    volumes = volume[keep]
    positions = moment[keep] / volumes[:, None]
    heights = np.minimum(volumes / area[keep], cell)
    return SamplePoints(positions=positions - jitter, volumes=volumes, heights=heights, cell=cell)


@numba.njit(cache=True)
def _crossings(
    triangles: np.ndarray,
    x0: float,
    z0: float,
    step: float,
    nx: int,
    nz: int,
    counts: np.ndarray,
    hits_y: np.ndarray,
    hits_w: np.ndarray,
    offsets: np.ndarray,
    fill: bool,
) -> None:
    """Intersect every vertical ray (i, k) at (x0 + (i+0.5) step, z0 + (k+0.5) step) with the
    triangles. With ``fill`` False only count per ray; with True write height and winding sign
    (+1 entering the solid going up, -1 leaving) into the CSR arrays."""
    for t in range(triangles.shape[0]):
        ax, ay, az = triangles[t, 0, 0], triangles[t, 0, 1], triangles[t, 0, 2]
        bx, by, bz = triangles[t, 1, 0], triangles[t, 1, 1], triangles[t, 1, 2]
        cx, cy, cz = triangles[t, 2, 0], triangles[t, 2, 1], triangles[t, 2, 2]
        # y component of (b - a) x (c - a): sign tells up- or down-facing.
        ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az)
        if ny == 0.0:
            continue
        sign = -1 if ny > 0 else 1
        i0 = max(int(np.ceil((min(ax, bx, cx) - x0) / step - 0.5)), 0)
        i1 = min(int(np.floor((max(ax, bx, cx) - x0) / step - 0.5)), nx - 1)
        k0 = max(int(np.ceil((min(az, bz, cz) - z0) / step - 0.5)), 0)
        k1 = min(int(np.floor((max(az, bz, cz) - z0) / step - 0.5)), nz - 1)
        for i in range(i0, i1 + 1):
            px = x0 + (i + 0.5) * step
            for k in range(k0, k1 + 1):
                pz = z0 + (k + 0.5) * step
                # Barycentric weights of (px, pz) in the projected triangle.
                wa = ((bz - pz) * (cx - px) - (bx - px) * (cz - pz)) / ny
                wb = ((cz - pz) * (ax - px) - (cx - px) * (az - pz)) / ny
                wc = 1.0 - wa - wb
                if wa < 0.0 or wb < 0.0 or wc < 0.0:
                    continue
                ray = i * nz + k
                if fill:
                    j = offsets[ray] + counts[ray]
                    hits_y[j] = wa * ay + wb * by + wc * cy
                    hits_w[j] = sign
                counts[ray] += 1


@numba.njit(cache=True, parallel=True)
def _accumulate(
    hits_y: np.ndarray,
    hits_w: np.ndarray,
    offsets: np.ndarray,
    x0: float,
    y0: float,
    z0: float,
    cell: float,
    shape: np.ndarray,
    sub: int,
    volume: np.ndarray,
    moment: np.ndarray,
    area: np.ndarray,
) -> None:
    """Integrate the inside intervals of every ray into the cells (one thread per cell column):
    volume, first moments and the horizontal area of rays that meet solid in the cell."""
    nx, ny, nz = shape[0], shape[1], shape[2]
    last_ray = np.full(nx * ny * nz, -1, dtype=np.int64)
    step = cell / sub
    ray_area = step * step
    for c in numba.prange(nx * nz):
        ci = c // nz
        ck = c % nz
        for si in range(sub):
            i = ci * sub + si
            px = x0 + (i + 0.5) * step
            for sk in range(sub):
                k = ck * sub + sk
                pz = z0 + (k + 0.5) * step
                ray = i * (nz * sub) + k
                start, stop = offsets[ray], offsets[ray + 1]
                if stop - start < 2:
                    continue
                order = np.argsort(hits_y[start:stop]) + start
                winding = 0
                for h in range(len(order) - 1):
                    winding += hits_w[order[h]]
                    if winding <= 0:
                        continue
                    ya = hits_y[order[h]]
                    yb = hits_y[order[h + 1]]
                    ja = max(int((ya - y0) / cell), 0)
                    jb = min(int((yb - y0) / cell), ny - 1)
                    for j in range(ja, jb + 1):
                        lo = max(ya, y0 + j * cell)
                        hi = min(yb, y0 + (j + 1) * cell)
                        if hi <= lo:
                            continue
                        v = (hi - lo) * ray_area
                        cell_index = (ci * ny + j) * nz + ck
                        if last_ray[cell_index] != ray:
                            last_ray[cell_index] = ray
                            area[cell_index] += ray_area
                        volume[cell_index] += v
                        moment[cell_index, 0] += v * px
                        moment[cell_index, 1] += v * 0.5 * (lo + hi)
                        moment[cell_index, 2] += v * pz


def _voxelise(
    triangles: np.ndarray, origin: np.ndarray, cell: float, shape: np.ndarray, sub: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    nx, nz = int(shape[0]) * sub, int(shape[2]) * sub
    step = cell / sub
    counts = np.zeros(nx * nz, dtype=np.int64)
    empty_f, empty_i = np.zeros(0), np.zeros(0, dtype=np.int64)
    _crossings(
        triangles, origin[0], origin[2], step, nx, nz, counts, empty_f, empty_i, counts, False
    )
    offsets = np.zeros(nx * nz + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    hits_y = np.empty(offsets[-1])
    hits_w = np.empty(offsets[-1], dtype=np.int64)
    counts[:] = 0
    _crossings(triangles, origin[0], origin[2], step, nx, nz, counts, hits_y, hits_w, offsets, True)
    n_cells = int(np.prod(shape))
    volume = np.zeros(n_cells)
    moment = np.zeros((n_cells, 3))
    area = np.zeros(n_cells)
    _accumulate(
        hits_y,
        hits_w,
        offsets,
        origin[0],
        origin[1],
        origin[2],
        cell,
        np.asarray(shape, dtype=np.int64),
        sub,
        volume,
        moment,
        area,
    )
    return volume, moment, area
