"""Texture sets of the ``bakeshop water`` commands: numbered frames, flipbook atlases or texture
arrays, their previews, and the ``--outputs`` list."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from bakeshop.errors import ArgumentError


def _write_png(path: Path, values: np.ndarray, bits: int) -> None:
    from bakeshop.io import write_image

    write_image(path, values, bits=bits)


def _write_exr(path: Path, values: np.ndarray) -> None:
    from bakeshop.io import write_image

    write_image(path, np.asarray(values, np.float32), pixel_type="float")


def _write_container(path: Path, layers: np.ndarray, dtype: str, kind: str, mips: bool) -> None:
    from bakeshop.io.dds import write_dds
    from bakeshop.io.ktx2 import write_ktx2
    from bakeshop.water.textures import box_mips, normal_mips

    side = layers.shape[1]
    if mips and side & (side - 1) == 0:
        if kind == "normal":
            # renormalised 2x2 means of the unit vectors, re-packed
            from bakeshop.water.textures import pack_normals

            chain = [pack_normals(m) for m in normal_mips(layers * 2 - 1)]
        elif kind == "normal_xy":
            from bakeshop.water.textures import pack_normals, unpack_normals

            chain = [pack_normals(m, channels="xy") for m in normal_mips(unpack_normals(
                layers, channels="xy").astype(np.float32))]  # fmt: skip
        else:
            chain = box_mips(layers)
    else:
        chain = [layers]
    writer = write_ktx2 if path.suffix == ".ktx2" else write_dds
    writer(path, chain, dtype=dtype, array=True)


class TextureSet:
    """Receives frames of named outputs in batches and writes them as numbered frames, a
    flipbook atlas or a texture array. Each output is (kind, channels, encoding)."""

    def __init__(self, out_dir: Path, name: str, layout: str, *, container: str,
                 columns: int | None, gutter: int, mips: bool, frames: int) -> None:  # fmt: skip
        self.out_dir, self.name, self.layout = out_dir, name, layout
        self.container, self.columns, self.gutter, self.mips = container, columns, gutter, mips
        self.frames = frames
        self.gathered: dict[str, list] = {}
        self.files: list[dict] = []
        self.formats: dict[str, str] = {}

    def frame_path(self, output: str, index: int, ext: str) -> Path:
        """The file of one frame of one output: ``NAME_OUTPUT_0001.EXT``."""
        digits = max(4, len(str(self.frames - 1)))
        return self.out_dir / f"{self.name}_{output}_{index:0{digits}d}{ext}"

    def add(self, output: str, values: np.ndarray, fmt: str, indices: Iterable[int]) -> None:
        """``values`` (B, N, N, C) float32 texel values ready to store (packed normals in
        [0, 1], metres for heights ...) for frames ``indices``; ``fmt`` is png8, png16, exr."""
        self.formats[output] = fmt
        if self.layout == "frames":
            ext = ".exr" if fmt == "exr" else ".png"
            for value, f in zip(values, indices, strict=True):
                path = self.frame_path(output, int(f), ext)
                if fmt == "exr":
                    _write_exr(path, value)
                else:
                    _write_png(path, value, 16 if fmt == "png16" else 8)
            return
        self.gathered.setdefault(output, []).append(values.astype(np.float32))

    def finish(self) -> None:
        """Write the gathered frames as flipbooks or arrays, and the sidecar."""
        from bakeshop.water.textures import flipbook

        if self.layout == "frames":
            digits = max(4, len(str(self.frames - 1)))
            for output, fmt in self.formats.items():
                ext = ".exr" if fmt == "exr" else ".png"
                pattern = f"{self.name}_{output}_{'#' * digits}{ext}"
                self.files.append({"output": output, "layout": "frames", "pattern": pattern,
                                   "format": fmt})  # fmt: skip
            return
        for output, parts in self.gathered.items():
            fmt = self.formats[output]
            stack = np.concatenate(parts).astype(np.float32)
            if self.layout == "atlas":
                atlas, layout = flipbook(stack, columns=self.columns, gutter=self.gutter)
                ext = ".exr" if fmt == "exr" else ".png"
                path = self.out_dir / f"{self.name}_{output}_atlas{ext}"
                if fmt == "exr":
                    _write_exr(path, atlas)
                else:
                    _write_png(path, atlas, 16 if fmt == "png16" else 8)
                self.files.append({"output": output, "layout": "atlas", "file": path.name,
                                   "format": fmt, "atlas": layout})  # fmt: skip
            else:
                path = self.out_dir / f"{self.name}_{output}.{self.container}"
                dtype = {"png8": "unorm8", "png16": "float16", "exr": "float32"}[fmt]
                if output == "normal" and fmt == "png8" and stack.shape[-1] == 2:
                    kind = "normal_xy"
                else:
                    kind = "normal" if output == "normal" else output
                if fmt == "png16" and output == "normal":
                    dtype = "float16"
                _write_container(path, stack, dtype, kind, self.mips)
                self.files.append({"output": output, "layout": "array", "file": path.name,
                                   "format": dtype, "layers": int(stack.shape[0]),
                                   "mips": bool(self.mips)})  # fmt: skip


def _write_previews(out_dir: Path, name: str, frames: np.ndarray, tiled: np.ndarray) -> list:
    """Shaded frame grid and the 2x2 tiling of frame 0, sRGB PNGs."""
    from bakeshop.image import to_srgb8
    from bakeshop.io import write_image
    from bakeshop.water.textures import grid, shade, tile

    shaded = np.stack([shade(f) for f in frames])
    grid_path = out_dir / f"{name}_preview_frames.png"
    tiled_path = out_dir / f"{name}_preview_tiled.png"
    write_image(grid_path, to_srgb8(grid(shaded, border=2)))
    write_image(tiled_path, to_srgb8(tile(shade(tiled), 2)))
    return [grid_path.name, tiled_path.name]


def _preview_indices(frames: int, count: int = 16) -> np.ndarray:
    return np.unique(np.linspace(0, frames - 1, min(count, frames)).round().astype(int))


def _parse_outputs(text: str, allowed: Sequence[str]) -> list[str]:
    names = [t.strip() for t in text.split(",") if t.strip()]
    bad = [n for n in names if n not in allowed]
    if not names or bad:
        raise ArgumentError(
            f"unknown output {', '.join(map(repr, bad)) or repr(text)}; choose from: "
            + ", ".join(allowed)
        )
    return list(dict.fromkeys(names))
