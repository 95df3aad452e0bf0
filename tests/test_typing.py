"""The Literal modes of bakeshop._typing name exactly what the functions accept at run time,
and the Face enum is the cube's face axis."""

import numpy as np
import pytest

from bakeshop import image, light, sphere
from bakeshop._typing import (
    Convention,
    Face,
    Filter,
    IrradianceMethod,
    LayoutName,
    ToneOperator,
    choices,
)
from bakeshop.errors import ArgumentError


@pytest.mark.parametrize(
    ("alias", "runtime"),
    [
        (LayoutName, sphere.LAYOUT_NAMES),
        (Filter, sphere.FILTERS),
        (Convention, tuple(sphere.CONVENTIONS)),
        (IrradianceMethod, light.METHODS),
        (ToneOperator, image.TONE_OPERATORS),
    ],
)
def test_each_literal_is_the_list_its_function_checks(alias, runtime):
    assert choices(alias) == tuple(runtime)


def test_a_value_outside_the_literal_is_refused_at_run_time():
    with pytest.raises(ArgumentError, match="equirect"):
        sphere.layout("equirect")
    with pytest.raises(ArgumentError, match="gaussian"):
        sphere.remap(np.ones((8, 16, 3), np.float32), "latlong", "cube", 4, filter="gaussian")


def test_faces_are_the_cube_axis_in_opengl_order():
    assert [f.value for f in Face] == list(range(6))
    assert len(Face) == len(sphere.FACE_NAMES) == 6
    short = [("p" if f.name.startswith("POSITIVE") else "n") + f.name[-1].lower() for f in Face]
    assert short == list(sphere.FACE_NAMES_SHORT)
    # a cube's face axis indexes by Face: +Y's centre looks up
    dirs, _ = sphere.layout("cube").directions((6, 3, 3))
    np.testing.assert_allclose(dirs[Face.POSITIVE_Y, 1, 1], [0.0, 1.0, 0.0], atol=1e-12)
