import numpy as np

def merge_rows(
    codes: np.ndarray,
    table: np.ndarray,
    weight: np.ndarray,
    slope: np.ndarray,
    low: int,
    high: int,
    inv_exposure: np.ndarray,
    shifts: np.ndarray,
    ghost: float,
    noise: float,
    row0: int,
    row1: int,
    out: np.ndarray,
    votes: np.ndarray,
    wsum: np.ndarray,
    status: np.ndarray,
    counts: np.ndarray,
) -> None: ...
