"""Every byte that enters or leaves bakeshop: image files, environments, containers, meshes.

``read_image(path)`` returns a float32 ``(H, W, C)`` array, C in {1, 3, 4}, linear values, row 0 at
the top of the picture; ``write_image(path, image, **options)`` writes one, atomically. The codec
is chosen by the file's extension (the table :data:`CODECS`, plain data) and, on read, checked
against the file's magic bytes: a file whose content is another format than its name says is
refused with an error naming what it really is.

Each codec is one module of this package exposing ``NAME``, ``sniff(head) -> bool``,
``read(path, *, ...) -> (image, metadata)`` and ``write(path, image, *, ...)``, whose options are
keyword-only parameters (an option a codec does not take is refused with the list it does).

Beside the codecs: :func:`read_environment`/:func:`write_environment` (any layout, six
``{face}`` files, DDS/KTX/KTX2 cube maps; :mod:`bakeshop.io.environment`), the texture
containers (:data:`CONTAINERS`), :func:`load_mesh` (:mod:`bakeshop.io.mesh`), JSON and text
documents, and :func:`atomic_path`, the one way a file is written.
"""

from __future__ import annotations

import importlib
import os
import warnings
from pathlib import Path
from types import ModuleType
from typing import Any, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import (
    BakeshopError,
    BakeshopWarning,
    FormatError,
    UnsupportedError,
    with_article,
)
from bakeshop.io import _intent, verify
from bakeshop.io._files import (
    atomic_path,
    check_input,
    describe_os_error,
    open_input,
    record_writes,
)
from bakeshop.io._options import checked_options
from bakeshop.io.budget import DECODE_FLOOR, DECODE_RATIO, decode_budget
from bakeshop.io.containers import CONTAINERS, read_container, write_container
from bakeshop.io.documents import read_json, write_json, write_text
from bakeshop.io.environment import (
    EnvironmentFile,
    read_environment,
    write_chain,
    write_environment,
    write_table,
)
from bakeshop.io.mesh import load_mesh
from bakeshop.io.store import ArrayStore, user_store
from bakeshop.io.verify import verify_writes

#: codec module -> the file extensions it owns.
CODECS: dict[str, tuple[str, ...]] = {
    "pfm": (".pfm",),
    "rgbe": (".hdr", ".pic", ".rgbe"),
    "tga": (".tga",),
    "exr": (".exr",),
    "ldr": (".png", ".jpg", ".jpeg"),
    "tiff": (".tif", ".tiff"),
}

#: codecs that store floating-point values; the others store 8- or 16-bit integers that the
#: readers scale to [0, 1] (display-encoded pictures, never linearised silently).
HDR_CODECS = frozenset({"pfm", "rgbe", "exr"})

#: extensions whose formats store an alpha channel (PFM, Radiance and JPEG store none).
ALPHA_EXTENSIONS = frozenset({".tga", ".exr", ".png", ".tif", ".tiff"})

#: bytes read from the head of a file to recognise its format.
SNIFF_BYTES = 64

__all__ = [
    "ALPHA_EXTENSIONS",
    "ArrayStore",
    "CODECS",
    "DECODE_FLOOR",
    "DECODE_RATIO",
    "CONTAINERS",
    "HDR_CODECS",
    "EnvironmentFile",
    "atomic_path",
    "check_input",
    "check_write_options",
    "codec_for",
    "decode_budget",
    "describe_os_error",
    "load_mesh",
    "read_container",
    "read_environment",
    "read_image",
    "read_json",
    "record_writes",
    "sniff_format",
    "stored_bits",
    "user_store",
    "verify",
    "verify_writes",
    "write_chain",
    "write_container",
    "write_environment",
    "write_image",
    "write_json",
    "write_table",
    "write_text",
]


def _module(name: str) -> ModuleType:
    return importlib.import_module(f"bakeshop.io.{name}")


def codec_for(path: str | os.PathLike) -> str:
    """The codec name that owns ``path``'s extension; :class:`UnsupportedError` if none does."""
    ext = Path(path).suffix.lower()
    for name, extensions in CODECS.items():
        if ext in extensions:
            return name
    known = ", ".join(e for exts in CODECS.values() for e in exts)
    raise UnsupportedError(
        f"unknown image extension {ext!r}; bakeshop reads and writes {known}", path
    )


def stored_bits(metadata: dict) -> int | None:
    """Bits of an integer-stored file's samples (8 or 16; fewer count as 8), None for floats."""
    stored = str(metadata.get("stored", ""))
    if not stored.startswith("uint"):
        return None
    digits = "".join(ch for ch in stored if ch.isdigit())
    return 16 if int(digits or 8) > 8 else 8


def sniff_format(head: bytes) -> str | None:
    """The codec whose magic bytes match ``head``, or None (TGA has no magic and never matches)."""
    for name in CODECS:
        if name != "tga" and _module(name).sniff(head):
            return name
    return None


@overload
def read_image(
    path: str | os.PathLike,
    *,
    with_metadata: Literal[False] = False,
    max_decoded: int | None = None,
    **options: Any,
) -> np.ndarray: ...


@overload
def read_image(
    path: str | os.PathLike,
    *,
    with_metadata: Literal[True],
    max_decoded: int | None = None,
    **options: Any,
) -> tuple[np.ndarray, dict]: ...


@overload
def read_image(
    path: str | os.PathLike,
    *,
    with_metadata: bool,
    max_decoded: int | None = None,
    **options: Any,
) -> np.ndarray | tuple[np.ndarray, dict]: ...


def read_image(
    path: str | os.PathLike,
    *,
    with_metadata: bool = False,
    max_decoded: int | None = None,
    **options: Any,
) -> np.ndarray | tuple[np.ndarray, dict]:
    """Read an image file as a float32 ``(H, W, C)`` array.

    Parameters
    ----------
    path : path-like
        The file; its extension picks the codec (see :data:`CODECS`). It must be a regular
        file: a directory, named pipe, device or symbolic link loop is refused at once
        (:func:`check_input`).
    with_metadata : bool
        Also return a dict of what the file says beyond the pixels: at least ``format`` and
        ``stored`` (the sample type in the file), plus codec-specific entries.
    max_decoded : int, optional
        Bytes the file may decode to. Default: the budget in force
        (:func:`decode_budget`), normally ``max(DECODE_FLOOR, DECODE_RATIO * file size)``:
        1 GiB, or 256 bytes per byte of file when that is more (see :mod:`bakeshop.io.budget`).
    **options
        Passed to the codec's reader (for example ``raw=True`` for Radiance files, which keeps
        the stored values instead of dividing by the file's EXPOSURE).

    Returns
    -------
    image : (H, W, C) float32
    metadata : dict, only with ``with_metadata=True``

    Raises
    ------
    bakeshop.errors.BakeshopError
        Unknown extension, not a regular file, a file that is another format than its name
        says, a truncated, corrupt or absurdly large file, or one that would decode to more
        than the budget.
    """
    name = codec_for(path)
    try:
        with open_input(path) as f:
            head = f.read(SNIFF_BYTES)
    except OSError as e:
        raise BakeshopError(e.strerror or str(e), path) from None
    codec = _module(name)
    options = checked_options(codec.read, options, codec.NAME, path)
    if not codec.sniff(head):
        actual = sniff_format(head)
        if actual is not None and actual != name:
            raise FormatError(
                f"the file is {_module(actual).NAME}, not {codec.NAME} as its extension says; "
                "rename it",
                path,
            )
        if name != "tga":
            raise FormatError(f"not {with_article(codec.NAME)} file (bad magic bytes)", path)
    try:
        if max_decoded is None:
            image, meta = codec.read(Path(path), **options)
        else:
            with decode_budget(max_decoded):
                image, meta = codec.read(Path(path), **options)
    except BakeshopError as e:
        if e.path is None:
            e.path = os.fspath(path)
        raise
    except MemoryError:
        raise FormatError("the image is too large for this machine's memory", path) from None
    meta.setdefault("format", codec.NAME)
    return (image, meta) if with_metadata else image


def write_image(path: str | os.PathLike, image: ArrayLike, **options: Any) -> None:
    """Write ``image`` ((H, W) or (H, W, C) array, C in {1, 3, 4}) to ``path``, atomically.

    The codec is picked by the extension; ``options`` go to it (see each codec's ``write``). The
    file appears complete or not at all: it is written beside the target and renamed.
    """
    name = codec_for(path)
    image = as_image(image, path)
    codec = _module(name)
    options = checked_options(codec.write, options, codec.NAME, path)
    with (
        _intent.intent(path, "image", image, codec=name, options=options),
        atomic_path(path) as tmp,
        warnings.catch_warnings(record=True) as said,
    ):
        try:
            codec.write(tmp, image, **options)
        except BakeshopError as e:
            if e.path is None:
                e.path = os.fspath(path)
            raise
    for w in said:  # said again, of the file written rather than its temporary
        if isinstance(w.message, BakeshopWarning) and w.message.path is None:
            w.message.path = os.fspath(path)
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def check_write_options(path: str | os.PathLike, options: dict) -> None:
    """Refuse, before any work, a format ``path``'s extension does not name, or ``options``
    its codec's writer does not take or whose values are of the wrong type (what
    :func:`write_image` would refuse at the end)."""
    codec = _module(codec_for(path))
    checked_options(codec.write, options, codec.NAME, path)


def as_image(image: ArrayLike, path: str | os.PathLike | None = None) -> np.ndarray:
    """Return ``image`` as a C-contiguous ``(H, W, C)`` array (C in {1, 3, 4}) of its own dtype.

    A 2-D array becomes one channel. Any other shape raises :class:`ArgumentError`.
    """
    from bakeshop.errors import ArgumentError

    a = np.asarray(image)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 3, 4) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ArgumentError(
            f"an image must be (H, W) or (H, W, C) with C in 1, 3, 4; got shape {a.shape}", path
        )
    return np.ascontiguousarray(a)
