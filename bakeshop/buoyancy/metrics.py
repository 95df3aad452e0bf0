"""What the test bench measures in a :class:`~bakeshop.buoyancy.stepping.Trace`.

The body's *clearance* is the height of its lowest point (the lowest vertex of its convex hull)
above the water surface there; the body is in the water while the clearance is negative. The
*draft* is minus the clearance.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from bakeshop.buoyancy import _native
from bakeshop.buoyancy.hydrostatics import archimedes_draft
from bakeshop.buoyancy.state import quaternion_to_matrix

if TYPE_CHECKING:
    from bakeshop.buoyancy.forces import ForceModel
    from bakeshop.buoyancy.mass import Fleet
    from bakeshop.buoyancy.stepping import Trace
    from bakeshop.buoyancy.water import Water

#: Fraction of a run, at its end, over which the settled draft is averaged.
SETTLED_WINDOW = 0.25


def clearance(fleet: Fleet, trace: Trace, water: Water) -> np.ndarray:
    """(S, B) height (m) of each body's lowest point above the water surface below it."""
    out = np.empty(trace.position.shape[:2])
    for b, body in enumerate(fleet.bodies):
        # the world position of the lowest hull vertex at each recorded step
        p = np.empty((trace.position.shape[0], 3))
        _native.lowest_points(
            np.ascontiguousarray(body.hull_vertices, dtype=np.float64),
            np.ascontiguousarray(trace.quaternion[:, b]),
            np.ascontiguousarray(trace.position[:, b]),
            p,
        )
        out[:, b] = p[:, 1] - water.height(p[:, 0], p[:, 2], trace.time)
    return out


def energy(fleet: Fleet, trace: Trace, water: Water, model: ForceModel) -> np.ndarray:
    """(S, B) total mechanical energy (J) in calm water: kinetic + gravity + buoyancy potential.

    The buoyancy of a column point of volume V, height h, centre y has the potential
    ``rho g V G(y)`` with ``G' = -f`` (f the submerged fraction): ``G = (eta + h/2 - y)^2 / (2h)``
    while the column crosses the surface, ``eta - y`` below it, 0 above. Without damping and
    waves the total is conserved by the exact dynamics.
    """
    rho, g = model.rho_water, model.gravity
    rot = quaternion_to_matrix(trace.quaternion)  # (S, B, 3, 3)
    out = np.empty(trace.position.shape[:2])
    for b, body in enumerate(fleet.bodies):
        pts = fleet.points[fleet.offsets[b] : fleet.offsets[b + 1]]
        vol = fleet.volumes[fleet.offsets[b] : fleet.offsets[b + 1]]
        h = fleet.heights[fleet.offsets[b] : fleet.offsets[b + 1]]
        y = np.einsum("sj,vj->sv", rot[:, b, 1, :], pts) + trace.position[:, b, 1, None]
        depth = water.level - y
        g_col = np.where(
            depth >= h / 2, depth, np.where(depth <= -h / 2, 0.0, (depth + h / 2) ** 2 / (2 * h))
        )
        w_body = np.einsum("sji,sj->si", rot[:, b], trace.angular_velocity[:, b])
        kinetic = 0.5 * body.mass * (trace.velocity[:, b] ** 2).sum(-1)
        kinetic += 0.5 * np.einsum("si,ij,sj->s", w_body, body.inertia, w_body)
        out[:, b] = kinetic + body.mass * g * trace.position[:, b, 1] + rho * g * g_col @ vol
    return out


def summarize(
    fleet: Fleet, trace: Trace, water: Water, model: ForceModel, *, settle_tolerance: float = 0.01
) -> list[dict]:
    """The test bench's numbers for each body.

    Returns
    -------
    list of dict
        Per body: ``volume_m3``, ``mass_kg``, ``points``, ``archimedes_draft_m`` (exact, in the
        orientation the body ended in, calm water; None if the body sinks), ``draft_m`` (mean
        over the last quarter of the run), ``times_left_water`` (times the body came fully out
        of the water after first entering it), ``max_jump_m`` (highest clearance after first
        entering), ``settle_time_s`` (when the centre of mass last strayed more than
        ``settle_tolerance`` times the body's size from its final mean, or None if it never
        settled).
    """
    clear = clearance(fleet, trace, water)
    t = trace.time
    window = t >= t[-1] * (1 - SETTLED_WINDOW)
    out = []
    for b, body in enumerate(fleet.bodies):
        rot = quaternion_to_matrix(trace.quaternion[-1, b])
        tri = body.mesh.triangles @ rot.T
        arch = archimedes_draft(tri, body.mass, rho_water=model.rho_water)
        c = clear[:, b]
        wet = c < 0
        entered = int(np.argmax(wet)) if wet.any() else len(c)
        after = c[entered:]
        left = int(np.count_nonzero(np.diff((after >= 0).astype(np.int8)) == 1))
        size = float(body.mesh.extents.max())
        final = trace.position[window, b].mean(axis=0)
        stray = np.linalg.norm(trace.position[:, b] - final, axis=1) > settle_tolerance * size
        if stray[window].any():
            settle = None
        else:
            settle = float(t[np.nonzero(stray)[0][-1] + 1]) if stray.any() else 0.0
        out.append(
            {
                "volume_m3": body.volume,
                "mass_kg": body.mass,
                "points": len(body.points),
                "archimedes_draft_m": arch,
                "draft_m": float(-c[window].mean()),
                "times_left_water": left,
                "max_jump_m": float(max(after.max(), 0.0)) if after.size else 0.0,
                "settle_time_s": settle,
            }
        )
    return out
