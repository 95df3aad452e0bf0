import numpy as np

def half_planes(bits: np.ndarray, out: np.ndarray) -> None: ...
def rgbe_decode(
    data: np.ndarray,
    pos: int,
    nscan: int,
    scanlen: int,
    out: np.ndarray,
    factors: np.ndarray,
    dry: bool,
) -> tuple[int, int, int]: ...
def rgbe_scan(
    data: np.ndarray, pos: int, scanlen: int, count: int, starts: np.ndarray, first: int
) -> tuple[int, int, int]: ...
def rgbe_encode(
    image: np.ndarray,
    rle: bool,
    block_rows: int,
    buf: np.ndarray,
    starts: np.ndarray,
    stops: np.ndarray,
) -> None: ...
def tga_unrle(data: np.ndarray, start: int, count: int, bpp: int, out: np.ndarray) -> int: ...
def tga_rle(rows: np.ndarray, width: int, bpp: int, out: np.ndarray) -> int: ...
def tga_expand8(
    raw: np.ndarray,
    height: int,
    width: int,
    bpp: int,
    order: np.ndarray,
    flip_x: bool,
    flip_y: bool,
    lut: np.ndarray,
    out: np.ndarray,
) -> None: ...
def png_unfilter(
    buf: np.ndarray, start: int, height: int, stride: int, bpp: int, out: np.ndarray
) -> int: ...
def png_filter_rows(rows: np.ndarray, bpp: int, out: np.ndarray) -> None: ...
def quantize(values: np.ndarray, top: int, out: np.ndarray) -> None: ...
