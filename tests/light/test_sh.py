"""Real spherical harmonics: the basis against scipy, projection, kernels, export, blending."""

import json
import math

import numpy as np
import pytest
from scipy import integrate
from scipy.special import eval_legendre, sph_harm_y

from bakeshop.errors import ArgumentError, FormatError
from bakeshop.io import read_json, write_json
from bakeshop.light import sh
from tests.tolerances import SH_BASIS, SH_QUADRATURE


def _random_dirs(n, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _scipy_real(l, m, d):
    """Real SH from scipy's complex ones (which carry the Condon-Shortley phase)."""
    theta = np.arccos(np.clip(d[:, 2], -1, 1))
    phi = np.arctan2(d[:, 1], d[:, 0])
    c = sph_harm_y(l, abs(m), theta, phi)
    if m == 0:
        return c.real
    return math.sqrt(2) * (-1) ** m * (c.real if m > 0 else c.imag)


def test_basis_matches_scipy_to_high_order():
    d = _random_dirs(500)
    order = 48
    ours = sh.basis(d, order)
    for l in range(order + 1):
        for m in range(-l, l + 1):
            ref = _scipy_real(l, m, d)
            np.testing.assert_allclose(ours[:, sh.index(l, m)], ref, atol=SH_BASIS, rtol=0)


def test_low_order_closed_forms_and_frame():
    # Ramamoorthi & Hanrahan's table: Y(1,-1) ~ y, Y(1,0) ~ z, Y(1,1) ~ x, and degree 2.
    d = _random_dirs(100, seed=1)
    x, y, z = d.T
    b = sh.basis(d, 2)
    expected = [
        0.282095 * np.ones_like(x),
        0.488603 * y,
        0.488603 * z,
        0.488603 * x,
        1.092548 * x * y,
        1.092548 * y * z,
        0.315392 * (3 * z * z - 1),
        1.092548 * x * z,
        0.546274 * (x * x - y * y),
    ]
    np.testing.assert_allclose(b, np.stack(expected, 1), atol=1e-6)


def test_basis_at_poles_and_shapes():
    poles = np.array([[0, 0, 1.0], [0, 0, -1.0]])
    b = sh.basis(poles, 6)
    assert np.isfinite(b).all()
    for l in range(7):  # only m = 0 is non-zero on the polar axis
        for m in range(-l, l + 1):
            if m:
                assert b[:, sh.index(l, m)] == pytest.approx(0, abs=1e-15)
    assert sh.basis(np.zeros((4, 5, 3)) + [1, 0, 0], 3).shape == (4, 5, 16)


def test_orthonormal_by_quadrature():
    # Gauss-Legendre in cos(theta) x uniform phi integrates products up to degree 2*order.
    order = 8
    zs, wz = np.polynomial.legendre.leggauss(order + 2)
    n_phi = 2 * order + 3
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    z = np.repeat(zs, n_phi)
    r = np.sqrt(1 - z * z)
    d = np.stack([r * np.cos(np.tile(phi, zs.size)), r * np.sin(np.tile(phi, zs.size)), z], 1)
    w = np.repeat(wz, n_phi) * 2 * np.pi / n_phi
    b = sh.basis(d, order)
    gram = b.T @ (b * w[:, None])
    np.testing.assert_allclose(gram, np.eye(gram.shape[0]), atol=SH_QUADRATURE)


def test_projection_recovers_known_coefficients_in_every_layout():
    from bakeshop.sphere import layout

    rng = np.random.default_rng(3)
    truth = rng.normal(size=(16, 3))
    for name, size in (("latlong", 128), ("cube", 48), ("angular", 160)):
        lay = layout(name)
        shape = lay.shape(size)
        dirs, valid = lay.directions(shape)
        omega = lay.solid_angles(shape)
        env = sh.evaluate(truth, dirs)
        got = sh.project(env, dirs, omega, order=3)
        np.testing.assert_allclose(got, truth, atol=5e-3, err_msg=name)


def test_project_scalar_and_refuses_bad_input():
    d = _random_dirs(10)
    w = np.full(10, 4 * np.pi / 10)
    assert sh.project(np.ones(10), d, w, order=1).shape == (4,)
    with pytest.raises(ArgumentError):
        sh.project(np.full(10, np.nan), d, w, order=1)
    with pytest.raises(ArgumentError):
        sh.project(np.ones(9), d, w, order=1)
    with pytest.raises(ArgumentError):
        sh.basis(d, -1)
    with pytest.raises(ArgumentError):
        sh.basis(d, 1.5)
    with pytest.raises(ArgumentError):
        sh.basis(d, sh.MAX_ORDER + 1)


def test_clamped_cosine_matches_published_values_and_quadrature():
    a = sh.clamped_cosine(20)
    # Ramamoorthi & Hanrahan's values, then their closed form for even l >= 2
    np.testing.assert_allclose(a[:5], [np.pi, 2 * np.pi / 3, np.pi / 4, 0, -np.pi / 24], atol=1e-14)
    for l in range(2, 21):
        closed = 0.0
        if l % 2 == 0:
            closed = (
                2
                * np.pi
                * (-1) ** (l // 2 - 1)
                / ((l + 2) * (l - 1))
                * math.factorial(l)
                / (2**l * math.factorial(l // 2) ** 2)
            )
        assert a[l] == pytest.approx(closed, abs=1e-14)
    for exponent in (1.0, 3.5, 20.0):
        k = sh.cosine_power_kernel(10, exponent)
        for l in range(11):
            ref = integrate.quad(
                lambda t, a=exponent, l=l: t**a * eval_legendre(l, t), 0, 1, limit=200
            )[0]
            assert k[l] == pytest.approx(2 * np.pi * ref, abs=1e-10)


def test_phong_kernel_is_energy_normalised():
    for exponent in (0.0, 1.0, 10.0, 1000.0):
        assert sh.phong_kernel(4, exponent)[0] == pytest.approx(1.0)


def test_irradiance_of_a_constant_and_of_a_cosine_lobe():
    # uniform radiance 1 -> E = pi -> DIM 1 everywhere
    c = np.zeros((9, 1))
    c[0] = 2 * np.sqrt(np.pi)  # Y00 = 1 / (2 sqrt(pi))
    d = _random_dirs(50)
    np.testing.assert_allclose(sh.evaluate(sh.irradiance_coefficients(c), d), 1.0, atol=1e-12)
    # radiance = z (order 1): E(n) = 2 pi / 3 * n_z, by the Funk-Hecke theorem
    c = np.zeros(4)
    c[sh.index(1, 0)] = 1 / 0.4886025119029199
    e = sh.evaluate(sh.convolve(c, sh.clamped_cosine(1)), d)
    np.testing.assert_allclose(e, 2 * np.pi / 3 * d[:, 2], atol=1e-12)


def test_irradiance_matrices_agree_with_sh_evaluation():
    rng = np.random.default_rng(5)
    c = rng.normal(size=(9, 3))
    d = _random_dirs(200, seed=6)
    m = sh.irradiance_matrices(c)
    p = np.concatenate([d, np.ones((200, 1))], 1)
    quad = np.einsum("ni,cij,nj->nc", p, m, p)
    ref = sh.evaluate(sh.irradiance_coefficients(c), d)
    # the published constants have 6 significant digits
    np.testing.assert_allclose(quad, ref, atol=2e-5 * np.abs(c).max())


def test_json_round_trip_and_errors(tmp_path):
    c = np.random.default_rng(7).normal(size=(16, 3))
    path = tmp_path / "sh.json"
    write_json(path, sh.to_document(c))
    doc = json.loads(path.read_text())
    assert doc["order"] == 3 and len(doc["coefficients"]) == 16
    np.testing.assert_array_equal(sh.from_document(read_json(path)), c)
    with pytest.raises(FormatError):
        sh.from_document({})
    with pytest.raises(ArgumentError):
        sh.from_document({"coefficients": [[1, 2, 3]] * 5})


@pytest.mark.parametrize("language", ["glsl", "hlsl"])
def test_shader_snippet(language):
    c = np.random.default_rng(8).normal(size=(9, 3))
    text = sh.shader_snippet(c, language=language, window="none")
    assert "bakeshop_irradiance" in text and text.count("BAKESHOP_SH_M") >= 6
    assert ("mat4" in text) == (language == "glsl")
    # the emitted numbers are the matrices
    m = sh.irradiance_matrices(c)
    first = text.split("BAKESHOP_SH_MR = ")[1].split("(", 1)[1].split(")")[0]
    np.testing.assert_allclose([float(v) for v in first.split(",")], m[0].reshape(-1), rtol=1e-8)
    with pytest.raises(ArgumentError):
        sh.shader_snippet(c, language="metal")


def test_blend_is_linear_and_interpolates():
    rng = np.random.default_rng(9)
    probes = rng.normal(size=(3, 9, 3))
    d = _random_dirs(20)
    w = np.array([0.2, 0.5, 0.3])
    blended = sh.blend(probes, w * 7)  # weights are normalised
    e_blend = sh.evaluate(sh.irradiance_coefficients(blended), d)
    e_each = [sh.evaluate(sh.irradiance_coefficients(p), d) for p in probes]
    np.testing.assert_allclose(
        e_blend, sum(wi * e for wi, e in zip(w, e_each, strict=True)), atol=1e-12
    )
    many = sh.blend(probes, np.eye(3))
    np.testing.assert_allclose(many, probes, atol=1e-15)
    with pytest.raises(ArgumentError):
        sh.blend(probes, [1, -1, 1])
    with pytest.raises(ArgumentError):
        sh.blend(probes, [0, 0, 0])
    with pytest.raises(ArgumentError):
        sh.blend(probes, [1, 1])


def test_inverse_distance_weights_are_continuous_and_exact_at_probes():
    probes = np.array([[0, 0, 0], [10, 0, 0], [0, 0, 10.0]])
    w = sh.inverse_distance_weights(probes[1], probes)
    np.testing.assert_array_equal(w, [0, 1, 0])
    near = sh.inverse_distance_weights(probes[1] + [1e-6, 0, 0], probes)
    assert near[1] > 1 - 1e-9
    path = np.linspace(probes[0], probes[1], 101)
    ws = sh.inverse_distance_weights(path, probes)
    assert np.allclose(ws.sum(1), 1) and np.abs(np.diff(ws, axis=0)).max() < 0.2


def test_project_is_the_weighted_sum_over_the_basis():
    rng = np.random.default_rng(11)
    d = _random_dirs(5000, seed=12)
    f = rng.normal(size=(5000, 3)).astype(np.float32)
    w = rng.random(5000)
    w[::7] = 0  # texels outside a disk
    brute = sh.basis(d, 6).T @ (f.astype(np.float64) * w[:, None])
    np.testing.assert_allclose(sh.project(f, d, w, order=6), brute, rtol=1e-10, atol=1e-12)


def test_glsl_snippet_compiles_and_agrees_on_a_real_opengl_driver():
    # the emitted GLSL, compiled by the driver (Mesa's llvmpipe over EGL) and run through
    # transform feedback at random normals, against the SH evaluation in float64
    import moderngl

    c = np.random.default_rng(13).normal(size=(9, 3))
    snippet = sh.shader_snippet(c, language="glsl", window="none")
    source = (
        "#version 330\n"
        + snippet
        + ("in vec3 n;\nout vec3 e;\nvoid main() { e = bakeshop_irradiance(n); }\n")
    )
    ctx = moderngl.create_context(standalone=True, backend="egl")
    try:
        ctx.simple_framebuffer((1, 1)).use()
        prog = ctx.program(vertex_shader=source, varyings=["e"])
        d = _random_dirs(256, seed=14).astype(np.float32)
        vbo = ctx.buffer(d.tobytes())
        out = ctx.buffer(reserve=d.nbytes)
        ctx.vertex_array(prog, [(vbo, "3f", "n")]).transform(out, mode=moderngl.POINTS)
        got = np.frombuffer(out.read(), np.float32).reshape(-1, 3)
    finally:
        ctx.release()
    expected = np.maximum(sh.evaluate(sh.irradiance_coefficients(c), d.astype(np.float64)), 0)
    assert (expected == 0).any() and (expected > 0).any()  # the clamp is exercised too
    # R&H's six-digit constants and float32 arithmetic
    np.testing.assert_allclose(got, expected, rtol=1e-4, atol=1e-4 * np.abs(expected).max())
