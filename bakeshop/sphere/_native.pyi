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
