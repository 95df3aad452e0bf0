"""Pictures of floating runs (bakeshop.buoyancy.plots): the size and type a caller gets, and
that what is asked for is drawn (a draft line, a cell per treatment and frame rate)."""

import numpy as np

from bakeshop.buoyancy.matrix import Matrix
from bakeshop.buoyancy.plots import plot_grid, plot_trace

TIME = np.linspace(0.0, 4.0, 200)
CLEAR = np.stack([np.cos(3 * TIME) - 0.5, 0.5 * np.sin(2 * TIME) - 0.2], axis=1)


def test_a_trace_is_an_rgb_picture_of_the_figure_size():
    picture = plot_trace(TIME, CLEAR, labels=["box", "sphere"], title="two bodies")
    assert picture.dtype == np.uint8
    # 3.4 in of plot and one 0.16 in row of legend below (three entries: the surface, two bodies)
    assert picture.shape == (round((3.4 + 0.16) * 90), 8 * 90, 3)
    assert picture.std() > 0  # something is drawn


def test_the_expected_draft_is_drawn_when_given():
    plain = plot_trace(TIME, CLEAR[:, :1], labels=["box"], title="one")
    with_draft = plot_trace(TIME, CLEAR[:, :1], labels=["box"], title="one", draft=[0.5])
    skipped = plot_trace(TIME, CLEAR[:, :1], labels=["box"], title="one", draft=[None])
    assert np.any(plain != with_draft)
    np.testing.assert_array_equal(plain, skipped)


def test_the_grid_has_a_panel_per_treatment_and_frame_rate():
    clearances = {
        ("per-frame", t, f): (TIME, CLEAR) for t in ("none", "team", "drag") for f in (30, 60)
    }
    clearances[("per-substep", "none", 30)] = (TIME, CLEAR)  # another force mode: left out
    matrix = Matrix(("box", "sphere"), [], clearances)
    picture = plot_grid(matrix, forces="per-frame")
    assert picture.dtype == np.uint8
    # 1.7 in per treatment and a 0.3 in row of legend below the grid
    assert picture.shape == (round((1.7 * 3 + 0.3) * 80), round(2.6 * 2 * 80), 3)
