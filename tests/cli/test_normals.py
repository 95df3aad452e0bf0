"""``bakeshop normals``: combine, transfer, from-height, check and convert, end to end."""

import cv2
import numpy as np
import pytest

from bakeshop.cli.main import main
from bakeshop.normals.blend import blend
from bakeshop.normals.encoding import decode_normals
from bakeshop.normals.height import height_to_normal
from bakeshop.normals.tiling import place_detail
from tests.files import DATA
from tests.normals.test_blend import random_normals
from tests.normals.test_transfer import cylinder, plane, write_gltf

#: one 8-bit step of a packed component, in decoded units, plus float slack
STEP = 2 / 255 + 1e-6


def write_png(path, normals, convention="gl"):
    n = normals * (1, -1, 1) if convention == "dx" else normals
    rgb = np.rint((n + 1) / 2 * 255).astype(np.uint8)
    cv2.imwrite(str(path), rgb[..., ::-1])
    return path


def read_png(path, convention="gl"):
    rgb = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1]
    scale = 65535.0 if rgb.dtype == np.uint16 else 255.0
    return decode_normals(rgb / scale, convention=convention)


def maps(h=32, w=48, seed=0):
    return random_normals(h * w, seed, 60).reshape(h, w, 3)


def test_help_teaches_with_examples(capsys):
    for command in ("combine", "transfer", "from-height", "check", "convert"):
        assert main(["normals", command, "--help"]) == 0
        assert "Example:" in capsys.readouterr().out


def test_combine_matches_the_library(tmp_path, capsys):
    macro, detail = maps(), maps(16, 16, 1)
    m = write_png(tmp_path / "m.png", macro)
    d = write_png(tmp_path / "d.png", detail, "dx")
    out = tmp_path / "o.png"
    args = [
        "normals",
        "combine",
        str(m),
        str(d),
        str(out),
        "--tile",
        "3x2",
        "--rotate",
        "30",
        "--strength",
        "0.7",
        "--detail-convention",
        "dx",
        "-O",
        "bits=16",
    ]
    assert main(args) == 0
    assert "1 detail layer" in capsys.readouterr().out
    assert cv2.imread(str(out), cv2.IMREAD_UNCHANGED).dtype == np.uint16
    m8, d8 = read_png(m), read_png(d, "dx")
    expected = blend(m8, place_detail(d8, (32, 48), tile=(3, 2), rotation=30), strength=0.7)
    assert np.abs(read_png(out) - expected).max() < 1e-4  # 16-bit output


def test_combine_layers_with_material_ids(tmp_path):
    macro, a, b = maps(), maps(8, 8, 2), maps(8, 8, 3)
    ids = np.zeros((32, 48, 3), np.uint8)
    ids[:, :24] = (200, 50, 50)
    ids[:, 24:] = 90
    cv2.imwrite(str(tmp_path / "ids.png"), ids[..., ::-1])
    paths = [write_png(tmp_path / f"{k}.png", x) for k, x in (("m", macro), ("a", a), ("b", b))]
    out = tmp_path / "o.png"
    args = [
        "normals",
        "combine",
        *map(str, paths[:2]),
        str(out),
        "--method",
        "rnm",
        "--tile",
        "4",
        "--mask",
        str(tmp_path / "ids.png"),
        "--mask-id",
        "#c83232",
        "--layer",
        f"{paths[2]},tile=2,rotate=90,mask={tmp_path / 'ids.png'},id=90",
    ]
    assert main(args) == 0
    m8, a8, b8 = (read_png(p) for p in paths)
    left = blend(m8, place_detail(a8, (32, 48), tile=4), method="rnm")
    right = blend(m8, place_detail(b8, (32, 48), tile=2, rotation=90), method="rnm")
    got = read_png(out)
    assert np.abs(got[:, :24] - left[:, :24]).max() < STEP
    assert np.abs(got[:, 24:] - right[:, 24:]).max() < STEP


@pytest.mark.slow
def test_flat_detail_leaves_the_macro_map(tmp_path):
    macro = DATA / "NormalTangentTest_Normal.png"
    flat = write_png(tmp_path / "flat.png", np.broadcast_to([0.0, 0, 1], (4, 4, 3)))
    # an 8-bit flat texel is (128, 128, 255): slopes of 1/255, so strength 0 for exactness
    out = tmp_path / "o.png"
    assert main(["normals", "combine", str(macro), str(flat), str(out), "--strength", "0"]) == 0
    before = cv2.imread(str(macro)).astype(int)
    after = cv2.imread(str(out)).astype(int)
    assert np.abs(after - before).max() <= 1  # renormalising the stored vectors, nothing else


def test_transfer_gltf_second_uv_set_and_obj_projection(tmp_path, capsys):
    import trimesh

    detail = maps(16, 16, 4)
    d = write_png(tmp_path / "d.png", detail)
    mesh = plane(uv2=plane().uv * 3)
    write_gltf(tmp_path / "p.gltf", mesh)
    out = tmp_path / "o.png"
    assert (
        main(
            [
                "normals",
                "transfer",
                str(tmp_path / "p.gltf"),
                str(d),
                str(out),
                "--size",
                "32",
                "-O",
                "bits=16",
            ]
        )
        == 0
    )
    assert "100.0% of texels covered" in capsys.readouterr().out
    expected = place_detail(read_png(d), (32, 32), tile=3)
    assert np.abs(read_png(out) - expected).max() < 1e-4
    # OBJ (one UV set): planar projection along z, blended onto a macro map in one go
    c = cylinder(segments=24)
    tm = trimesh.Trimesh(
        c.positions,
        c.faces,
        vertex_normals=c.normals,
        process=False,
        visual=trimesh.visual.TextureVisuals(uv=c.uv),
    )
    tm.export(tmp_path / "c.obj")
    macro = write_png(tmp_path / "m.png", maps(32, 64, 5))
    out2 = tmp_path / "o2.png"
    assert (
        main(
            [
                "normals",
                "transfer",
                str(tmp_path / "c.obj"),
                str(d),
                str(out2),
                "--projection",
                "triplanar",
                "--tile",
                "2",
                "--macro",
                str(macro),
            ]
        )
        == 0
    )
    assert cv2.imread(str(out2)).shape == (32, 64, 3)
    assert (
        main(["normals", "transfer", str(tmp_path / "c.obj"), str(d), str(out2), "--size", "16"])
        == 2
    )
    assert "second UV set" in capsys.readouterr().err


def test_from_height_matches_the_library(tmp_path):
    h = (np.random.default_rng(6).random((24, 40)) * 255).astype(np.uint8)
    cv2.imwrite(str(tmp_path / "h.png"), h)
    out = tmp_path / "n.png"
    assert (
        main(
            [
                "normals",
                "from-height",
                str(tmp_path / "h.png"),
                str(out),
                "--strength",
                "4",
                "--derivative",
                "sobel",
                "--convention",
                "dx",
            ]
        )
        == 0
    )
    expected = height_to_normal(h / 255.0, strength=4, derivative="sobel")
    assert np.abs(read_png(out, "dx") - expected).max() < STEP


def test_check_exit_status(tmp_path, capsys):
    good = write_png(tmp_path / "good.png", maps())
    bad = maps()
    bad[:, :, 2] *= -1
    bad = write_png(tmp_path / "bad.png", bad)
    assert main(["normals", "check", str(good)]) == 0
    assert main(["normals", "check", str(good), str(bad)]) == 1
    out = capsys.readouterr().out
    assert "good.png: ok" in out and "bad.png: FLAGGED" in out and "--xy" in out


def test_convert_gl_dx_round_trip_is_byte_exact(tmp_path):
    src = write_png(tmp_path / "gl.png", maps())
    dx, back = tmp_path / "dx.png", tmp_path / "back.png"
    assert main(["normals", "convert", str(src), str(dx), "--from", "gl", "--to", "dx"]) == 0
    assert main(["normals", "convert", str(dx), str(back), "--from", "dx", "--to", "gl"]) == 0
    a, b, c = (cv2.imread(str(p)) for p in (src, dx, back))
    np.testing.assert_array_equal(c, a)
    np.testing.assert_array_equal(b[..., 1], 255 - a[..., 1])
    np.testing.assert_array_equal(b[..., [0, 2]], a[..., [0, 2]])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--layer", "{d},tilt=3"], "invalid layer setting"),
        (["--layer", "{d},tile=abc"], "invalid layer setting tile=abc"),
        (["--mask-id", "3"], "needs a mask"),
        (["--tile", "0"], "non-zero"),
    ],
)
def test_combine_bad_arguments_are_one_line(tmp_path, capsys, args, message):
    m = write_png(tmp_path / "m.png", maps())
    d = write_png(tmp_path / "d.png", maps(8, 8, 1))
    args = [a.format(d=d) for a in args]
    assert main(["normals", "combine", str(m), str(d), str(tmp_path / "o.png"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("bakeshop: error: ") and message in err and err.count("\n") == 1


def test_refuses_to_overwrite_its_input(tmp_path, capsys):
    m = write_png(tmp_path / "m.png", maps())
    assert main(["normals", "combine", str(m), str(m), str(m)]) == 2
    assert "refusing" in capsys.readouterr().err


def test_transfer_size_arguments(tmp_path, capsys):
    d = write_png(tmp_path / "d.png", maps(8, 8, 1))
    m = write_png(tmp_path / "m.png", maps(32, 32, 2))
    write_gltf(tmp_path / "p.gltf", plane(uv2=plane().uv))
    base = ["normals", "transfer", str(tmp_path / "p.gltf"), str(d), str(tmp_path / "o.png")]
    assert main(base) == 2
    assert "--size" in capsys.readouterr().err
    assert main([*base, "--macro", str(m), "--size", "64"]) == 2
    assert "differs from the macro map's 32x32" in capsys.readouterr().err
    assert main([*base, "--macro", str(m), "--size", "32"]) == 0
