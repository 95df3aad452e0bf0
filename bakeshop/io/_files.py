"""File plumbing shared by the codecs: atomic writes and header-versus-size checks."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from bakeshop.errors import BakeshopError, FormatError

#: Largest accepted image side, in pixels.
MAX_SIDE = 1 << 20
#: Largest accepted pixel count (about 268 megapixels: 3.2 GB as float32 RGB). Codecs that can
#: read larger images take a ``max_pixels`` option.
MAX_PIXELS = 1 << 28


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike):
    """Yield a temporary path beside ``target`` (same extension); rename it over ``target`` on
    success, delete it on failure. A failed write leaves no partial file and the old one intact.
    """
    target = Path(target)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise BakeshopError(f"directory {str(directory)!r} does not exist", target)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=directory)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def check_dimensions(width: int, height: int, channels: int = 1, *, max_pixels: int = MAX_PIXELS):
    """Refuse absurd sizes before anything is allocated."""
    if width < 1 or height < 1:
        raise FormatError(f"invalid image size {width}x{height}")
    if width > MAX_SIDE or height > MAX_SIDE or width * height > max_pixels:
        raise FormatError(
            f"image size {width}x{height} exceeds the limit of {max_pixels} pixels "
            f"({MAX_SIDE} per side); pass max_pixels= to read larger images"
        )


def check_payload(needed: int, available: int, what: str = "pixel data"):
    """Refuse a header that promises more bytes than the file holds."""
    if needed > available:
        raise FormatError(
            f"truncated file: the header promises {needed} bytes of {what}, "
            f"the file holds {available}"
        )
