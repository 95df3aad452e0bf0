"""``bake-probe --engine E``: every engine's files keep the source probe's energy and its sun
(issue 28: Unity's and Filament's GGX chains were re-baked from the probe with its sun painted
out), and what the bake needs (the compress extra, writable folders, free space) is refused
before the work starts."""

import json
import os
import sys
import time

import numpy as np
import pytest

from bakeshop import engines
from bakeshop.cli.main import main
from bakeshop.errors import BakeshopError
from bakeshop.io import read_container, write_image
from bakeshop.light import prefilter_ggx
from bakeshop.sphere import layout
from tests.cli.test_process import one_error_line
from tests.io.test_files import tmpfs  # noqa: F401 - a fixture
from tests.tolerances import BC6H_ENERGY, BC6H_SUN

#: a small bright sun: about nine tenths of the sky's energy.
SUN = 1e4
SUN_DIRECTION = np.array([0.5, 0.6, -0.62]) / np.linalg.norm([0.5, 0.6, -0.62])
SIZES = ["--cube-size", "32", "--specular-size", "32", "--mips", "6"]


def _sky(height: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """A latlong sky (H, 2H, 3) with a 4-degree disc of ``SUN``, and the disc alone."""
    d, _ = layout("latlong").directions((height, 2 * height))
    sky = 0.3 + np.array([0.5, 0.7, 1.0]) * np.clip(d[..., 1:2], 0, None)
    disc = SUN * (d @ SUN_DIRECTION > np.cos(np.radians(4)))[..., None] * np.ones(3)
    return (sky + disc).astype(np.float32), disc


def _energy(image: np.ndarray) -> np.ndarray:
    """The integral over the sphere of each channel of a latlong (exact texel solid angles)."""
    omega = layout("latlong").solid_angles(image.shape[:-1])
    return np.einsum("hwc,hw->c", image.astype(np.float64), omega)


@pytest.fixture(scope="module")
def baked(tmp_path_factory):
    """``bake-probe --engine unity`` of the sky through the command line, and every other
    preset's files from the same bake and probe as the command passed them on (recorded):
    (folder, the source's energy, its sun's)."""
    import bakeshop.cli.bake_probe as command

    folder = tmp_path_factory.mktemp("chains")
    sky, disc = _sky()
    write_image(folder / "sky.pfm", sky)
    calls = []
    real = command.bake_compressed

    def record(bake, image, *rest, **kwargs):  # the probe as it is when the chains are made
        calls.append(((bake, image.copy(), *rest), kwargs))
        return real(bake, image, *rest, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(command, "bake_compressed", record)
        args = ["-q", "bake-probe", folder / "sky.pfm", "-o", folder, "--engine", "unity"]
        assert main([str(a) for a in [*args, *SIZES]]) == 0
    (bake, image, *rest), kwargs = calls[0]
    np.testing.assert_array_equal(image, sky)  # the probe itself, its sun included
    for name in sorted(set(engines.ENGINES) - {"unity"}):
        real(bake, image, rest[0], rest[1], name, **kwargs)
    return folder, _energy(sky), _energy(disc)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(engines.ENGINES))
def test_every_texture_keeps_the_source_probe_energy_and_sun(baked, name):
    folder, source, sun = baked
    e = engines.ENGINES[name]
    textures = [folder / name / e.files["environment"]]
    if "specular" in e.files:
        textures.append(folder / name / e.files["specular"])
    for path in textures:
        mips, meta = read_container(path)
        assert meta["stored"] == "bc6h", path
        levels = mips if path.name == e.files.get("specular") else mips[:1]
        for m, level in enumerate(levels):  # a GGX filter keeps the energy at every roughness
            energy = engines.energy(level, cube=bool(meta["cube"]))
            np.testing.assert_allclose(energy, source, rtol=BC6H_ENERGY, err_msg=f"{path} {m}")
            # the sun's integral: what the level holds above the sky without the sun
            np.testing.assert_allclose(energy - (source - sun), sun, rtol=BC6H_SUN,
                                       err_msg=f"{path} {m}")  # fmt: skip
        sidecar = json.loads((path.parent / f"{path.name}.json").read_text())["source"]
        np.testing.assert_allclose(sidecar["energy"], source, rtol=BC6H_ENERGY)
        np.testing.assert_allclose(sidecar["sun_irradiance"], sun, rtol=BC6H_SUN)
        assert len(sidecar["levels"]) == len(levels)
        assert all(abs(row["energy_ratio"] - 1) <= BC6H_ENERGY for row in sidecar["levels"])


@pytest.mark.slow
def test_openimageio_reads_the_same_dds_levels(baked):
    oiio = pytest.importorskip("OpenImageIO")
    folder, source, _ = baked
    for name in ("unity", "unreal", "godot"):
        e = engines.ENGINES[name]
        for f in e.files.values():
            path = folder / name / f
            if path.suffix != ".dds":
                continue
            ours, _ = read_container(path)
            theirs = oiio.ImageBuf(str(path))
            assert not theirs.has_error, theirs.geterror()
            pixels = theirs.get_pixels(oiio.FLOAT)
            # the same texels, in whatever order OpenImageIO lays out a cube's faces
            assert pixels.size == ours[0].size, path
            np.testing.assert_allclose(
                np.sort(pixels.reshape(-1, 3), axis=0),
                np.sort(ours[0].reshape(-1, 3), axis=0),
                rtol=1e-3,
                err_msg=str(path),
            )


def test_a_black_probe_passes_the_check():
    black = [np.zeros((6, 4, 4, 3), np.float32)]
    report = engines.check_energy(black, engines.SourceEnergy.of_bake(np.zeros((9, 3)), None),
                                  cube=True, encoded=black)  # fmt: skip
    assert report["levels"][0]["energy_ratio"] == 1


def test_a_chain_made_from_the_shadow_probe_is_refused():
    sky, disc = _sky()
    reference = engines.SourceEnergy(_energy(sky), _energy(disc))
    good = prefilter_ggx(sky, "latlong", size=16, mips=5)
    report = engines.check_energy(good, reference, cube=True)
    assert all(abs(row["energy_ratio"] - 1) <= BC6H_ENERGY for row in report["levels"])
    shadow = (sky - disc).astype(np.float32)  # the probe with its sun painted out
    sunless = prefilter_ggx(shadow, "latlong", size=16, mips=5)
    with pytest.raises(BakeshopError, match="not made from the source probe"):
        engines.check_energy(sunless, reference, cube=True)


# ---- refused before the work starts -------------------------------------------------------


def _refused_at_once(capfd, tmp_path, *extra) -> str:
    write_image(tmp_path / "sky.pfm", _sky(32)[0])
    started = time.perf_counter()
    args = ["bake-probe", tmp_path / "sky.pfm", *extra]
    status = main([str(a) for a in args])
    took = time.perf_counter() - started
    assert status == 2
    assert took < 5.0, f"refused after {took:.1f} s: the bake ran first"
    assert not list(tmp_path.rglob("env_*")) and not list(tmp_path.rglob("*.dds"))
    return one_error_line(capfd)


def test_a_missing_compress_extra_is_refused_before_the_bake(capfd, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ispc_texcomp", None)  # import fails as when missing
    err = _refused_at_once(capfd, tmp_path, "-o", tmp_path / "out", "--engine", "unity")
    assert "environment.dds: " in err and "install bakeshop[compress]" in err


def test_a_missing_zstandard_is_refused_before_the_bake(capfd, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "zstandard", None)
    err = _refused_at_once(capfd, tmp_path, "-o", tmp_path / "out", "--compress", "--zstd")
    assert "environment.ktx2: " in err and "zstandard" in err


def test_an_output_folder_under_a_file_is_refused_before_the_bake(capfd, tmp_path):
    (tmp_path / "file").write_text("not a folder")
    target = tmp_path / "file" / "baked"
    err = _refused_at_once(capfd, tmp_path, "-o", target)
    assert f"{target}: cannot create this folder: {tmp_path / 'file'} is a file" in err


def test_a_folder_nothing_can_be_written_in_is_refused_before_the_bake(capfd, tmp_path):
    # /proc/self exists and is a folder, but nothing can be created in it (even by root)
    if not os.path.isdir("/proc/self"):
        pytest.skip("needs Linux's /proc")
    err = _refused_at_once(capfd, tmp_path, "-o", "/proc/self")
    assert "/proc/self: cannot write in this folder: " in err


def test_a_read_only_file_system_is_refused_before_the_bake(capfd, tmp_path, tmpfs):  # noqa: F811
    folder = tmpfs("1m", read_only=True)
    err = _refused_at_once(capfd, tmp_path, "-o", folder / "baked")
    assert f"{folder / 'baked'}: cannot create this folder: read-only file system" in err


def test_too_little_free_space_is_refused_before_the_bake(capfd, tmp_path, tmpfs):  # noqa: F811
    folder = tmpfs("200k")
    err = _refused_at_once(capfd, tmp_path, "-o", folder, "--engine", "unity")
    assert f"{folder}: the bake writes up to " in err and "MB free" in err and "--cube-size" in err
    assert not list(folder.iterdir())
