"""Figures drawn off-screen with matplotlib's object API (never pyplot's global state), and
turned into RGB arrays that :func:`bakeshop.io.write_image` saves.

A library function that draws returns a :class:`matplotlib.figure.Figure` or its pixels, so a
notebook can show it and the command line can write it; importing this module never changes
the caller's matplotlib backend.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from bakeshop.errors import ArgumentError

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def new_figure(width: float, height: float, *, dpi: int = 100) -> Figure:
    """A :class:`matplotlib.figure.Figure` of ``width`` x ``height`` inches on its own Agg
    canvas (so it renders without a display and without touching pyplot)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def to_rgb(fig: Figure) -> np.ndarray:
    """The figure's pixels: ``(H, W, 3)`` uint8 sRGB (the figure is on an Agg canvas, as
    :func:`new_figure` makes them)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas
    if not isinstance(canvas, FigureCanvasAgg):
        raise ArgumentError("to_rgb reads figures on an Agg canvas (bakeshop.figures.new_figure)")
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()
