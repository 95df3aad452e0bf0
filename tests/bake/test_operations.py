"""The real operations of a recipe make what the commands they mirror make, from the same
library functions (never by shelling out), and every file they write is re-read and checked."""

import numpy as np
import pytest

import bakeshop.io as bio
from bakeshop.bake import load_recipe, plan, run
from bakeshop.cli.main import main


def normal_map(n: int, amp: float) -> np.ndarray:
    u = np.linspace(0, 2 * np.pi, n, endpoint=False)
    gx = np.repeat(amp * np.sin(3 * u)[None, :], n, 0)
    gy = np.repeat(amp * np.cos(2 * u)[:, None], n, 1)
    v = np.stack([-gx, -gy, np.ones_like(gx)], -1)
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    return ((v + 1) / 2).astype(np.float32)


def sky(height: int = 16) -> np.ndarray:
    y = np.linspace(1, -1, height)[:, None, None]
    img = (0.3 + np.clip(y, 0, None)) * np.array([0.5, 0.7, 1.0]) * np.ones((height, 2 * height, 3))
    img[2:4, 20:22] = 300.0
    return img.astype(np.float32)


def bake(folder, text):
    (folder / "r.toml").write_text(text)
    result = run(load_recipe(folder / "r.toml"))
    assert not result.failed, result.failed
    return result, bio.read_json(folder / "r.bake.json")


def reloads(manifest) -> list:
    return [o["reload"] for s in manifest["steps"].values() for o in s["outputs"]]


def test_normals_and_compress_steps_match_their_commands(tmp_path):
    bio.write_image(tmp_path / "macro.png", normal_map(32, 0.3), bits=16)
    bio.write_image(tmp_path / "grain.png", normal_map(8, 0.5), bits=16)
    cube = np.random.default_rng(3).random((6, 8, 8, 3), dtype=np.float32) * 4
    bio.write_chain(tmp_path / "env.dds", [cube, cube[:, ::2, ::2], cube[:, ::4, ::4]])
    result, manifest = bake(
        tmp_path,
        """
        [normals.crate]
        macro = "macro.png"
        layers = [{ detail = "grain.png", tile = 4, rotate = 30.0, strength = 0.5 }]
        output = "out/crate.png"
        [compress.env]
        input = "env.dds"
        output = "out/env_bc6h.dds"
        """.replace("out/", ""),
    )
    assert result.built == ["normals.crate", "compress.env"]
    assert main(["-q", "normals", "combine", str(tmp_path / "macro.png"),
                 str(tmp_path / "grain.png"), str(tmp_path / "cli.png"), "--tile", "4",
                 "--rotate", "30", "--strength", "0.5"]) == 0  # fmt: skip
    np.testing.assert_array_equal(
        bio.read_image(tmp_path / "crate.png"), bio.read_image(tmp_path / "cli.png")
    )
    assert main(["-q", "compress", str(tmp_path / "env.dds"), str(tmp_path / "cli.dds")]) == 0
    assert (tmp_path / "env_bc6h.dds").read_bytes() == (tmp_path / "cli.dds").read_bytes()
    checks = reloads(manifest)
    assert len(checks) == 3 and all(c["ok"] for c in checks)  # png, dds, its json sidecar
    assert {c["writer"] for c in checks} == {"image:ldr", "blocks:dds", "json"}


def test_water_step_matches_the_command(tmp_path):
    result, manifest = bake(
        tmp_path,
        """
        [water.harbour]
        output = "harbour"
        resolution = 32
        size = 16.0
        wind = 5.0
        """,
    )
    out = [o["file"] for o in manifest["steps"]["water.harbour"]["outputs"]]
    frames = manifest["steps"]["water.harbour"]["facts"]["frames"]
    assert len(out) == frames + 1 and out[-1] == "harbour/ocean.json"
    assert main(["-q", "water", "ocean", str(tmp_path / "cli"), "--resolution", "32",
                 "--size", "16", "--wind", "5", "--no-preview"]) == 0  # fmt: skip
    for name in ("ocean_normal_0000.png", f"ocean_normal_{frames - 1:04d}.png"):
        assert (tmp_path / "harbour" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert all(c["ok"] and c["check"] == "exact" for c in reloads(manifest))


@pytest.mark.slow
def test_probe_step_matches_bake_probe(tmp_path):
    bio.write_image(tmp_path / "sky.hdr", sky())
    result, manifest = bake(
        tmp_path,
        """
        [probe.sky]
        input = "sky.hdr"
        output = "baked"
        cube_size = 8
        specular_size = 8
        mips = 3
        """,
    )
    assert main(["-q", "bake-probe", str(tmp_path / "sky.hdr"), "-o", str(tmp_path / "cli"),
                 "--cube-size", "8", "--specular-size", "8", "--mips", "3"]) == 0  # fmt: skip
    made = {o["file"].removeprefix("baked/") for o in manifest["steps"]["probe.sky"]["outputs"]}
    cli = {p.name for p in (tmp_path / "cli").iterdir()}
    assert made == cli - {"contact_sheet.png"}
    for name in made:
        assert (tmp_path / "baked" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert all(c["ok"] for c in reloads(manifest)) and len(reloads(manifest)) == len(made)


WATER_LEVEL = """
[water.a]
output = "a"
resolution = 32
size = 16.0
[water.b]
output = "b"
resolution = 32
size = 8.0
seed = 1
[compress.a0]
input = "a/ocean_normal_0000.png"
output = "a0_bc5.dds"
format = "bc5"
normals = true
"""


def _files(folder):
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
        and not any(part.startswith(".") for part in p.relative_to(folder).parts)
        and not p.name.endswith(".bake.json")
    }


@pytest.mark.slow
def test_a_bake_killed_at_any_moment_resumes_to_the_same_result(tmp_path):
    import random
    import signal
    import subprocess
    import sys
    import time

    clean = tmp_path / "clean"
    clean.mkdir()
    bake(clean, WATER_LEVEL)
    expected = _files(clean)
    killed = tmp_path / "killed"
    killed.mkdir()
    (killed / "r.toml").write_text(WATER_LEVEL)
    rng = random.Random(18)
    command = [sys.executable, "-m", "bakeshop.cli.main", "-q", "bake", str(killed / "r.toml")]

    def written_since(started: float) -> int:
        """Files (temporaries included) written under ``killed`` since ``started``."""
        count = 0
        for p in killed.rglob("*"):
            try:
                count += p.is_file() and p.stat().st_mtime >= started
            except FileNotFoundError:  # a temporary renamed under us
                pass
        return count

    interrupted = 0
    for writes in (rng.randint(1, len(expected) // 2), *rng.sample(range(1, len(expected)), 3)):
        # killed at a random point of its own progress (once it has written that many files),
        # not of the clock: a fast machine finished the whole bake before a timed kill
        started = time.time()
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 600
        while process.poll() is None and written_since(started) < writes:
            assert time.monotonic() < deadline, "the bake never wrote its files"
            time.sleep(0.001)
        process.send_signal(signal.SIGKILL)
        process.wait()
        left = [d for d in plan(load_recipe(killed / "r.toml")) if d.action != "skip"]
        interrupted += bool(left) and process.returncode == -signal.SIGKILL
    assert interrupted  # at least one kill landed before the bake was done
    result, manifest = bake(killed, WATER_LEVEL)
    assert _files(killed) == expected  # no output half written, none missing, none different
    hidden = [p.name for p in killed.rglob(".*") if p.name != ".bakeshop"]
    assert hidden == []  # and no temporary left behind
    assert all(c["ok"] for c in reloads(manifest))
    assert run(load_recipe(killed / "r.toml")).built == []


def test_remap_steps_match_the_command(tmp_path):
    bio.write_image(tmp_path / "sky.hdr", sky())
    _, manifest = bake(
        tmp_path,
        """
        [remap.cross]
        input = "sky.hdr"
        output = "sky_cross.exr"
        to = "cross-vertical"
        size = 8
        [remap.faces]
        input = "sky.hdr"
        output = "sky_{face}.pfm"
        to = "faces"
        convention = "directx"
        """,
    )
    assert main(["-q", "remap", str(tmp_path / "sky.hdr"), str(tmp_path / "cli_cross.exr"),
                 "--to", "cross-vertical", "--size", "8"]) == 0  # fmt: skip
    assert main(["-q", "remap", str(tmp_path / "sky.hdr"), str(tmp_path / "cli_{face}.pfm"),
                 "--to", "faces", "--convention", "directx"]) == 0  # fmt: skip
    np.testing.assert_array_equal(
        bio.read_image(tmp_path / "sky_cross.exr"), bio.read_image(tmp_path / "cli_cross.exr")
    )
    for face in ("posx", "negz"):
        a = (tmp_path / f"sky_{face}.pfm").read_bytes()
        assert a == (tmp_path / f"cli_{face}.pfm").read_bytes()
    assert len(reloads(manifest)) == 7 and all(c["ok"] for c in reloads(manifest))


def test_parallel_bakes_write_the_same_bytes_as_serial_ones(tmp_path):
    recipe = """
        [remap.cross]
        input = "sky.hdr"
        output = "out/cross.exr"
        to = "cross-vertical"
        size = 8
        [remap.faces]
        input = "sky.hdr"
        output = "out/env.dds"
        to = "faces"
        size = 8
        [compress.env]
        input = "out/env.dds"
        output = "out/env_bc6h.ktx2"
        zstd = true
        [normals.crate]
        macro = "macro.png"
        layers = [{ detail = "grain.png", tile = 4 }]
        output = "out/crate.png"
        """
    for name in ("serial", "parallel"):
        folder = tmp_path / name
        folder.mkdir()
        bio.write_image(folder / "sky.hdr", sky())
        bio.write_image(folder / "macro.png", normal_map(32, 0.3), bits=16)
        bio.write_image(folder / "grain.png", normal_map(8, 0.5), bits=16)
        (folder / "r.toml").write_text(recipe)
        result = run(load_recipe(folder / "r.toml"), jobs=1 if name == "serial" else 2)
        assert not result.failed and len(result.built) == 4
    serial, parallel = _files(tmp_path / "serial"), _files(tmp_path / "parallel")
    assert serial.keys() == parallel.keys() and len(serial) == 9
    assert serial == parallel


def test_a_probe_step_refuses_to_drop_an_alpha_that_holds_something(tmp_path):
    rgba = np.concatenate([sky(), np.full((16, 32, 1), 0.5, np.float32)], -1)
    bio.write_image(tmp_path / "sky.exr", rgba)
    (tmp_path / "r.toml").write_text(
        '[probe.sky]\ninput = "sky.exr"\noutput = "baked"\nformat = "hdr"\ncube_size = 8\n'
        "specular_size = 8\nmips = 3\n"
    )
    result = run(load_recipe(tmp_path / "r.toml"))
    ((step, error),) = result.failed.items()
    assert step == "probe.sky" and 'format = "exr"' in str(error), result.failed
    assert not (tmp_path / "baked").exists()
