import numpy as np

# --- sampling (src/sphere/bind_sampling.cpp) ---------------------------------------------------
# maps.hpp: the layouts' maps
def directions_at(kind: int, h: int, w: int, coords: np.ndarray, out: np.ndarray) -> None: ...
def coordinates_of(kind: int, h: int, w: int, dirs: np.ndarray, out: np.ndarray) -> None: ...
def latlong_directions(out: np.ndarray) -> None: ...
def latlong_trig(h: int, w: int, out: np.ndarray) -> None: ...

# gather.hpp: remap plans and gathers (images float32 or float64)
EXCEPTION: int

def taps_of(
    kind: int,
    h: int,
    w: int,
    dirs: np.ndarray,
    nearest: bool,
    index: np.ndarray,
    frac: np.ndarray,
) -> None: ...
def plan(
    skind: int,
    sh: int,
    sw: int,
    dkind: int,
    dh: int,
    dw: int,
    faces: int,
    rot: np.ndarray,
    nearest: bool,
    base: np.ndarray,
    frac: np.ndarray,
    src: np.ndarray,
    out: np.ndarray,
    first_row: int,
) -> None: ...
def plan_exceptions(
    skind: int,
    sh: int,
    sw: int,
    dkind: int,
    dh: int,
    dw: int,
    rot: np.ndarray,
    where: np.ndarray,
    taps: np.ndarray,
) -> None: ...
def reorder_plan(
    base: np.ndarray,
    frac: np.ndarray,
    order: np.ndarray,
    out_base: np.ndarray,
    out_frac: np.ndarray,
) -> None: ...
def gather_at(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    where: np.ndarray,
    out: np.ndarray,
) -> None: ...
def gather_plan(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    out: np.ndarray,
) -> None: ...
def gather_plan_clamped(
    src: np.ndarray,
    row: int,
    base: np.ndarray,
    frac: np.ndarray,
    taps: np.ndarray,
    clamp: float,
    out: np.ndarray,
) -> None: ...
def gather_nearest(src: np.ndarray, index: np.ndarray, out: np.ndarray) -> None: ...
def gather_bilinear(
    src: np.ndarray, index: np.ndarray, frac: np.ndarray, out: np.ndarray
) -> None: ...

# windows.hpp: the taps of a part of a remap
def part_taps(
    skind: int,
    sh: int,
    sw: int,
    dkind: int,
    dh: int,
    dw: int,
    rot: np.ndarray,
    f: int,
    j0: int,
    j1: int,
    i0: int,
    i1: int,
    nearest: bool,
    taps: np.ndarray,
    frac: np.ndarray,
) -> None: ...
def latlong_window(
    h: int, w: int, top: int, bottom: int, left: int, right: int, dirs: np.ndarray
) -> None: ...

# texels.hpp: texel directions, cosines and checks
def count_nonfinite(flat: np.ndarray) -> tuple[int, int, int]: ...
def row_directions(
    kind: int, h: int, w: int, r0: int, r1: int, trig: np.ndarray, out: np.ndarray
) -> None: ...
def index_directions(
    kind: int, h: int, w: int, index: np.ndarray, trig: np.ndarray, out: np.ndarray
) -> None: ...
def texel_cosines(
    kind: int, faces: int, h: int, w: int, up: np.ndarray, out: np.ndarray
) -> None: ...

# cube_latlong.hpp: a cube texel's exact overlaps with a latlong's texels
def latlong_taps(
    skind: int,
    sh: int,
    sw: int,
    f: int,
    i: int,
    j: int,
    rot: np.ndarray,
    dh: int,
    dw: int,
    om: float,
    o: int,
    room: int,
    taps: np.ndarray,
    weights: np.ndarray,
) -> int: ...

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
