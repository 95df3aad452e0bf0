import numpy as np

# diffuse (src/light/diffuse.hpp)
def cosine_sum(
    normals: np.ndarray,
    dirs: np.ndarray,
    energy: np.ndarray,
    g_starts: np.ndarray,
    g_axes: np.ndarray,
    g_sin: np.ndarray,
    g_linear: np.ndarray,
    s_starts: np.ndarray,
    s_axes: np.ndarray,
    s_sin: np.ndarray,
    s_linear: np.ndarray,
    out: np.ndarray,
) -> None: ...
def bins(dirs: np.ndarray, subset: np.ndarray, size: int, out: np.ndarray) -> None: ...
def accumulate(
    values: np.ndarray,
    dirs: np.ndarray,
    omega: np.ndarray,
    subset: np.ndarray,
    index: np.ndarray,
    n_bins: int,
    chunks: int,
    size: int,
    colour: int,
    sums: np.ndarray,
) -> None: ...
def energy(values: np.ndarray, omega: np.ndarray, colour: int) -> float: ...

# spherical harmonics (src/light/sh/harmonics.hpp)
def basis_rows(dirs: np.ndarray, order: int, out: np.ndarray) -> None: ...
def project(
    values: np.ndarray,
    dirs: np.ndarray,
    weights: np.ndarray,
    order: int,
    chunks: int,
    out: np.ndarray,
) -> None: ...
def project_order2(
    values: np.ndarray, dirs: np.ndarray, weights: np.ndarray, chunks: int, out: np.ndarray
) -> None: ...

# the sun's texels (src/light/sun_texels.hpp)
def cap(
    dirs: np.ndarray, omega: np.ndarray, centre: np.ndarray, cos_limit: float
) -> np.ndarray: ...
def brightest(
    values: np.ndarray,
    weights: np.ndarray,
    omega: np.ndarray,
    dirs: np.ndarray,
    centre: np.ndarray,
    cos_limit: float,
) -> int: ...

# fresnel (src/light/fresnel.hpp)
def reflectance(c: np.ndarray, n: float, out: np.ndarray) -> None: ...
def apply_reflectance(
    cos: np.ndarray, n: float, image: np.ndarray, out: np.ndarray, colour: int
) -> None: ...

# DFG (src/light/dfg.hpp)
def dfg_terms(
    n_dot_v: np.ndarray, roughness: np.ndarray, xi: np.ndarray, schlick: bool, out: np.ndarray
) -> None: ...
def dfg_grid(
    n_dot_v: np.ndarray, roughness: np.ndarray, xi: np.ndarray, schlick: bool, out: np.ndarray
) -> None: ...

# specular (src/light/specular.hpp)
def filter(
    dirs: np.ndarray,
    samples: np.ndarray,
    pyramid: np.ndarray,
    offsets: np.ndarray,
    sizes: np.ndarray,
    lod_bias: float,
    log2_fit: np.ndarray,
    out: np.ndarray,
) -> None: ...
def lobe(
    dirs: np.ndarray,
    src_dirs: np.ndarray,
    src_omega: np.ndarray,
    src_values: np.ndarray,
    ggx: bool,
    param: float,
    cos_cut: float,
    acc: np.ndarray,
    total: np.ndarray,
) -> None: ...
