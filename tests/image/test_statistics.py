"""bakeshop.image.statistics against hand-computed values (ITU-R BT.709 luminance)."""

import numpy as np
import pytest

from bakeshop.image import describe, luminance


def test_luminance_is_the_bt709_weighted_sum():
    rgb = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [2.0, 4.0, 8.0]])
    np.testing.assert_allclose(luminance(rgb), [0.2126, 0.7152, 0.0722, 3.8636], rtol=1e-12)
    rgba = np.concatenate([rgb, np.full((4, 1), 9.0)], axis=1)
    np.testing.assert_array_equal(luminance(rgba), luminance(rgb))  # alpha ignored
    grey = np.array([[0.5], [3.0]])
    np.testing.assert_array_equal(luminance(grey), [0.5, 3.0])


def test_describe_counts_and_ranges():
    img = np.array(
        [[[1.0, 2.0, 3.0], [0.25, np.nan, 1.0]], [[np.inf, 0.5, 0.5], [4.0, 8.0, 12.0]]],
        np.float32,
    )
    d = describe(img)
    assert d["shape"] == [2, 2, 3] and d["nan"] == 1 and d["inf"] == 1
    red = d["channels"][0]
    assert red == {"min": 0.25, "max": 4.0, "mean": pytest.approx((1 + 0.25 + 4) / 3)}
    # finite positive luminances: (1, 2, 3) and (4, 8, 12): 1.8596 and 7.4384, 2 stops apart
    assert d["dynamic_range_stops"] == pytest.approx(2.0)


def test_describe_edge_cases():
    assert describe(np.zeros((2, 2)))["dynamic_range_stops"] is None
    empty = describe(np.full((1, 1, 1), np.nan))
    assert empty["channels"] == [{"min": None, "max": None, "mean": None}] and empty["nan"] == 1
