"""bakeshop.io.environment: environments in any layout, incl. .dds/.ktx/.ktx2 cube maps."""

import numpy as np
import pytest

from bakeshop.errors import ArgumentError
from bakeshop.io import read_environment, write_container, write_environment
from bakeshop.io.ktx2 import read_ktx2, write_ktx2
from bakeshop.sphere import auto_filter, cube_to_faces, layout


def test_containers_are_half_float_unless_a_value_overflows(tmp_path):
    level = np.full((6, 4, 4, 3), 2.0, np.float32)
    write_container(tmp_path / "a.ktx2", [level])
    assert read_ktx2(tmp_path / "a.ktx2")[1]["stored"] == "float16"
    level[2, 1, 1] = 1e5  # the sun: float16 tops out at 65504
    write_container(tmp_path / "b.ktx2", [level])
    mips, meta = read_ktx2(tmp_path / "b.ktx2")
    assert meta["stored"] == "float32" and mips[0][2, 1, 1, 0] == 1e5
    write_container(tmp_path / "c.ktx2", [np.ones((6, 4, 4, 3), np.float32)], float32=True)
    assert read_ktx2(tmp_path / "c.ktx2")[1]["stored"] == "float32"


def test_cube_round_trip_through_ktx2_in_every_convention(tmp_path):
    rng = np.random.default_rng(3)
    cube = rng.uniform(0, 4, (6, 8, 8, 3)).astype(np.float32)
    for convention in ("opengl", "vulkan", "directx"):
        path = tmp_path / f"{convention}.ktx2"
        assert write_environment(path, cube, "cube", convention=convention) == [path]
        stored = read_ktx2(path)[0][0][..., :3]  # the faces as the engine loads them
        np.testing.assert_allclose(stored, cube_to_faces(cube, convention=convention), rtol=1e-3)
        back, layout, how = read_environment(path, convention=convention)
        assert layout == "cube" and how == "a cube map file"
        np.testing.assert_allclose(back[..., :3], cube, rtol=1e-3)


def test_a_2d_texture_is_not_an_environment(tmp_path):
    path = tmp_path / "lut.ktx2"
    write_ktx2(path, [np.zeros((8, 8, 2), np.float32)])
    with pytest.raises(ArgumentError, match="not a cube map"):
        read_environment(path, None)


def test_auto_filter_averages_only_when_the_output_holds_at_most_half_the_directions():
    def auto(src, shape, dst, size):
        return auto_filter(src, shape, dst, layout(dst).shape(size))

    latlong = (64, 128)  # 8192 directions
    assert auto("latlong", latlong, "cube", 16) == "area"  # 6 x 256 = 1536
    assert auto("latlong", latlong, "cube", 26) == "area"  # 4056 <= 4096
    assert auto("latlong", latlong, "cube", 27) == "bilinear"  # 4374 > 4096
    assert auto("latlong", latlong, "cube", 64) == "bilinear"  # 24576
    assert auto("latlong", latlong, "latlong", (128, 64)) == "bilinear"  # as many
    # a mirror ball holds directions in its disk only (pi/4 of the square: 804 of 1024)
    ball = (32, 32)
    assert auto("mirrorball", ball, "latlong", (28, 14)) == "area"  # 392 <= 402
    assert auto("mirrorball", ball, "latlong", (30, 15)) == "bilinear"  # 450
