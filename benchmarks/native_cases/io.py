"""Before/after cases of the io slice's kernels (issue 32): the old JIT (main before the
port) against the C++ kernels. Each case runs a function whose name and signature exist in both
trees; the inputs (and the files read) are made here, outside the thunks."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable

import numpy as np

from bakeshop.io import _quantize, ldr, rgbe, tga
from bakeshop.io.stream import rgbe as stream_rgbe


def cases() -> list[tuple[str, Callable[[], object]]]:
    folder = tempfile.mkdtemp(prefix="bakeshop-io-cases-")
    rng = np.random.default_rng(32)

    probe = np.exp(rng.normal(0, 2, (1024, 2048, 3))).astype(np.float32)
    probe[:, 600:1400] = probe[:, 599:600]  # sky-like runs
    hdr = os.path.join(folder, "probe.hdr")
    rgbe.write(hdr, probe)
    flat = os.path.join(folder, "flat.hdr")
    rgbe.write(flat, probe, rle=False)
    out_hdr = os.path.join(folder, "out.hdr")

    picture = rng.integers(0, 256, (2048, 2048, 4), dtype=np.uint8)
    picture[:, 512:1536] = picture[:, 511:512]  # runs for RLE
    tga_rle = os.path.join(folder, "rle.tga")
    tga.write(tga_rle, picture, rle=True)
    tga_flat = os.path.join(folder, "flat.tga")
    tga.write(tga_flat, picture)
    out_tga = os.path.join(folder, "out.tga")

    rows = rng.integers(0, 256, (1024, 2048 * 4), dtype=np.uint8)
    rows[:, 4096:] = rows[:, 4095:4096]
    filtered = np.empty((rows.shape[0], rows.shape[1] + 1), np.uint8)
    ldr._filter_rows(rows, 4, filtered)
    flat_filtered = filtered.reshape(-1)
    unfiltered = np.empty_like(rows)

    values = rng.random((2048, 4096, 3), dtype=np.float32) * 1.2 - 0.1

    return [
        ("io.rgbe read 2048x1024 rle", lambda: rgbe.read(hdr)),
        ("io.rgbe read 2048x1024 flat", lambda: rgbe.read(flat)),
        ("io.rgbe write 2048x1024 rle", lambda: rgbe.write(out_hdr, probe)),
        ("io.rgbe write 2048x1024 flat", lambda: rgbe.write(out_hdr, probe, rle=False)),
        ("io.rgbe stream index 2048x1024", lambda: stream_rgbe.open(hdr)._walk()),
        ("io.tga read rle 2048x2048 rgba", lambda: tga.read(tga_rle)),
        ("io.tga read 2048x2048 rgba", lambda: tga.read(tga_flat)),
        ("io.tga write rle 2048x2048 rgba", lambda: tga.write(out_tga, picture, rle=True)),
        ("io.png filter rows 2048x1024 rgba8", lambda: ldr._filter_rows(rows, 4, filtered)),
        (
            "io.png unfilter 2048x1024 rgba8",
            lambda: ldr._unfilter(flat_filtered, 0, rows.shape[0], rows.shape[1], 4, unfiltered),
        ),
        ("io.quantize 4096x2048x3 to 8 bits", lambda: _quantize.float_to_unsigned(values, 8)),
        ("io.quantize 4096x2048x3 to 16 bits", lambda: _quantize.float_to_unsigned(values, 16)),
    ]
