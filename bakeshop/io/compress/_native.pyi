import numpy as np

def decode_bc7(
    blocks: np.ndarray,
    out: np.ndarray,
    modes: np.ndarray,
    weights: np.ndarray,
    p2: np.ndarray,
    p3: np.ndarray,
    a2: np.ndarray,
    a31: np.ndarray,
    a32: np.ndarray,
) -> None: ...
def decode_bc6h(
    blocks: np.ndarray,
    out: np.ndarray,
    signed: bool,
    modes: np.ndarray,
    layout: np.ndarray,
    weights: np.ndarray,
    p2: np.ndarray,
    a2: np.ndarray,
) -> None: ...
def decode_s3tc(blocks: np.ndarray, out: np.ndarray, kind: int) -> None: ...
def encode_bc6h_signed(q_blocks: np.ndarray, out: np.ndarray, layout: np.ndarray) -> None: ...
def half_rgba(bits: np.ndarray, out: np.ndarray) -> None: ...
