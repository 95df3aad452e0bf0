import numpy as np

# --- sampling (src/sphere/bind_sampling.cpp) ---------------------------------------------------
# maps.hpp: the layouts' maps
def directions_at(kind: int, h: int, w: int, coords: np.ndarray, out: np.ndarray) -> None: ...
def coordinates_of(kind: int, h: int, w: int, dirs: np.ndarray, out: np.ndarray) -> None: ...
def latlong_directions(out: np.ndarray) -> None: ...
def latlong_trig(h: int, w: int, out: np.ndarray) -> None: ...
def direction(
    kind: int, h: int, w: int, f: float, x: float, y: float
) -> tuple[float, float, float]: ...
def coordinates(
    kind: int, h: int, w: int, x: float, y: float, z: float
) -> tuple[float, float, float]: ...
def cube_face(x: float, y: float, z: float) -> tuple[int, float, float]: ...
def valid(kind: int, h: int, w: int, f: float, i: int, j: int) -> bool: ...
# --- end of sampling ---------------------------------------------------------------------------


# --- the area filter (src/sphere/bind_area.cpp) ---

def splat_rows(
    anchor: np.ndarray,
    wq: np.ndarray,
    scale: np.ndarray,
    row: int,
    offsets: np.ndarray,
    taps: np.ndarray,
    weights: np.ndarray,
    alpha: np.ndarray,
    inverse: np.ndarray,
    cursor: np.ndarray,
    fill: bool,
    indices: np.ndarray,
    values: np.ndarray,
) -> None: ...
def row_starts(cursor: np.ndarray, extra: np.ndarray, indptr: np.ndarray) -> None: ...
def bilinear_rows(
    alpha: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    indptr: np.ndarray,
    counts: np.ndarray,
    fill: bool,
    indices: np.ndarray,
    values: np.ndarray,
) -> None: ...
def scale_rows(
    indptr: np.ndarray, indices: np.ndarray, values: np.ndarray, factor: np.ndarray
) -> None: ...
def balance_rows(
    indptr: np.ndarray,
    indices: np.ndarray,
    values: np.ndarray,
    omega_out: np.ndarray,
    col: np.ndarray,
    blocks: np.ndarray,
    energy: np.ndarray,
) -> None: ...
def balance_columns(
    energy: np.ndarray, omega_in: np.ndarray, col: np.ndarray, step: np.ndarray
) -> float: ...
def reorder_rows(
    indptr: np.ndarray,
    indices: np.ndarray,
    values: np.ndarray,
    order: np.ndarray,
    out_indptr: np.ndarray,
    out_indices: np.ndarray,
    out_values: np.ndarray,
) -> None: ...
def area_gather(
    src: np.ndarray, indptr: np.ndarray, indices: np.ndarray, values: np.ndarray, out: np.ndarray
) -> None: ...
def box_reduce(fine: np.ndarray, omega: np.ndarray, k: int, out: np.ndarray) -> None: ...
def peak_stats(
    values: np.ndarray, omega: np.ndarray, stats: np.ndarray, peaks: np.ndarray
) -> None: ...

def splat_plan(
    skind: int,
    sh: int,
    sw: int,
    sfaces: int,
    omega: np.ndarray,
    dkind: int,
    dh: int,
    dw: int,
    rot: np.ndarray,
    anchor: np.ndarray,
    wq: np.ndarray,
    scale: np.ndarray,
    width: np.ndarray,
    parts: np.ndarray,
    acc: np.ndarray,
) -> None: ...
def splat_exceptions(
    skind: int,
    sh: int,
    sw: int,
    omega: np.ndarray,
    dkind: int,
    dh: int,
    dw: int,
    rot: np.ndarray,
    where: np.ndarray,
    parts: np.ndarray,
    offsets: np.ndarray,
    taps: np.ndarray,
    weights: np.ndarray,
    counts: np.ndarray,
    latlong_done: bool = False,
) -> None: ...
def compact_exceptions(
    at: np.ndarray,
    counts: np.ndarray,
    taps: np.ndarray,
    weights: np.ndarray,
    ends: np.ndarray,
    out_taps: np.ndarray,
    out_weights: np.ndarray,
) -> None: ...
def deposit_exceptions(
    where: np.ndarray,
    offsets: np.ndarray,
    taps: np.ndarray,
    weights: np.ndarray,
    width: np.ndarray,
    acc: np.ndarray,
) -> None: ...
def area_alpha(
    acc: np.ndarray, omega: np.ndarray, alpha: np.ndarray, inverse: np.ndarray
) -> None: ...
def _supersample_cube(
    skind: int,
    sh: int,
    sw: int,
    src: np.ndarray,
    clamp: float,
    size: int,
    k: int,
    rot: np.ndarray,
    out: np.ndarray,
) -> None: ...

# --- end of the area filter ---
