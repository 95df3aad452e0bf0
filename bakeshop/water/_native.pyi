import numpy as np

FOLD_FLOOR: float

def splitmix64(z: int) -> int: ...
def mode_normals(seed: int, mx: np.ndarray, my: np.ndarray, out: np.ndarray) -> None: ...
def loop_spectra(
    a: np.ndarray,
    b: np.ndarray,
    cycles: np.ndarray,
    frames: np.ndarray,
    table: np.ndarray,
    mult: np.ndarray,
    out: np.ndarray,
) -> None: ...
def free_spectra(
    a: np.ndarray,
    b: np.ndarray,
    omega: np.ndarray,
    times: np.ndarray,
    mult: np.ndarray,
    out: np.ndarray,
) -> None: ...
def normals(
    spectra: np.ndarray, slope: int, stretch: int, height: int, lam: float, out: np.ndarray
) -> None: ...
def flat_normals(spectra: np.ndarray, slope: int, out: np.ndarray) -> None: ...
def gerstner_sums(
    amp: np.ndarray,
    kx: np.ndarray,
    ky: np.ndarray,
    phase: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    out: np.ndarray,
) -> None: ...
def sample_add(
    field: np.ndarray, size: float, x: np.ndarray, y: np.ndarray, weight: float, out: np.ndarray
) -> None: ...
def laplacian_step(
    h: np.ndarray,
    v: np.ndarray,
    c2: float,
    damp_a: float,
    damp_b: float,
    dt: float,
    dx2: float,
    force: np.ndarray,
    rm: np.ndarray,
    rp: np.ndarray,
    cm: np.ndarray,
    cp: np.ndarray,
) -> None: ...
def shade(normals: np.ndarray, view: np.ndarray, sun: np.ndarray, out: np.ndarray) -> None: ...
