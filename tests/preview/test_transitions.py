"""Probe transitions: weights that sum to 1 and move continuously, a blended walk against
snapping, and the proof that blending bakes is baking the blend."""

import numpy as np
import pytest

from bakeshop.light import bake_probe
from bakeshop.preview import bake_from_arrays
from bakeshop.preview.transitions import blend_bakes, influence_weights, path_weights, walk
from bakeshop.sphere import layout
from tests.preview.bakes import sky

PROBES = np.array([[0.0, 1.0, 0.0], [20.0, 1.0, 0.0], [40.0, 1.0, 5.0]])
PATH = np.stack([np.linspace(-5, 45, 501), np.full(501, 1.5), np.linspace(0, 5, 501)], -1)
#: blend of bakes vs bake of the blend, relative to the probe's peak radiance (the sun's): the
#: float32 rounding of sums over a texel's footprint that hold the sun (measured 1e-7).
LINEAR_PEAK = 1e-6


@pytest.mark.parametrize(
    "options",
    [
        {"method": "inverse-distance"},
        {"method": "volumes", "radii": [14.0, 14.0, 14.0], "blend_distance": 6.0},
        {"method": "volumes", "radii": [14.0, 30.0, 14.0], "blend_distance": [6, 10, 6],
         "priority": [1, 0, 1]},
    ],
)  # fmt: skip
def test_weights_sum_to_one_and_move_continuously(options):
    w = path_weights(PATH, PROBES, **options)
    assert w.shape == (len(PATH), 3)
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-12)
    assert (w >= 0).all()
    # a step of 0.1 m moves no weight by more than the steepest ramp allows (no jump)
    step = np.linalg.norm(np.diff(PATH, axis=0), axis=1).max()
    assert np.abs(np.diff(w, axis=0)).max() < 0.1
    assert step < 0.11


def test_volumes_with_priority_give_the_inner_probe_its_whole_share():
    """Deep inside a high-priority volume its probe takes everything, whatever lower-priority
    volume also covers the point; in its blend band the rest goes to the lower one."""
    centres, radii = PROBES[:2], [10.0, 100.0]
    w = influence_weights([[1.0, 1.0, 0.0], [7.0, 1.0, 0.0]], centres, radii,
                          blend_distance=4.0, priority=[1, 0])  # fmt: skip
    np.testing.assert_allclose(w[0], [1.0, 0.0])
    # 7 m from the first: raw (10 - 7) / 4 = 0.75 for it, the rest for the big volume
    np.testing.assert_allclose(w[1], [0.75, 0.25])


def _probe(shift, sun):
    d, _ = layout("latlong").directions((32, 64))
    p = sky(d) * (1 + shift) + 0.2 * shift * np.roll(sky(d), 9, axis=1)
    return (p + 4000.0 * ((d @ sun) > np.cos(np.radians(3)))[..., None]).astype(np.float32)


SMALL = {"cube_size": 16, "dim_size": (32, 16), "specular_size": 16, "mips": 3, "dfg_size": 16}


@pytest.mark.slow
def test_blending_bakes_is_baking_the_blend():
    """bake(a P1 + b P2) = a bake(P1) + b bake(P2) for the cube, the GGX chain, the radiance SH
    and the sun DIM (two probes with different suns); the shadow DIM is each probe's own and is
    not."""
    s1 = np.array([0.5, 0.6, -0.6]) / np.linalg.norm([0.5, 0.6, -0.6])
    s2 = np.array([-0.3, 0.4, 0.8]) / np.linalg.norm([-0.3, 0.4, 0.8])
    p1, p2 = _probe(0.0, s1), _probe(0.7, s2)
    a = 0.3
    raw = [bake_probe(p, "latlong", **SMALL) for p in (p1, p2)]
    b1, b2 = (bake_from_arrays(r) for r in raw)
    raw_mixed = bake_probe((a * p1 + (1 - a) * p2).astype(np.float32), "latlong", **SMALL)
    mixed = bake_from_arrays(bake_probe((a * p1 + (1 - a) * p2).astype(np.float32), "latlong",
                                        **SMALL))  # fmt: skip
    blended = blend_bakes([b1, b2], [a, 1 - a])
    peak = float(np.abs(a * p1 + (1 - a) * p2).max())
    for got, want in [(blended.cube, mixed.cube), (blended.sun_dim, mixed.sun_dim),
                      *zip(blended.specular, mixed.specular, strict=True)]:  # fmt: skip
        np.testing.assert_allclose(got, want, rtol=0, atol=LINEAR_PEAK * peak)
    # the radiance SH are linear; the exported irradiance SH are windowed per probe (Sloan's
    # minimal non-negative window, chosen from the probe), so their blend is only close
    sh_blend = a * raw[0].sh + (1 - a) * raw[1].sh
    np.testing.assert_allclose(sh_blend, raw_mixed.sh, rtol=0, atol=LINEAR_PEAK * peak)
    # not linear: the blend's own sun split removes one sun, the pair's blend removes each
    assert np.abs(blended.shadow_dim - mixed.shadow_dim).max() > 1e-2 * mixed.shadow_dim.max()


def test_a_blended_walk_changes_less_per_frame_than_snapping():
    from tests.preview.bakes import synthetic_bake

    bakes = [synthetic_bake()]
    bakes += [bakes[0]._replace(sun_dim=bakes[0].sun_dim * k) for k in (2.0, 0.5)]
    result = walk(bakes, PROBES, PATH, method="volumes", radii=14.0, blend_distance=6.0)
    assert result.worst_step < result.worst_snap_step / 20  # measured: 62 times smaller
    # at a probe, the walk shows that probe's own irradiance
    at = np.argmin(np.linalg.norm(PATH - PROBES[1], axis=1))
    np.testing.assert_allclose(result.blended[at], result.snapped[at], rtol=0.05)
