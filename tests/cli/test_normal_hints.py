"""``normals combine`` says what a map's content shows: an HDR image given as a normal map, a
green channel of the other convention, a detail tiled finer than the output can hold."""

from __future__ import annotations

import numpy as np

from bakeshop.cli.main import main
from bakeshop.io import write_image
from bakeshop.normals.encoding import encode_normals
from tests.cli.test_process import one_error_line
from tests.normals.test_plausibility import bumps, normals_of


def _map(path, normals, convention="gl"):
    write_image(
        path, np.round(encode_normals(normals, convention=convention) * 255).astype(np.uint8)
    )
    return str(path)


def test_an_hdr_probe_is_not_combined_as_a_normal_map(tmp_path, capfd):
    probe = tmp_path / "probe.hdr"
    write_image(probe, np.random.default_rng(1).lognormal(0, 2, (32, 64, 3)).astype(np.float32))
    detail = _map(tmp_path / "detail.png", normals_of(bumps(32)))
    assert main(["-q", "normals", "combine", str(probe), detail, str(tmp_path / "o.png")]) == 2
    line = one_error_line(capfd)
    assert line.startswith(f"bakeshop: error: {probe}: not a normal map: ") and "[0, 1]" in line
    assert not (tmp_path / "o.png").exists()


def test_a_detail_of_the_other_convention_is_named(tmp_path, capfd):
    macro = _map(tmp_path / "macro.png", normals_of(bumps(64, seed=1)))
    detail = _map(tmp_path / "detail.png", normals_of(bumps(64, seed=2)), convention="dx")
    assert main(["-q", "normals", "combine", macro, detail, str(tmp_path / "o.png")]) == 0
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and f"warning: {detail}: read as gl" in err
    assert "looks dx; check --detail-convention" in err
    args = ["--detail-convention", "dx"]
    assert main(["-q", "normals", "combine", macro, detail, str(tmp_path / "o.png"), *args]) == 0
    assert capfd.readouterr().err == ""


def test_a_detail_filtered_away_by_its_tiling_is_named(tmp_path, capfd):
    macro = _map(tmp_path / "macro.png", normals_of(bumps(64, seed=1)))
    rough = normals_of(np.random.default_rng(2).normal(0, 1.0, (128, 128)))
    detail = _map(tmp_path / "detail.png", rough)
    out = str(tmp_path / "o.png")
    assert main(["-q", "normals", "combine", macro, detail, out, "--tile", "16"]) == 0
    err = capfd.readouterr().err
    assert "tiled 16x16 times over 64x64 texels, filtering leaves" in err and "--tile" in err
    assert main(["-q", "normals", "combine", macro, detail, out, "--tile", "0.5"]) == 0
    assert capfd.readouterr().err == ""
