"""What saves must load: every file written is read back by bakeshop and compared with what was
meant to be written, before it takes its name.

Within :func:`verify_writes`, each :func:`bakeshop.io.atomic_path` write is checked when its
temporary file is complete and before it is renamed over the target: a file that does not
reload, or reloads as something else than was written, raises
:class:`~bakeshop.errors.FormatError` naming the target, and the target is left as it was.

The writers say what they meant (:func:`intent`): an image and its codec's options
(:func:`bakeshop.io.write_image`), a mip chain and its sample type (the DDS, KTX and KTX2
writers), block-compressed levels, a JSON document, a text. The comparison is the format's:

============================  ===============================================================
format                        the file must read back as
============================  ===============================================================
PFM, EXR float, TIFF 32       the float32 values, bit for bit
EXR half, DDS/KTX/KTX2 half   the float16 values (round to nearest even, finite values beyond
                              +-65504 clamped), bit for bit
Radiance RGBE                 within half a mantissa step of the pixel's largest component:
                              ``|read - max(v, 0)| <= 2**-8 * max(r, g, b)`` (+ 2**-128)
PNG, TGA, TIFF 8/16, unorm8   the integer codes ``rint(clip(v, 0, 1) * (2**n - 1))`` (float32
                              arithmetic, NaN -> 0), exactly
JPEG                          those codes within :data:`JPEG_MIN_PSNR` dB PSNR
EXR lossy compressions        loads with the same shape (error recorded, no bound stated)
block-compressed textures     the same blocks, byte for byte (the encoder's own error is the
                              quality sidecar's)
JSON                          the same document; text: the same characters
anything else                 loads through bakeshop's reader for its extension
============================  ===============================================================

Each check is a record (a dict: ``file``, ``writer``, ``check``, ``ok``, ``max_error``,
``tolerance``, ``reason``, ``seconds``), collected by the session and, with ``log``,
appended to a JSON-lines file as it is made. ``bakeshop bake`` (:mod:`bakeshop.bake`) keeps
these records in its manifest as each output's reload proof. A check costs a read of the file
and a comparison: about as much again as the write, more for RGBE (measured on a loaded 2-core
machine: a 6 x 512^2 half-float DDS chain 0.68 s to write, 1.56 s with its check; a 2048x1024
EXR 1.37 s / 2.36 s; the same as RGBE 0.36 s / 1.96 s).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from bakeshop.errors import BakeshopError
from bakeshop.io import _intent
from bakeshop.io._intent import intent

if TYPE_CHECKING:
    from bakeshop.io.compress.texture import BlockTexture


__all__ = ["JPEG_MIN_PSNR", "check_file", "intent", "verify_writes", "verifying"]

#: the PSNR (dB, over the 8-bit codes) a JPEG must keep against the codes it was given: the
#: stated error of bakeshop's JPEG writer (quality 95, no chroma subsampling).
JPEG_MIN_PSNR = 30.0
#: EXR compressions that lose information (their error is recorded, not bounded).
EXR_LOSSY = frozenset({"b44", "b44a", "dwaa", "dwab"})
#: extensions of text documents bakeshop writes.
TEXT_EXTENSIONS = frozenset({".glsl", ".hlsl", ".txt", ".md", ".csv", ".toml"})


def verifying() -> bool:
    """True while a :func:`verify_writes` session is open (in any thread)."""
    return _intent.verifying()


@contextlib.contextmanager
def verify_writes(
    log: str | os.PathLike | None = None,
    *,
    this_thread: bool = False,
    guard: Callable[[Path, Path], object] | None = None,
) -> Iterator[list[dict]]:
    """Check every file written within the block (see the module notes).

    Parameters
    ----------
    log : path-like, optional
        A JSON-lines file each check's record is appended to, as it is made.
    this_thread : bool
        Check (and record) only the files the calling thread writes: one session per task
        when tasks run at once.
    guard : callable, optional
        Called with each target and its complete temporary file before the check and the
        rename; it raises a :class:`~bakeshop.errors.BakeshopError` to refuse the write (a
        bake refuses a file outside its step's output, or one it did not write itself, and
        journals the others).

    Yields
    ------
    list of dict
        The records, in the order the files were written.
    """
    with _intent.session(check_file, log, this_thread=this_thread, guard=guard) as records:
        yield records


def check_file(
    path: str | os.PathLike, kind: str | None = None, data: Any = None, **context: Any
) -> dict:
    """Read ``path`` back through bakeshop and compare it with ``data`` (see the module notes).

    Returns
    -------
    dict
        The record: ``writer`` (what was checked), ``check`` (``"exact"``, ``"within"``,
        ``"loads"``), ``ok``, ``max_error`` and ``tolerance`` (None when exact or unbounded),
        ``reason`` (why it failed, or what was checked), ``seconds``.
    """
    started = time.perf_counter()
    path = Path(path)
    try:
        record = _CHECKS.get(kind, _loads)(path, data, **context)
    except BakeshopError as e:
        record = _record(kind or "file", "loads", False, reason=e.reason)
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        record = _record(kind or "file", "loads", False, reason=f"{type(e).__name__}: {e}")
    record["seconds"] = round(time.perf_counter() - started, 6)
    return record


def _record(
    writer: str,
    check: str,
    ok: bool | np.bool_,
    *,
    max_error: float | None = None,
    tolerance: float | None = None,
    reason: str = "",
) -> dict:
    def number(v: float | None) -> float | None:
        return None if v is None or not math.isfinite(v) else float(v)

    return {
        "writer": writer,
        "check": check,
        "ok": bool(ok),
        "max_error": number(max_error),
        "tolerance": number(tolerance),
        "reason": reason,
    }


# --- loads (no intent) ---------------------------------------------------------------------------


def _loads(path: Path, data: object = None, **context: object) -> dict:
    """Load-only check by extension: an image (its header, when a streaming reader exists),
    a container, a JSON document, a text."""
    from bakeshop.io import CODECS
    from bakeshop.io.containers import is_container, read_container

    ext = path.suffix.lower()
    if is_container(path):
        mips, meta = read_container(path)
        what = f"{meta.get('stored')} {tuple(mips[0].shape)}, {len(mips)} level(s)"
        return _record("container", "loads", True, reason=f"loads: {what}")
    if any(ext in exts for exts in CODECS.values()):
        from bakeshop.io import read_image

        image, meta = read_image(path, with_metadata=True)
        return _record("image", "loads", True, reason=f"loads: {meta.get('stored')} {image.shape}")
    if ext == ".json":
        from bakeshop.io.documents import read_json

        read_json(path)
        return _record("json", "loads", True, reason="loads: a JSON object")
    if ext in TEXT_EXTENSIONS:
        path.read_bytes().decode("utf-8")
        return _record("text", "loads", True, reason="loads: UTF-8 text")
    return _record("file", "loads", False, reason=f"bakeshop has no reader for {ext or 'it'}")


# --- images --------------------------------------------------------------------------------------


def _image(path: Path, image: ArrayLike, *, codec: str, options: dict) -> dict:
    from bakeshop.io import read_image

    intended = np.asarray(image)
    if intended.ndim == 2:
        intended = intended[:, :, None]
    read, meta = read_image(path, with_metadata=True)
    writer = f"image:{codec}"
    if read.shape[:2] != intended.shape[:2]:
        return _record(
            writer, "loads", False, reason=f"reads as {read.shape}, written {intended.shape}"
        )
    if read.shape[2] != intended.shape[2]:
        if not (intended.shape[2] == 1 and read.shape[2] == 3):
            return _record(
                writer,
                "loads",
                False,
                reason=f"reads {read.shape[2]} channels, written {intended.shape[2]}",
            )
        read = read[..., :1] if np.array_equal(read[..., :1], read[..., 1:2]) else read
        if read.shape[2] != 1:
            return _record(writer, "exact", False, reason="a grey image reads back coloured")
    stored = str(meta.get("stored", ""))
    if codec == "rgbe":
        return _rgbe(writer, read, intended)
    if stored.startswith("uint"):
        bits = int("".join(c for c in stored if c.isdigit()) or 8)
        return _codes(
            writer,
            read,
            intended,
            bits,
            jpeg=codec == "ldr" and path.suffix.lower() in (".jpg", ".jpeg"),
        )
    if codec == "exr" and options.get("compression") in EXR_LOSSY:
        err = float(np.nanmax(np.abs(read - intended))) if read.size else 0.0
        return _record(
            writer,
            "loads",
            True,
            max_error=err,
            reason=f"lossy {options['compression']} compression: error recorded",
        )
    half = stored in ("half", "float16")
    return _floats(writer, read, intended, half=half)


def _as_float(intended: np.ndarray) -> np.ndarray:
    if intended.dtype.kind in "ui":
        return intended.astype(np.float32)
    with np.errstate(over="ignore"):
        return intended.astype(np.float32)


def _half(values: np.ndarray) -> np.ndarray:
    """float16 by round-to-nearest-even, finite values beyond +-65504 clamped (independent of
    the codecs' own conversion)."""
    with np.errstate(over="ignore", invalid="ignore"):
        half = values.astype(np.float16)
        wild = np.isinf(half) & np.isfinite(values)
    half[wild] = np.copysign(np.float16(65504.0), values[wild])
    return half.astype(np.float32)


def _floats(writer: str, read: np.ndarray, intended: np.ndarray, *, half: bool) -> dict:
    want = _as_float(intended)
    if half:
        want = _half(want)
    same = np.array_equal(read.view(np.uint32), want.view(np.uint32)) or np.array_equal(
        read, want, equal_nan=True
    )
    if same:
        return _record(writer, "exact", True, reason="bit-exact" + (" (half)" if half else ""))
    with np.errstate(invalid="ignore"):
        err = float(np.nanmax(np.abs(read - want)))
    return _record(
        writer,
        "exact",
        False,
        max_error=err,
        reason=f"values differ from those written by up to {err:.6g}",
    )


def _rgbe(writer: str, read: np.ndarray, intended: np.ndarray) -> dict:
    want = np.nan_to_num(_as_float(intended), nan=0.0, posinf=1.7e38)
    want = np.clip(want, 0.0, 1.7e38)
    peak = want.max(axis=2, keepdims=True)
    bound = peak * 2.0**-8 + 2.0**-128
    err = np.abs(read.astype(np.float64) - want)
    ratio = float(np.max(err / bound)) if err.size else 0.0
    ok = ratio <= 1.0 + 1e-6
    worst = float(err.max()) if err.size else 0.0
    return _record(
        writer,
        "within",
        ok,
        max_error=ratio,
        tolerance=1.0,
        reason=f"RGBE: largest error {ratio:.3f} of the stated bound 2^-8 x the "
        f"pixel's largest component (absolute {worst:.3g})",
    )


def _codes(
    writer: str, read: np.ndarray, intended: np.ndarray, bits: int, *, jpeg: bool = False
) -> dict:
    top = (1 << bits) - 1
    got = np.rint(read.astype(np.float64) * top)
    if intended.dtype.kind == "u":
        want = intended.astype(np.float64)
        if intended.dtype == np.uint8 and bits == 16:
            want = want * 257
    else:
        # the stated quantisation, in float32 as the writers compute it (a float64 product
        # rounds the other way for a value within float32's rounding of a half code)
        with np.errstate(over="ignore", invalid="ignore"):
            v = np.nan_to_num(intended.astype(np.float32), nan=0.0)
        want = np.rint(np.clip(v, 0, 1) * np.float32(top)).astype(np.float64)
    if jpeg:
        mse = float(np.mean((got - want) ** 2))
        psnr = math.inf if mse == 0 else 10 * math.log10(top * top / mse)
        return _record(
            writer,
            "within",
            psnr >= JPEG_MIN_PSNR,
            max_error=-psnr,
            tolerance=-JPEG_MIN_PSNR,
            reason=f"JPEG: {psnr:.2f} dB PSNR against the codes written "
            f"(at least {JPEG_MIN_PSNR:g} dB)",
        )
    diff = float(np.max(np.abs(got - want))) if got.size else 0.0
    return _record(
        writer,
        "exact",
        diff == 0,
        max_error=diff,
        reason=f"{bits}-bit codes " + ("exact" if diff == 0 else f"differ by up to {diff:g}"),
    )


# --- containers, blocks, documents ---------------------------------------------------------------


def _mips(path: Path, mips: Sequence[ArrayLike], *, dtype: str, array: bool = False) -> dict:
    from bakeshop.io.containers import read_container

    read, meta = read_container(path)
    writer = f"mips:{path.suffix.lower()[1:]}"
    levels = [np.asarray(m) for m in mips]
    if len(read) != len(levels):
        return _record(
            writer, "loads", False, reason=f"reads {len(read)} levels, written {len(levels)}"
        )
    for m, (got, want) in enumerate(zip(read, levels, strict=True)):
        if want.ndim == 2:
            want = want[:, :, None]
        if got.shape[:-1] != want.shape[:-1] and got.size == want.size * got.shape[-1] // max(
            1, want.shape[-1]
        ):
            got = got.reshape(want.shape[:-1] + got.shape[-1:])
        if got.shape[-1] == 4 and want.shape[-1] == 3:  # RGB is padded with an opaque alpha
            if not np.all(got[..., 3] == 1):
                return _record(writer, "exact", False, reason=f"level {m}: the pad alpha is not 1")
            got = got[..., :3]
        if got.shape != want.shape:
            return _record(
                writer,
                "loads",
                False,
                reason=f"level {m} reads as {got.shape}, written {want.shape}",
            )
        if dtype == "unorm8":
            r = _codes(writer, got, want, 8)
        else:
            r = _floats(writer, got, want, half=dtype == "float16")
        if not r["ok"]:
            r["reason"] = f"level {m}: {r['reason']}"
            return r
    return _record(writer, "exact", True, reason=f"{len(levels)} level(s) bit-exact ({dtype})")


def _blocks(path: Path, texture: BlockTexture) -> dict:
    ext = path.suffix.lower()
    if ext == ".dds":
        from bakeshop.io.dds import read_dds_blocks as read
    elif ext == ".ktx2":
        from bakeshop.io.ktx2 import read_ktx2_blocks as read
    else:
        from bakeshop.io.ktx import read_ktx_blocks as read
    got, _ = read(path)
    writer = f"blocks:{ext[1:]}"
    if got.format.name != texture.format.name or len(got.levels) != len(texture.levels):
        return _record(
            writer,
            "loads",
            False,
            reason=f"reads {got.format.name} x{len(got.levels)} levels, written "
            f"{texture.format.name} x{len(texture.levels)}",
        )
    for m, (a, b) in enumerate(zip(got.levels, texture.levels, strict=True)):
        if bytes(a) != bytes(b):
            return _record(writer, "exact", False, reason=f"level {m}: the blocks differ")
    return _record(
        writer,
        "exact",
        True,
        reason=f"{texture.format.name} blocks byte-exact, {len(texture.levels)} level(s)",
    )


def _json(path: Path, document: dict) -> dict:
    from bakeshop.io.documents import _plain, read_json

    got = read_json(path)
    want = json.loads(json.dumps(_plain(document), allow_nan=False))
    ok = got == want
    return _record(
        "json",
        "exact",
        ok,
        reason="the same document" if ok else "the document read back differs from the one written",
    )


def _text(path: Path, text: str) -> dict:
    got = path.read_bytes().decode("utf-8")
    want = text if text.endswith("\n") else text + "\n"
    ok = got == want
    return _record("text", "exact", ok, reason="the same text" if ok else "the text differs")


#: the check of each kind of intent; a file written without one is only loaded (:func:`_loads`).

_CHECKS: dict[str | None, Callable[..., dict]] = {
    "image": _image,
    "mips": _mips,
    "blocks": _blocks,
    "json": _json,
    "text": _text,
}
