import numpy as np

def srgb_apply(a: np.ndarray, decode: bool, out: np.ndarray) -> None: ...
def srgb8(a: np.ndarray, colour: int, dither: bool, seed: int, out: np.ndarray) -> None: ...
def box(src: np.ndarray, fy: int, fx: int, out: np.ndarray) -> None: ...
def separable(
    src: np.ndarray,
    ry: np.ndarray,
    ky: np.ndarray,
    wy: np.ndarray,
    rx: np.ndarray,
    kx: np.ndarray,
    wx: np.ndarray,
    out: np.ndarray,
) -> None: ...
