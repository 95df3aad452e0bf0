import numpy as np

def blend_texels(
    method: int, macro: np.ndarray, detail: np.ndarray, strength: np.ndarray, out: np.ndarray
) -> None: ...
def sample_points(
    texels: np.ndarray,
    offsets: np.ndarray,
    shapes: np.ndarray,
    xs: np.ndarray,
    ys: np.ndarray,
    lods: np.ndarray,
    wrap: bool,
    out: np.ndarray,
) -> None: ...
def place(
    texels: np.ndarray,
    offsets: np.ndarray,
    shapes: np.ndarray,
    lod: float,
    affine: np.ndarray,
    cos_r: float,
    sin_r: float,
    sign_x: float,
    sign_y: float,
    out: np.ndarray,
) -> None: ...
def rasterize(
    tex: np.ndarray, faces: np.ndarray, face_map: np.ndarray, bary: np.ndarray
) -> None: ...
def dilate(out: np.ndarray, filled: np.ndarray, rings: int) -> None: ...
def world_to_tangent(
    world: np.ndarray, tangent: np.ndarray, sign: np.ndarray, normal: np.ndarray, out: np.ndarray
) -> None: ...
def shade(
    texels_idx: np.ndarray,
    face_of: np.ndarray,
    bary: np.ndarray,
    faces: np.ndarray,
    normals: np.ndarray,
    positions: np.ndarray,
    uv2: np.ndarray,
    frame: np.ndarray,
    frame2: np.ndarray,
    texels: np.ndarray,
    offsets: np.ndarray,
    shapes: np.ndarray,
    lod: np.ndarray,
    box_axis: np.ndarray,
    mode: int,
    axis: int,
    sharpness: float,
    place: np.ndarray,
    axes: np.ndarray,
    out: np.ndarray,
) -> None: ...
