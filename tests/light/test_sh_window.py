"""SH windowing against ringing: fixed windows, Sloan's minimal non-negative window, the
negative fraction, and what is exported (sh.json, the shader), each against a closed form or a
brute-force computation."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import eval_legendre

from bakeshop.errors import ArgumentError
from bakeshop.light import sh
from tests.tolerances import (
    SH_MINIMAL_LAMBDA_RTOL,
    SH_MINIMAL_NEGATIVE,
    SH_NEGATIVE_FRACTION_ATOL,
    SH_WINDOW_BRUTE_FORCE,
    SH_WINDOW_CLOSED_FORM,
)

#: Ramamoorthi and Hanrahan's A_l / pi for l = 0, 1, 2 (the DIM's kernel), written out.
DIM_KERNEL = np.array([1.0, 2.0 / 3.0, 1.0 / 4.0])

SUN = np.array([0.3, 0.8, -0.52]) / np.linalg.norm([0.3, 0.8, -0.52])


def _delta_light(direction, order=2):
    """SH coefficients of a unit delta light (radiance delta(w - s)): c_lm = Y_lm(s)."""
    return sh.basis(direction, order)[:, None]


def _delta_dim(t, factors):
    """Closed form of a windowed order-L DIM of a unit delta light at cos(angle) t: by the
    addition theorem sum_m Y_lm(s) Y_lm(n) = (2l + 1) / (4 pi) P_l(n.s), so
    E/pi = sum_l w_l (A_l / pi) (2l + 1) / (4 pi) P_l(t)."""
    kernel = sh.clamped_cosine(len(factors) - 1) / math.pi
    return sum(
        w * k * (2 * l + 1) / (4 * math.pi) * eval_legendre(l, t)
        for l, (w, k) in enumerate(zip(factors, kernel, strict=True))
    )


def _fibonacci(n):
    k = np.arange(n) + 0.5
    z = 1 - 2 * k / n
    r = np.sqrt(1 - z * z)
    phi = math.pi * (3 - math.sqrt(5)) * k
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def test_fixed_windows_closed_forms():
    h = sh.window_factors(2, "hanning")
    np.testing.assert_allclose(h.factors, [1.0, 0.75, 0.25], atol=1e-15)  # (1 + cos(pi l/3))/2
    lz = sh.window_factors(2, "lanczos")
    x = np.pi * np.array([1, 2]) / 3
    np.testing.assert_allclose(lz.factors, [1.0, *(np.sin(x) / x)], rtol=1e-14)
    lap = sh.window_factors(3, "laplacian", strength=0.5)
    np.testing.assert_allclose(lap.factors, [1, 1 / 3, 1 / 19, 1 / 73], rtol=1e-14)
    assert sh.window_factors(4, "hanning", width=2).factors.tolist() == [1, 0.5, 0, 0, 0]
    np.testing.assert_array_equal(sh.window_factors(3, "none").factors, np.ones(4))
    for bad in ({"width": 0}, {"width": float("nan")}):
        with pytest.raises(ArgumentError):
            sh.window_factors(2, "hanning", **bad)
    with pytest.raises(ArgumentError):
        sh.window_factors(2, "laplacian")
    with pytest.raises(ArgumentError):
        sh.window_factors(2, "gaussian")


@pytest.mark.parametrize("window", ["none", "hanning", "lanczos", "minimal"])
def test_windowed_delta_light_matches_the_addition_theorem(window):
    irr = sh.windowed_irradiance(_delta_light(SUN), window=window)
    n = _fibonacci(2000)
    got = sh.evaluate(irr.coefficients, n)[:, 0]
    want = _delta_dim(n @ SUN, irr.window.factors)
    np.testing.assert_allclose(got, want, atol=SH_WINDOW_CLOSED_FORM)


def test_unwindowed_delta_light_is_negative_on_the_analytic_fraction():
    # E/pi(t) = 1/4 + t/2 + 5/32 (3t^2 - 1) < 0 between the roots of 15t^2 + 16t + 3 = 0:
    # a band opposite the light covering (t1 - t2) / 2 of the sphere
    t1, t2 = sorted(np.roots([15, 16, 3]))
    exact = (t2 - t1) / 2
    assert exact == pytest.approx(0.2906, abs=1e-4)
    irr = sh.windowed_irradiance(_delta_light(SUN), window="none")
    assert irr.negative_raw == pytest.approx(exact, abs=SH_NEGATIVE_FRACTION_ATOL)
    assert irr.negative == irr.negative_raw
    # the fixed windows help but do not cure it: Hanning of width 3 leaves E(-1) < 0
    hann = sh.windowed_irradiance(_delta_light(SUN), window="hanning")
    assert _delta_dim(-1.0, [1, 0.75, 0.25]) < 0 and 0 < hann.negative < exact


def test_minimal_window_is_the_root_of_the_closed_form_minimum():
    # min over t in [-1, 1] of the windowed delta DIM, with w_l = 1 / (1 + lam l^2 (l+1)^2):
    # its root in lam is the least window that makes the DIM non-negative
    t = np.linspace(-1, 1, 400001)

    def lowest(lam):
        return _delta_dim(t, [1, 1 / (1 + 4 * lam), 1 / (1 + 36 * lam)]).min()

    root = brentq(lowest, 1e-6, 10, xtol=1e-12)
    irr = sh.windowed_irradiance(_delta_light(SUN), window="minimal")
    assert irr.window.name == "minimal"
    assert irr.window.parameter == pytest.approx(root, rel=SH_MINIMAL_LAMBDA_RTOL)
    assert irr.window.parameter >= root * (1 - 1e-9)  # on the non-negative side
    assert irr.negative == 0 and irr.negative_raw > 0.29


@pytest.mark.slow
def test_minimal_window_is_non_negative_by_brute_force_and_leaves_good_functions_alone():
    rng = np.random.default_rng(3)
    dense = _fibonacci(50_000)
    for order in (2, 4):
        # a sunny sky: a few delta lights on a dim ambient of random low-order colour
        c = np.zeros(((order + 1) ** 2, 3))
        c[0] = 0.2 * math.sqrt(4 * math.pi)
        for _ in range(3):
            d = rng.normal(size=3)
            c += np.outer(sh.basis(d / np.linalg.norm(d), order), rng.uniform(1, 20, 3))
        w = sh.minimal_window(c)
        assert w.parameter > 0
        f = sh.convolve(sh.convolve(c, sh.clamped_cosine(order) / math.pi), w.factors)
        values = sh.evaluate(f, dense)
        mean = f[0] / math.sqrt(4 * math.pi)
        assert (values.min(axis=0) >= -SH_MINIMAL_NEGATIVE * mean).all()
        # "minimal": a slightly weaker window (lambda 1% smaller) is negative somewhere
        weaker = sh.window_factors(order, "laplacian", strength=0.99 * w.parameter)
        assert sh.evaluate(sh.convolve(sh.convolve(c, sh.clamped_cosine(order) / math.pi),
                                       weaker.factors), dense).min() < 0  # fmt: skip
    # a function that is non-negative already gets no window
    uniform = np.zeros((9, 3))
    uniform[0] = 1.0
    uniform[1] = 0.2  # a gentle gradient: 1 + ... stays positive
    assert sh.minimal_window(uniform).parameter == 0
    with pytest.raises(ArgumentError):
        sh.minimal_window(-uniform)


@pytest.mark.slow
def test_windowed_sh_irradiance_matches_brute_force_convolution():
    # an environment on texels: the SH route (project, window, evaluate) against the direct
    # sum of radiance x the windowed truncated kernel K(n.w) over every texel
    from bakeshop.sphere import layout

    lay = layout("latlong")
    shape = lay.shape(48)
    dirs, _ = lay.directions(shape)
    omega = lay.solid_angles(shape)
    sun = np.exp(200 * (dirs @ SUN - 1))[..., None]  # a small bright lobe
    radiance = 0.3 + 0.2 * dirs[..., 1:2] + 2000 * sun * np.array([1.0, 0.9, 0.7])
    c = sh.project(radiance, dirs, omega, order=2)
    irr = sh.windowed_irradiance(c, window="minimal")
    normals = _fibonacci(300)
    got = sh.evaluate(irr.coefficients, normals)
    cos = normals @ dirs.reshape(-1, 3).T
    kernel = sum(
        w * k * (2 * l + 1) / (4 * math.pi) * eval_legendre(l, cos)
        for l, (w, k) in enumerate(zip(irr.window.factors, DIM_KERNEL, strict=True))
    )
    brute = kernel @ (radiance.reshape(-1, 3) * omega.reshape(-1, 1))
    np.testing.assert_allclose(got, brute, atol=SH_WINDOW_BRUTE_FORCE * np.abs(brute).max())
    assert irr.negative_raw > 0 and irr.negative == 0


def test_negative_fraction_and_minimum():
    c = _delta_light(SUN)
    raw = sh.irradiance_coefficients(c)
    value, where = sh.minimum(raw[:, 0])
    # closed form: 15t^2 + 16t + 3 has its minimum of E at t = -8/15
    t = -8 / 15
    assert value == pytest.approx(_delta_dim(t, [1, 1, 1]), abs=1e-9)
    assert float(where @ SUN) == pytest.approx(t, abs=1e-4)
    assert sh.negative_fraction(np.eye(4, 2)[:, :1]) == 0.0  # a constant


def test_document_keeps_raw_coefficients_and_adds_the_windowed_irradiance():
    c = _delta_light(SUN) * np.array([[1.0, 2.0, 3.0]])
    irr = sh.windowed_irradiance(c)
    doc = sh.to_document(c, irradiance=irr)
    np.testing.assert_array_equal(sh.from_document(doc), c)  # the raw ones, unchanged
    section = doc["irradiance"]
    assert section["window"] == "minimal" and section["negative_fraction"] == 0
    assert section["negative_fraction_unwindowed"] == pytest.approx(irr.negative_raw)
    np.testing.assert_allclose(section["coefficients"], irr.coefficients)
    np.testing.assert_allclose(
        section["coefficients"],
        sh.convolve(sh.irradiance_coefficients(c), section["window_factors"]),
    )
    assert "coefficients" in sh.to_document(c) and "irradiance" not in sh.to_document(c)


def test_shader_snippet_is_windowed_by_default():
    c = _delta_light(SUN) * np.array([[1.0, 0.8, 0.6]])
    text = sh.shader_snippet(c)
    assert "minimal window" in text
    # the emitted matrices, parsed back: n^T M n at many normals is the windowed DIM, and it
    # is nowhere negative (the shader's max(..., 0) has nothing left to cut)
    mats = []
    for name in "RGB":
        numbers = text.split(f"BAKESHOP_SH_M{name} = ")[1].split("(", 1)[1].split(")")[0]
        mats.append(np.array([float(v) for v in numbers.split(",")]).reshape(4, 4))
    n = _fibonacci(5000)
    p = np.concatenate([n, np.ones((len(n), 1))], axis=1)
    quad = np.stack([np.einsum("ni,ij,nj->n", p, m, p) for m in mats], axis=-1)
    irr = sh.windowed_irradiance(c)
    want = sh.evaluate(irr.coefficients, n)  # R&H's constants have six digits
    np.testing.assert_allclose(quad, want, atol=1e-5 * np.abs(want).max())
    assert quad.min() > -1e-6


# --- the search's memory (issue 28) ---------------------------------------------------------


def test_the_degree_parts_by_chunks_are_those_of_the_whole_basis(monkeypatch):
    from bakeshop.light.sh import window

    rng = np.random.default_rng(8)
    coeffs = rng.normal(size=(25, 3))
    dirs = window._fibonacci_sphere(100)
    y = sh.basis(dirs, 4)
    whole = np.stack(
        [y[:, l * l : (l + 1) ** 2] @ coeffs[l * l : (l + 1) ** 2] for l in range(5)], 1
    )
    monkeypatch.setattr(window, "_chunk", lambda order: 7)  # 15 chunks, the last one short
    np.testing.assert_allclose(window._degree_parts(coeffs, dirs), whole, rtol=0, atol=1e-12)


def test_the_minimal_window_at_order_64_is_refused_before_it_allocates(monkeypatch):
    """Order 64 once made its whole basis at 1024 * 65^2 directions (136 GiB) and failed deep
    in numpy; it is estimated first now (7.2 GB by chunks) and refused with the number."""
    from bakeshop import resources

    monkeypatch.setattr(resources, "memory_limits", lambda: {"memory available": 1 << 30})
    coeffs = np.zeros((65**2, 3))
    coeffs[0] = 1
    with pytest.raises(resources.MemoryLimitError, match="order 64 needs about 7.23 GB"):
        sh.minimal_window(coeffs)
