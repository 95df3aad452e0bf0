"""Detail layers of ``bakeshop normals combine``: ``--layer`` specs, per-layer placement
(tile, rotation, strength, by mask ids) and the layers they build."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click
import numpy as np

from bakeshop.cli._common import warn
from bakeshop.cli._numbers import Number, Numbers
from bakeshop.errors import ArgumentError
from bakeshop.normals.encoding import CONVENTIONS, read_normal_map

if TYPE_CHECKING:
    from bakeshop.normals.tiling import DetailLayer

FC = TypeVar("FC", bound=Callable[..., Any])

#: how a detail pattern is placed (options, and the keys of a --layer): repetitions and shift
#: (one number for both axes, or UxV), rotation in degrees, height scale.
PLACEMENT = {
    "tile": Numbers(-1e4, 1e4, count=2, sep="x", repeat=True),
    "offset": Numbers(-1e6, 1e6, count=2, sep="x", repeat=True),
    "rotate": Number(-360, 360),
    "strength": Number(-100, 100),
}


def placement_options(*, tile: str, rotate: str, strength: str) -> Callable[[FC], FC]:
    """The --tile, --offset, --rotate and --strength options that place a detail pattern."""
    options = [
        click.option(
            "--tile",
            type=PLACEMENT["tile"],
            default="1",
            show_default=True,
            metavar="N|UxV",
            help=tile,
        ),
        click.option(
            "--offset",
            type=PLACEMENT["offset"],
            default="0",
            show_default=True,
            metavar="U|UxV",
            help="Shift of the pattern, in tiles.",
        ),
        click.option(
            "--rotate",
            type=PLACEMENT["rotate"],
            default=0.0,
            show_default=True,
            metavar="DEG",
            help=rotate,
        ),
        click.option(
            "--strength",
            type=PLACEMENT["strength"],
            default=1.0,
            show_default=True,
            metavar="S",
            help=strength,
        ),
    ]

    def apply(command: FC) -> FC:
        for option in reversed(options):
            command = option(command)
        return command

    return apply


def _placement_value(key: str, value: object, path: Path) -> Any:
    """A --layer's ``key=value`` as the option of that name reads it (:data:`PLACEMENT`)."""
    try:
        return PLACEMENT[key].convert(value, None, None)
    except click.BadParameter as e:
        raise ArgumentError(f"invalid layer setting {key}={value}: {e.message}", path) from None


def _ids(texts: Sequence[str]) -> list[int | tuple[int, ...]]:
    """'3' -> 3 (grey level); '#ff8000' or '255,128,0' -> (255, 128, 0)."""
    ids: list[int | tuple[int, ...]] = []
    for text in texts:
        t = text.strip()
        try:
            if t.startswith("#") and len(t) == 7:
                ids.append(tuple(int(t[i : i + 2], 16) for i in (1, 3, 5)))
            elif "," in t or "/" in t:
                ids.append(tuple(int(v) for v in t.replace("/", ",").split(",")))
            else:
                ids.append(int(t))
            if not all(0 <= v <= 255 for v in np.atleast_1d(ids[-1])):
                raise ValueError
        except ValueError:
            raise ArgumentError(
                f"invalid material ID {text!r}: a grey level 0-255, #rrggbb or r/g/b"
            ) from None
    return ids


_LAYER_KEYS = ("tile", "offset", "rotate", "strength", "mask", "id", "convention")


def parse_layer(spec: str) -> dict:
    """``'grit.png,tile=16,rotate=30,mask=barrel.png'`` -> the layer's settings."""
    path, *pairs = spec.split(",")
    layer: dict[str, Any] = {"path": Path(path), "ids": []}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        key = key.strip()
        if not sep or key not in _LAYER_KEYS:
            raise ArgumentError(
                f"invalid layer setting {pair!r} in {spec!r}: use KEY=VALUE with KEY one of "
                + ", ".join(_LAYER_KEYS)
            )
        if key == "id":
            layer["ids"].append(value)
        else:
            layer[key] = value
    if not layer["path"].is_file():
        raise ArgumentError("detail layer file not found", layer["path"])
    return layer


#: degrees of relief below which a tiled detail counts as filtered away.
MIN_RELIEF = 1.0


def read_map(
    path: str | os.PathLike, convention: str, encoding: str, option: str
) -> tuple[np.ndarray, int | None]:
    """A normal map's unit normals and sample depth (:func:`read_normal_map`), with a warning
    when its content says its green channel is the other convention than ``option`` chose
    (:func:`~bakeshop.normals.encoding.guess_convention`)."""
    from bakeshop.normals.encoding import guess_convention

    normals, bits = read_normal_map(path, convention=convention, encoding=encoding, with_bits=True)
    guess, share = guess_convention(normals)
    if guess == "dx":
        other = "dx" if convention == "gl" else "gl"
        warn(
            f"read as {convention}, its slopes do not form a surface ({share:.0%} of their curl "
            f"is explained by a flipped green channel): it looks {other}; check {option}",
            path,
        )
    return normals, bits


def build_layers(
    shape: tuple[int, int],
    settings: Sequence[dict[str, Any]],
    method_convention: str,
    encoding: str,
    depths: list[int | None] | None = None,
) -> list[DetailLayer]:
    """Read each layer's detail map and mask into DetailLayer objects; each detail map's
    :func:`~bakeshop.io.stored_bits` is appended to ``depths``."""
    from bakeshop.io import read_image
    from bakeshop.normals.tiling import DetailLayer, as_pair, filtered_relief, mask_weights

    layers = []
    for s in settings:
        convention = s.get("convention") or method_convention
        if convention not in CONVENTIONS:
            raise ArgumentError(f"unknown convention {convention!r} for layer", s["path"])
        option = "convention= of the layer" if s.get("convention") else "--detail-convention"
        detail, bits = read_map(s["path"], convention, encoding, option)
        if depths is not None:
            depths.append(bits)
        mask = None
        if s.get("mask"):
            mask = mask_weights(read_image(s["mask"]), shape, ids=_ids(s["ids"]) or None)
        elif s["ids"]:
            raise ArgumentError("a material ID needs a mask (the ID map)", s["path"])
        place = {
            key: _placement_value(key, s.get(key, default), s["path"])
            for key, default in (("tile", "1"), ("offset", "0"), ("rotate", 0.0), ("strength", 1))
        }
        authored, left = filtered_relief(detail, shape, tile=place["tile"])
        if left < MIN_RELIEF <= authored:
            tiles = "x".join(f"{t:g}" for t in as_pair(place["tile"], "tile"))
            warn(
                f"tiled {tiles} times over {shape[1]}x{shape[0]} texels, "
                f"filtering leaves {left:.1f} of its {authored:.1f} degrees of relief: lower "
                "--tile (tile= of a layer) or combine onto a larger map",
                s["path"],
            )
        layers.append(
            DetailLayer(
                detail,
                tile=place["tile"],
                offset=place["offset"],
                rotation=place["rotate"],
                strength=place["strength"],
                mask=mask,
            )
        )
    return layers
