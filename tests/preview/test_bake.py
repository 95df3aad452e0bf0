"""Reading a bake folder, and the hints when something the preview needs is missing."""

import sys

import numpy as np
import pytest

from bakeshop.errors import ArgumentError, FormatError, UnsupportedError
from bakeshop.io import write_image
from bakeshop.preview import Renderer, read_bake
from tests.preview.bakes import synthetic_bake


def test_a_missing_moderngl_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "moderngl", None)  # import moderngl raises ImportError
    with pytest.raises(UnsupportedError, match=r"pip install 'bakeshop\[preview\]'"):
        Renderer(synthetic_bake())


def test_a_folder_without_a_bake_names_what_was_looked_for(tmp_path):
    with pytest.raises(ArgumentError, match="env_posx"):
        read_bake(tmp_path)
    for face in ("posx", "negx", "posy", "negy", "posz", "negz"):
        write_image(tmp_path / f"env_{face}.hdr", np.ones((4, 4, 3), np.float32))
    with pytest.raises(ArgumentError, match="sun_dim.hdr, sun_dim.exr, sun_dim.pfm"):
        read_bake(tmp_path)
    with pytest.raises(ArgumentError, match="not a folder"):
        read_bake(tmp_path / "env_posx.hdr")


def test_a_sun_json_that_lies_is_a_format_error(tmp_path):
    from bakeshop.preview.bake import _sun_from_document

    assert _sun_from_document({"sun": None}, "sun.json") is None
    with pytest.raises(FormatError, match="direction is zero"):
        _sun_from_document(
            {"direction": [0, 0, 0], "irradiance": [1, 1, 1], "angular_radius_deg": 0.3}, "s"
        )
    with pytest.raises(FormatError, match="not a bakeshop sun.json"):
        _sun_from_document({"direction": [0, 1, 0]}, "s")
