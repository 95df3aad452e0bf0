"""OpenEXR (.exr) through the reference implementation's own Python bindings (``OpenEXR`` 3.x).

Reading returns the data window of one part (the first unless ``part=`` says otherwise); tiled
and mip-mapped files give their top level. Half, float and uint channels all become float32
(half and uint values exactly, uint up to 2^24). The channels that make the image are found by
name, in the default layer or a named one (``layer="diffuse"`` reads ``diffuse.R`` ...):

=====================  =========================================
channels in the layer  image
=====================  =========================================
R, G, B (+ A)          (H, W, 3) RGB or (H, W, 4) RGBA
Y                      (H, W, 1)
Y, A                   (H, W, 4): Y copied to R, G and B, then A
any single channel     (H, W, 1) (a depth ``Z``, a mask ...)
=====================  =========================================

Other channels of the part are listed in the metadata as ``ignored_channels`` and never
converted or kept: the first part is read through OpenEXR's frame-buffer interface
(``OpenEXR.InputFile``), which fills only the channels asked for, in blocks of rows converted
straight into the float32 image (the peak is the image plus one block). Another part is read
with ``OpenEXR.File``, which decodes every channel of every part, and so is the first part by
bindings that no longer offer ``InputFile`` (deprecated in OpenEXR 3.3+); the decode budget
(:mod:`bakeshop.io.budget`) counts every channel from the header before anything is decoded.
Luminance-chroma (``RY``, ``BY``) and sub-sampled channels are refused rather than read wrongly.

Writing stores half floats by default, as scanlines with the named compression. Half holds
magnitudes up to 65504, and a sun is often brighter: an image with a finite value beyond that is
written as 32-bit floats instead, said in one warning (a clamp would lose the sun's energy
silently, OpenEXR's own conversion would make it infinite). ``pixel_type="half"`` asked for
explicitly refuses such an image, naming ``pixel_type=float``; NaN and +-Inf are stored as they
are. :func:`to_half` is the one float-to-half conversion of every half writer (EXR strips,
DDS/KTX/KTX2 levels, TIFF and zarr strips), and refuses overflow the same way.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import Imath  # the frame-buffer interface's pixel types, shipped with the OpenEXR bindings
import numpy as np
import OpenEXR
from numpy.typing import ArrayLike

from bakeshop.errors import (
    ArgumentError,
    BakeshopError,
    BakeshopWarning,
    FormatError,
    UnsupportedError,
    validate_choice,
)
from bakeshop.io._files import MAX_PIXELS, check_dimensions
from bakeshop.io._half import half_planes
from bakeshop.io.budget import check_decode

NAME = "OpenEXR"
MAGIC = b"\x76\x2f\x31\x01"

#: user name -> OpenEXR compression, every method this build of OpenEXR offers. zstd and the
#: htj2k methods are recent (OpenEXR 3.4): older readers cannot open files written with them.
COMPRESSIONS = {
    {"no": "none"}.get(short := name.removesuffix("_COMPRESSION").lower(), short): value
    for name, value in OpenEXR.Compression.__members__.items()
    if not name.startswith("NUM_")
}
#: the methods that reproduce every half and float value exactly.
LOSSLESS = ("none", "rle", "zips", "zip", "piz", "zstd", "htj2k256", "htj2k32")

PIXEL_TYPES = {"half": np.float16, "float": np.float32}
#: values of the standard ``envmap`` attribute (``ImfEnvmap.h``): an environment's mapping.
ENVMAPS = {"latlong": OpenEXR.Envmap.ENVMAP_LATLONG, "cube": OpenEXR.Envmap.ENVMAP_CUBE}
HALF_MAX = 65504.0
#: an inclusive pixel box, ``((xmin, ymin), (xmax, ymax))``.
Box = tuple[tuple[int, int], tuple[int, int]]
_T = TypeVar("_T")


_STORED = {np.dtype(np.float16): "half", np.dtype(np.float32): "float", np.dtype(np.uint32): "uint"}
_FLOAT = Imath.PixelType(Imath.PixelType.FLOAT)
#: float32 bytes converted per block of rows when reading the first part.
_BLOCK_BYTES = 8 << 20
#: rows per block are a multiple of this: every scanline compression's chunk height (1 to 256
#: rows) divides it, so no chunk is decompressed twice.
_CHUNK_ROWS = 256
#: bytes per stored sample assumed when a header does not say (float and uint; half is 2).
_SAMPLE_BYTES = 4


def sniff(head: bytes) -> bool:
    """True when ``head`` starts with the OpenEXR magic number 76 2f 31 01."""
    return head[:4] == MAGIC


@contextlib.contextmanager
def _library_messages() -> Iterator[list[str]]:
    """Collect what OpenEXR prints while reading (Python stdout and C stderr) into a list.

    The bindings report a corrupt chunk by printing a warning and returning an empty file, and
    the C core prints its own diagnostics on stderr; both become the reason of the
    :class:`FormatError` instead of stray lines on the terminal. File descriptor 2 is
    process-wide: while a read runs, other threads' output to it is collected too (and dropped).
    """
    messages: list[str] = []
    text = io.StringIO()
    with tempfile.TemporaryFile() as err:
        if sys.stderr is not None:  # None: descriptor 2 was closed when Python started
            sys.stderr.flush()
        try:
            saved = os.dup(2)
        except OSError:  # no stderr to protect
            saved = None
        else:
            os.dup2(err.fileno(), 2)
        try:
            with contextlib.redirect_stdout(text):
                yield messages
        finally:
            if saved is not None:
                os.dup2(saved, 2)
                os.close(saved)
            err.seek(0)
            lines = text.getvalue() + err.read().decode("utf-8", "replace")
            messages.extend(line.strip() for line in lines.splitlines() if line.strip())


def _reason(messages: list[str], error: Exception | None = None) -> str:
    said = [str(error)] if error is not None and str(error) else []
    said += [m.removeprefix("Warning: ") for m in messages]
    detail = "; ".join(said)[:300]
    return "corrupt or truncated OpenEXR file" + (f" (OpenEXR says: {detail})" if detail else "")


def _every_core() -> None:
    """Let OpenEXR compress and decompress chunks on every core, as OpenImageIO does: reads and
    writes take the library's global thread pool (the bindings' ``num_threads`` does not reach
    the writer in OpenEXR 3.5; noisy 4096x2048 half ZIP: write 0.81 -> 0.36 s, read 0.16 ->
    0.12 s on 2 cores). The pool is stopped around a fork, whose child has none of its threads
    (its next read or write starts its own), and restarted in the parent."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    if OpenEXR.global_thread_count() < (cores or 1):
        OpenEXR.set_global_thread_count(cores or 1)


_pool_before_fork = [0]


def _stop_pool() -> None:
    _pool_before_fork[0] = OpenEXR.global_thread_count()
    if _pool_before_fork[0]:
        OpenEXR.set_global_thread_count(0)


def _restart_pool() -> None:
    if _pool_before_fork[0]:
        OpenEXR.set_global_thread_count(_pool_before_fork[0])


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=_stop_pool, after_in_parent=_restart_pool)


def _library(action: Callable[..., _T | None], *args: object) -> _T:
    """Return ``action(*args)`` (a call into OpenEXR); its failures become a FormatError.

    The bindings raise RuntimeError, ValueError, IndexError, UnicodeDecodeError ... for corrupt
    files, or print a warning and return an empty file (``action`` then returns None).
    """
    _every_core()
    result, error = None, None
    with _library_messages() as messages:
        try:
            result = action(*args)
        except MemoryError:
            raise
        except Exception as e:
            error = e
    if result is None:
        raise FormatError(_reason(messages, error))
    return result


_LEVELS = {"ONE_LEVEL": "one", "MIPMAP_LEVELS": "mipmap", "RIPMAP_LEVELS": "ripmap"}


def _headers(path: str | os.PathLike) -> list[dict] | None:
    """What bakeshop needs of each part's header, as plain Python values.

    ``channels`` is a list of (name, x sampling, y sampling); a missing required attribute
    raises KeyError here, inside :func:`_library`.
    """
    f = OpenEXR.File(os.fspath(path), separate_channels=True, header_only=True)
    parts = []
    for i in range(len(f.parts)):
        header = f.header(i)
        storage = header.get("type", OpenEXR.scanlineimage).name
        tiles = header.get("tiles")
        part = {
            "channels": [(c.name, c.xSampling, c.ySampling) for c in header["channels"]],
            "compression": header["compression"],
            "data_window": _window(header["dataWindow"]),
            "display_window": _window(header["displayWindow"]),
            "storage": {"scanlineimage": "scanline", "tiledimage": "tiled"}.get(storage, storage),
            "levels": "one" if tiles is None else _LEVELS.get(tiles.mode.name, tiles.mode.name),
        }
        if "envmap" in header:
            part["envmap"] = header["envmap"].name.removeprefix("ENVMAP_").lower()
        parts.append(part)
    return parts or None


def _pixels(path: str | os.PathLike, part: int, names: list[str]) -> dict[str, np.ndarray] | None:
    """The pixel arrays of the named channels of one part (every channel of every part is
    decoded: ``OpenEXR.File`` reads whole files)."""
    f = OpenEXR.File(os.fspath(path), separate_channels=True)
    if part >= len(f.parts):
        return None
    channels = f.channels(part)
    return {n: channels[n].pixels for n in names if n in channels}


def _first_part(
    path: str | os.PathLike, names: list[str], window: Box
) -> tuple[np.ndarray, dict[str, str]]:
    """The named channels of the first part as a float32 ``(H, W, len(names))`` image, and
    the stored type of each, read through the frame buffer: only those channels are filled,
    converted to float by OpenEXR itself, block of rows by block of rows."""
    (x0, y0), (x1, y1) = window
    width, height = x1 - x0 + 1, y1 - y0 + 1
    f = OpenEXR.InputFile(os.fspath(path))
    try:
        described = f.header()["channels"]
        types = {n: str(described[n].type).lower() for n in names}
        image = np.empty((height, width, len(names)), np.float32)
        rows = max(1, _BLOCK_BYTES // (width * 4 * len(names)) // _CHUNK_ROWS) * _CHUNK_ROWS
        for top in range(0, height, rows):
            count = min(rows, height - top)
            planes = f.channels(names, _FLOAT, y0 + top, y0 + top + count - 1)
            for i, plane in enumerate(planes):
                image[top : top + count, :, i] = np.frombuffer(plane, np.float32).reshape(
                    count, width
                )
    finally:
        f.close()
    return image, types


def _window(box: Any) -> Box:  # the header's (min, max) corners, as the bindings give them
    lo, hi = box
    return (int(lo[0]), int(lo[1])), (int(hi[0]), int(hi[1]))


def _pick_channels(names: list[str], layer: str | None) -> tuple[str, list[str], bool]:
    """The layer read, its channel names in image order, and whether Y must become RGB."""
    layers: dict[str, dict[str, str]] = {}
    for name in names:
        prefix, _, base = name.rpartition(".")
        layers.setdefault(prefix, {})[base.upper()] = name

    def recognise(chans: dict[str, str]) -> tuple[list[str], bool] | None:
        if "RY" in chans or "BY" in chans:
            raise UnsupportedError(
                "luminance-chroma (Y, RY, BY) OpenEXR images are not supported; "
                "convert them to RGB with OpenEXR's exrmultipart or another tool"
            )
        if {"R", "G", "B"} <= chans.keys():
            return [chans[c] for c in "RGBA" if c in chans], False
        if "Y" in chans:
            return ([chans["Y"], chans["A"]], True) if "A" in chans else ([chans["Y"]], False)
        if len(chans) == 1:
            return list(chans.values()), False
        return None

    if layer is not None:
        if layer not in layers:
            raise ArgumentError(
                f"no layer {layer!r} in the file; its layers: "
                + ", ".join(repr(k) for k in sorted(layers))
            )
        found = recognise(layers[layer])
        if found is None:
            raise UnsupportedError(
                f"layer {layer!r} has channels {sorted(layers[layer].values())}, "
                "none of which make an RGB, RGBA, Y or single-channel image"
            )
        return layer, *found
    if "" in layers and (found := recognise(layers[""])) is not None:
        return "", *found
    candidates = {k: f for k, v in layers.items() if (f := recognise(v)) is not None}
    if len(candidates) == 1:
        (name, found), *_ = candidates.items()
        return name, *found
    raise UnsupportedError(
        f"cannot tell which of the channels {sorted(names)} make the image"
        + (
            "; pass layer= one of " + ", ".join(repr(k) for k in sorted(candidates))
            if candidates
            else ": no RGB, RGBA or Y set"
        )
    )


def read(
    path: str | os.PathLike,
    *,
    part: int = 0,
    layer: str | None = None,
    max_pixels: int = MAX_PIXELS,
) -> tuple[np.ndarray, dict]:
    """Read one part of an OpenEXR file as a float32 image.

    Parameters
    ----------
    path : path-like
    part : int
        Index of the part of a multi-part file.
    layer : str, optional
        The layer whose channels make the image (``"diffuse"`` for ``diffuse.R`` ...); by
        default the unnamed layer, or the only layer holding a recognisable channel set.
    max_pixels : int
        Refuse data windows larger than this before reading any pixels.

    Returns
    -------
    image : (H, W, C) float32
        The data window, row 0 at the top (its ``ymin``).
    metadata : dict
        ``stored`` (sample type, ``"half"``, ``"float"`` or ``"uint"``, or a ``/``-joined list
        when the channels differ), ``channel_types`` (name -> type), ``channels`` (the names
        read, in image order), ``ignored_channels``, ``layer``, ``compression``,
        ``data_window`` and ``display_window`` (``((xmin, ymin), (xmax, ymax))``, inclusive),
        ``storage`` (``"scanline"`` or ``"tiled"``), ``levels`` (``"one"``, ``"mipmap"``,
        ``"ripmap"``: only the top level is read), ``parts`` and, when the file says,
        ``envmap`` (``"latlong"`` or ``"cube"``).
    """
    headers = _library(_headers, path)
    if not 0 <= part < len(headers):
        raise ArgumentError(f"part {part} requested, the file has {len(headers)}")
    header = headers[part]
    descriptions = header["channels"]
    if header["storage"].startswith("deep"):
        raise UnsupportedError("deep OpenEXR images (several samples per pixel) are not supported")
    (x0, y0), (x1, y1) = header["data_window"]
    check_dimensions(x1 - x0 + 1, y1 - y0 + 1, max_pixels=max_pixels)
    all_names = [name for name, _, _ in descriptions]
    layer_name, names, grey_alpha = _pick_channels(all_names, layer)
    for name, xs, ys in descriptions:
        if name in names and (xs != 1 or ys != 1):
            raise UnsupportedError(
                f"channel {name!r} is sub-sampled ({xs}x{ys}); "
                "bakeshop reads only full-resolution channels"
            )

    width, height = x1 - x0 + 1, y1 - y0 + 1
    unique = list(dict.fromkeys(names))
    order = [names[0]] * 3 + [names[1]] if grey_alpha else names  # the image's channels
    # What the decoder inflates: every channel of the part, or of every part when a later part
    # is read (OpenEXR.File decodes them all); and the float32 image returned.
    stored = sum(_samples(h) for h in (headers if part > 0 else [header])) * _SAMPLE_BYTES
    check_decode(stored + width * height * len(order) * 4, os.path.getsize(path))
    if part == 0 and hasattr(OpenEXR, "InputFile"):  # deprecated in the bindings, still there
        planes, types = _library(_first_part, path, unique, header["data_window"])
        image = planes[:, :, [unique.index(n) for n in order]] if grey_alpha else planes
    else:
        pixels = _library(_pixels, path, part, unique)
        missing = [n for n in unique if n not in pixels]
        if missing:
            raise FormatError(_reason([f"channels {missing} could not be read"]))
        if any(pixels[n].shape != (height, width) for n in unique):
            raise FormatError(_reason(["channels of different sizes"]))
        image = np.empty((height, width, len(order)), np.float32)
        for i, n in enumerate(order):
            image[:, :, i] = pixels[n]
        types = {n: _STORED.get(pixels[n].dtype, str(pixels[n].dtype)) for n in unique}

    meta = {
        "stored": "/".join(sorted(set(types.values()))),
        "channel_types": types,
        "channels": names,
        "ignored_channels": sorted(set(all_names) - set(names)),
        "layer": layer_name,
        "compression": {v: k for k, v in COMPRESSIONS.items()}.get(
            header["compression"], header["compression"].name
        ),
        "data_window": header["data_window"],
        "display_window": header["display_window"],
        "storage": header["storage"],
        "levels": header["levels"],
        "parts": len(headers),
    }
    if "envmap" in header:
        meta["envmap"] = header["envmap"]
    return image, meta


def _samples(header: dict) -> int:
    """Stored samples of one part: each channel's (sub-sampled) pixel count, summed."""
    (x0, y0), (x1, y1) = header["data_window"]
    width, height = x1 - x0 + 1, y1 - y0 + 1
    return sum(-(-width // xs) * -(-height // ys) for _, xs, ys in header["channels"])


def finite_peak(image: np.ndarray) -> float:
    """The largest finite magnitude in ``image`` (0 when it holds none): two passes without a
    temporary array, and when it holds NaN or infinities, a third by blocks of rows (at most
    :data:`_BLOCK_BYTES` of values at a time)."""
    a = np.asarray(image)
    if a.size == 0:
        return 0.0
    peak = max(abs(float(np.max(a))), abs(float(np.min(a))))
    if np.isfinite(peak):
        return peak
    rows = max(1, _BLOCK_BYTES // max(1, a[0].nbytes))
    blocks = (a[top : top + rows] for top in range(0, a.shape[0], rows))
    return max(float(np.max(np.abs(b), where=np.isfinite(b), initial=0.0)) for b in blocks)


def check_half(image: np.ndarray, wider: str) -> np.ndarray:
    """``image``, refused for half floats when a finite value exceeds +-65504; ``wider`` names
    the option that keeps it (``"pixel_type=float"``)."""
    peak = finite_peak(image)
    if peak > HALF_MAX:
        raise ArgumentError(
            f"values reach {peak:.4g}, beyond the 65504 that half floats hold; {wider} keeps them"
        )
    return image


def to_half(image: np.ndarray, wider: str) -> np.ndarray:
    """Convert to float16 (NaN and +-Inf kept), refusing finite values beyond +-65504 with the
    option ``wider`` that keeps them (:func:`check_half`).

    Rounding is IEEE round-to-nearest-even, as OpenEXR's own float-to-half conversion. (The
    writer converts float32 images with the equivalent one-pass kernel of
    :mod:`bakeshop.io._half`; tests/io/test_exr.py holds the two to the same bits.)
    """
    return check_half(np.asarray(image), wider).astype(np.float16)


def write(
    path: str | os.PathLike,
    image: ArrayLike,
    *,
    pixel_type: str | None = None,
    compression: str = "zip",
    envmap: str | None = None,
) -> None:
    """Write an image as a scanline OpenEXR file.

    Parameters
    ----------
    path : path-like
    image : (H, W, C) array, C in {1, 3, 4}
        Values as they are (integers become floats of the same value). C = 1 is written as
        channel ``Y``, C = 3 as ``R, G, B``, C = 4 as ``R, G, B, A``.
    pixel_type : {"half", "float"}, optional
        Sample type in the file. Default: half, or float when a finite value exceeds 65504
        (said in a warning); ``"half"`` refuses such values (see the module notes).
    compression : str
        One of :data:`COMPRESSIONS`: ``"zip"`` (default), ``"none"``, ``"rle"``, ``"zips"``,
        ``"piz"``, ``"zstd"``, ``"htj2k256"``, ``"htj2k32"`` are lossless; ``"pxr24"`` is
        lossless for half but rounds float to 24 bits; ``"b44"``, ``"b44a"``, ``"dwaa"``,
        ``"dwab"`` are lossy.
    envmap : {"latlong", "cube"}, optional
        Write the standard ``envmap`` attribute: the image is an environment in OpenEXR's
        latitude-longitude or cube mapping (``ImfEnvmap.h``; bakeshop's layouts
        ``openexr-latlong`` and ``openexr-cube``, which :func:`bakeshop.io.write_environment`
        writes with it).
    """
    if pixel_type is not None:
        validate_choice(pixel_type, tuple(PIXEL_TYPES), "EXR pixel type")
    validate_choice(compression, tuple(COMPRESSIONS), "EXR compression")
    if envmap is not None:
        validate_choice(envmap, tuple(ENVMAPS), "EXR envmap")
    a = np.asarray(image)
    if a.dtype.kind not in "fiu":
        raise ArgumentError(f"cannot write {a.dtype} samples to OpenEXR")
    names = {1: "Y", 3: "RGB", 4: "RGBA"}[a.shape[2]]
    if pixel_type == "half":
        check_half(a, "pixel_type=float")
    elif pixel_type is None:
        peak = finite_peak(a)
        pixel_type = "half" if peak <= HALF_MAX else "float"
        if pixel_type == "float":
            warnings.warn(
                BakeshopWarning(
                    f"values reach {peak:.4g}, beyond the 65504 that half floats hold: "
                    "written as 32-bit floats"
                ),
                stacklevel=2,
            )
    if pixel_type == "half" and a.dtype == np.float32:
        planes = list(half_planes(a))  # converted and split in one pass
    else:
        a = a.astype(PIXEL_TYPES[pixel_type], copy=False)
        planes = [np.ascontiguousarray(a[:, :, i]) for i in range(a.shape[2])]
    channels = dict(zip(names, planes, strict=True))
    header = {"compression": COMPRESSIONS[compression], "type": OpenEXR.scanlineimage}
    if envmap is not None:
        header["envmap"] = ENVMAPS[envmap]
    _every_core()
    try:
        OpenEXR.File(header, channels).write(os.fspath(path))
    except MemoryError:
        raise
    except Exception as e:
        raise BakeshopError(f"OpenEXR could not write the file: {e}") from None
