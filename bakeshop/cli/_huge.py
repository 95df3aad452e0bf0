"""The options of the commands that run on images larger than memory (``--memory``,
``--scheduler``) and the rule for when they take the chunked path."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import click

from bakeshop.cli._numbers import MemorySize
from bakeshop.huge.scheduler import CONNECT_TIMEOUT, LOCAL_SCHEDULERS, scheduler_address
from bakeshop.io.stream import Reader

if TYPE_CHECKING:
    import numpy as np

    from bakeshop.huge import Engine

memory_option = click.option(
    "--memory",
    type=MemorySize(),
    metavar="SIZE",
    help="Memory bound of the job (and of each dask worker's tasks), e.g. 2GB or 1.5GiB; the "
    "job is cut into blocks that fit, or refused before it starts with the size it needs. "
    "Default: half of the memory available now (or BAKESHOP_MEMORY); 4 MiB to 1 PB.",
)


def _check_scheduler(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """Refuse a malformed address before the command reads anything."""
    if value is not None and value not in LOCAL_SCHEDULERS:
        scheduler_address(value)
    return value


scheduler_option = click.option(
    "--scheduler",
    metavar="ADDRESS",
    callback=_check_scheduler,
    help="Run the blocks on a dask.distributed cluster, tcp://HOST:PORT or tls://HOST:PORT (its "
    "workers must see the input file: a shared disk; .zarr is best); a scheduler not reached "
    f"within {CONNECT_TIMEOUT} s is an error. Default: BAKESHOP_SCHEDULER, else threads on "
    "this machine.",
)


def engine(memory: int | str | None, scheduler: str | None) -> Engine:
    """The :class:`bakeshop.huge.Engine` of the options."""
    from bakeshop.huge import Engine

    return Engine(scheduler, memory)


def chunked(source: str | os.PathLike, memory: int | str | None, scheduler: str | None) -> bool:
    """True when a command should run chunked: asked for (--memory, --scheduler,
    BAKESHOP_SCHEDULER), or the input is a chunked store (.zarr, .tif), or its decoded pixels
    would take more than a quarter of the memory bound."""
    from bakeshop.io.stream import STREAM_CODECS

    suffix = str(source).lower().rsplit(".", 1)[-1]
    if f".{suffix}" in STREAM_CODECS["zarr"] + STREAM_CODECS["tiff"]:
        return True
    if memory is not None or scheduler is not None or os.environ.get("BAKESHOP_SCHEDULER"):
        return True
    if not any(f".{suffix}" in exts for exts in STREAM_CODECS.values()):
        return False
    from bakeshop.huge.memory import resolve_memory
    from bakeshop.io.stream import open_image

    try:
        reader = open_image(source)
    except Exception:  # the in-memory reader says what is wrong with the file
        return False
    return reader.nbytes > resolve_memory(None) // 4


def open_fitted(
    source: str | os.PathLike, how: str | None, *targets: str | os.PathLike | None
) -> Reader:
    """The stream reader of ``source`` with its alpha made fit for ``targets`` window by window,
    by the rule of :func:`bakeshop.cli._common.fit_alpha` (``--alpha``): a window whose alpha is
    not 1 is refused when ``how`` is None, so an alpha of 1 is dropped without a pass of its own
    (its note is said first)."""
    from bakeshop.cli._common import rgb_only
    from bakeshop.io.stream import open_image

    reader = open_image(source)
    outputs = rgb_only(*targets)
    if reader.shape[2] != 4 or not outputs:
        return reader
    if how is None:
        suffix = Path(outputs[0]).suffix
        click.echo(f"{source}: alpha dropped as it is read ({suffix} stores RGB only; "
                   "an alpha other than 1 stops the command)")  # fmt: skip
    return _AlphaFitted(reader, how, outputs[0])


class _AlphaFitted(Reader):
    """``reader``'s colour, its alpha dropped or premultiplied as each window is read."""

    def __init__(self, reader: Reader, how: str | None, target: str | os.PathLike) -> None:
        self.reader, self.how, self.target = reader, how, target
        self.path, self.stored, self.format = reader.path, reader.stored, reader.format
        self.block, self.read_floor = reader.block, reader.read_floor
        h, w, _ = reader.shape
        self.shape = (h, w, 3)

    def _read(self, top: int, bottom: int, left: int, right: int) -> np.ndarray:
        from bakeshop.cli._common import fit_alpha

        window = self.reader.read((top, bottom), (left, right))
        return fit_alpha(window, self.how, self.path or "", self.target, note=False)
