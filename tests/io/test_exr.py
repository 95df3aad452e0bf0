"""OpenEXR: OpenEXR's sample files against OpenImageIO, exact round trips for half and float with
every lossless compression, the half overflow rule, channel sets and layers, files written by
OpenImageIO, and corrupt files (fuzzing included).

Peers: OpenImageIO reads and writes EXR with its own build of the OpenEXR library. OpenCV 5's
wheel has no EXR codec (cv2.imread returns None even with OPENCV_IO_ENABLE_OPENEXR), and imageio
delegates EXR to plugins that are not installed, so OpenImageIO is the independent reference.
Odd channel layouts are built with the OpenEXR bindings directly.
"""

from __future__ import annotations

import warnings

import numpy as np
import OpenEXR
import OpenImageIO as oiio
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bakeshop.errors import ArgumentError, BakeshopWarning, FormatError, UnsupportedError
from bakeshop.io import exr, read_image, write_image
from tests.files import DATA
from tests.io import fuzzing
from tests.tolerances import EXR_LOSSY_RTOL


def oiio_read(path):
    f = oiio.ImageInput.open(str(path))
    try:
        return f.read_image("float"), f.spec()
    finally:
        f.close()


def same_bits(a, b):
    a, b = np.asarray(a, np.float32), np.asarray(b, np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def hdr_image(height=13, width=29, channels=3, seed=0):
    rng = np.random.default_rng(seed)
    image = np.exp(rng.normal(0, 2, (height, width, channels))).astype(np.float32)
    assert image.max() < 65504  # half holds it all
    image[0, :4, 0] = [0.0, -0.0, -2.5, 1e-6]
    return image


def write_raw(path, channels, header=None):
    """A file written by the OpenEXR bindings with exactly the given channels."""
    head = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File({**head, **(header or {})}, dict(channels)).write(str(path))  # it edits the dict
    return path


# --- OpenEXR's sample files -----------------------------------------------------------------------


#: OpenEXR's environment sample pairs as stored in tests/data/exr (top level only, RGB, zip
#: scanlines), and the Kerner latlong exactly as published (tiled, mip-mapped, RGBA).
SAMPLES = {
    "KernerEnvLatLong.exr": ((512, 1024), "RGB", "latlong"),
    "KernerEnvCube.exr": ((1536, 256), "RGB", "cube"),
    "OrientationLatLong.exr": ((512, 1024), "RGB", "latlong"),
    "OrientationCube.exr": ((3072, 512), "RGB", "cube"),
    "KernerEnvLatLong_published.exr": ((512, 1024), "RGBA", "latlong"),
}


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_openexr_samples_match_openimageio(name):
    (height, width), channels, envmap = SAMPLES[name]
    path = DATA / "exr" / name
    image, meta = read_image(path, with_metadata=True)
    reference, spec = oiio_read(path)
    assert list(spec.channelnames) == list(channels)
    assert image.shape == (height, width, len(channels)) and image.dtype == np.float32
    assert same_bits(image, reference)
    assert meta["stored"] == "half" and meta["compression"] == "zip"
    assert meta["channels"] == list(channels) and meta["envmap"] == envmap
    assert meta["data_window"] == meta["display_window"] == ((0, 0), (width - 1, height - 1))


def test_tiled_mipmapped_file_reads_its_top_level():
    path = DATA / "exr" / "KernerEnvLatLong_published.exr"
    image, meta = read_image(path, with_metadata=True)
    assert meta["storage"] == "tiled" and meta["levels"] == "mipmap"
    # the reduced copy kept the same top-level R, G, B halves, bit for bit
    assert same_bits(image[..., :3], read_image(DATA / "exr" / "KernerEnvLatLong.exr"))


# --- writing: round trips, compressions, overflow ------------------------------------------------


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_float_round_trip_is_bit_exact_and_openimageio_agrees(tmp_path, channels):
    image = hdr_image(channels=channels)
    image.flat[5:8] = [np.nan, np.inf, -np.inf]
    path = tmp_path / "f.exr"
    write_image(path, image, pixel_type="float")
    back, meta = read_image(path, with_metadata=True)
    assert same_bits(back, image)
    assert meta["stored"] == "float" and meta["channels"] == list(
        {1: "Y", 3: "RGB", 4: "RGBA"}[channels]
    )
    reference, spec = oiio_read(path)
    assert same_bits(reference, image)
    assert spec.format == oiio.FLOAT


def test_half_is_the_default_and_rounds_to_nearest_even(tmp_path):
    image = hdr_image()
    write_image(tmp_path / "h.exr", image)
    back, meta = read_image(tmp_path / "h.exr", with_metadata=True)
    assert meta["stored"] == "half" and meta["compression"] == "zip"
    assert same_bits(back, image.astype(np.float16))  # numpy's cast is IEEE round-to-nearest-even
    reference, spec = oiio_read(tmp_path / "h.exr")
    assert spec.format == oiio.HALF and same_bits(reference, back)


@pytest.mark.parametrize("compression", exr.LOSSLESS)
@pytest.mark.parametrize("pixel_type", ["half", "float"])
def test_lossless_compressions_round_trip_exactly(tmp_path, compression, pixel_type):
    image = hdr_image(37, 41, 4, seed=2)
    image[10:20] = 1.5  # flat areas for the run-length and predictive coders
    path = tmp_path / "c.exr"
    write_image(path, image, pixel_type=pixel_type, compression=compression)
    back, meta = read_image(path, with_metadata=True)
    expected = image.astype(np.float16) if pixel_type == "half" else image
    assert same_bits(back, expected)
    assert meta["compression"] == compression and meta["stored"] == pixel_type


@pytest.mark.parametrize("compression", ["none", "zip", "piz", "rle", "zips", "pxr24"])
def test_compressions_written_are_read_by_openimageio(tmp_path, compression):
    image = hdr_image(seed=3)
    write_image(tmp_path / "o.exr", image, compression=compression)
    reference, spec = oiio_read(tmp_path / "o.exr")
    assert same_bits(reference, image.astype(np.float16))
    assert spec.get_string_attribute("compression") == compression


@pytest.mark.parametrize("compression", ["b44", "b44a", "dwaa", "dwab", "pxr24"])
def test_lossy_compressions_stay_close(tmp_path, compression):
    y, x = np.mgrid[0:64, 0:64].astype(np.float32)
    image = np.stack([np.sin(x / 9) + 2, np.cos(y / 7) + 2, (x + y) / 64 + 1], -1)
    pixel_type = "float" if compression == "pxr24" else "half"  # b44 leaves float untouched
    write_image(tmp_path / "l.exr", image, pixel_type=pixel_type, compression=compression)
    back = read_image(tmp_path / "l.exr")
    np.testing.assert_allclose(back, image, rtol=EXR_LOSSY_RTOL)
    assert not same_bits(back, image.astype(np.float16 if pixel_type == "half" else np.float32))


def test_half_overflow_is_written_as_float_by_default_and_refused_as_half(tmp_path):
    """A value beyond 65504 (a sun) makes the default file float32, said in one warning, with
    every value kept; half asked for explicitly refuses, naming the option that keeps it."""
    image = np.array(
        [[[1e5, -1e5, 65504.0], [65519.0, 65520.0, 3.4e38], [np.inf, -np.inf, np.nan]]], np.float32
    )
    with pytest.warns(BakeshopWarning, match="values reach 3.4e\\+38.*32-bit floats") as said:
        write_image(tmp_path / "o.exr", image)
    assert [w.message.path for w in said] == [str(tmp_path / "o.exr")]  # not its temporary
    back, meta = read_image(tmp_path / "o.exr", with_metadata=True)
    assert meta["stored"] == "float" and same_bits(back, image)
    with pytest.raises(ArgumentError, match="beyond the 65504 .* pixel_type=float keeps them"):
        write_image(tmp_path / "h.exr", image, pixel_type="half")
    assert not (tmp_path / "h.exr").exists()
    # within half's range (infinities and NaN included), the default is half, without a word
    image[np.isfinite(image) & (np.abs(image) > 65504)] = 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_image(tmp_path / "s.exr", image)
    back, meta = read_image(tmp_path / "s.exr", with_metadata=True)
    assert meta["stored"] == "half" and same_bits(back, image)


def test_the_finite_peak_is_found_by_blocks_past_nan_and_infinities(monkeypatch):
    monkeypatch.setattr(exr, "_BLOCK_BYTES", 64)  # a block of rows at a time
    image = np.ones((40, 5, 3), np.float32)
    image[0, 0, 0], image[3, 1, 2] = np.nan, -np.inf
    image[39, 4, 1] = -7e4  # in the last block
    assert exr.finite_peak(image) == 7e4
    assert exr.finite_peak(np.full((2, 2, 1), np.nan)) == 0.0


@pytest.mark.parametrize("kernel", [True, False])
def test_half_rounding_of_every_kind_of_float32_is_numpys(tmp_path, kernel):
    """The writer's float32 -> half conversions (the one-pass kernel of float32 images, and
    numpy's of the same values given as float64) against numpy's IEEE conversion of float32
    (round to nearest even): random bit patterns of every exponent, and every pattern around the
    subnormal, normal and overflow boundaries of half, both signs (finite values beyond 65504
    made infinite: half refuses them)."""
    rng = np.random.default_rng(7)
    edges = [0x33000000, 0x33800000, 0x38000000, 0x38800000, 0x477FE000, 0x47800000]
    near = np.concatenate([np.arange(e - 0x2000, e + 0x2000, dtype=np.uint32) for e in edges])
    bits = np.concatenate(
        [rng.integers(0, 2**32, 300_000, dtype=np.uint64).astype(np.uint32), near, near | 1 << 31]
    )
    image = bits[: bits.size // 900 * 900].view(np.float32).reshape(-1, 300, 3)
    beyond = np.isfinite(image) & (np.abs(image) > 65504)
    image[beyond] = np.copysign(np.inf, image[beyond])
    with np.errstate(invalid="ignore"):  # NaN patterns
        given = image if kernel else image.astype(np.float64)  # float64: exact, numpy converts it
    write_image(tmp_path / "h.exr", given, pixel_type="half")
    with np.errstate(invalid="ignore"):
        expected = image.astype(np.float16).astype(np.float32)
    back = read_image(tmp_path / "h.exr")
    nan = np.isnan(expected)
    assert np.array_equal(np.isnan(back), nan)
    assert same_bits(back[~nan], expected[~nan])


def test_integer_and_float64_input_are_written_by_value(tmp_path):
    write_image(tmp_path / "i.exr", np.arange(12, dtype=np.uint16).reshape(2, 2, 3) * 1000)
    np.testing.assert_array_equal(read_image(tmp_path / "i.exr").ravel(), np.arange(12) * 1000)
    write_image(tmp_path / "d.exr", np.full((2, 2), 0.1), pixel_type="float")
    assert read_image(tmp_path / "d.exr").shape == (2, 2, 1)


def test_writes_compress_on_every_core_and_openimageio_reads_them(tmp_path):
    """The writer runs OpenEXR's global thread pool (what compresses chunks in parallel), one
    thread a core, and the file is the same image."""
    import os

    a = np.random.default_rng(5).random((300, 200, 3)).astype(np.float32)
    OpenEXR.set_global_thread_count(0)  # as a process that has not touched OpenEXR yet
    write_image(tmp_path / "a.exr", a, pixel_type="float")
    assert OpenEXR.global_thread_count() >= len(os.sched_getaffinity(0))
    got = oiio.ImageInput.open(str(tmp_path / "a.exr")).read_image("float")
    assert np.array_equal(got, a)


def test_a_forked_child_reads_and_writes_exr_after_its_parent(tmp_path):
    """The pool's threads do not survive a fork: without stopping it around one, a forked
    child's first EXR write waited for them forever (multiprocessing forks on Linux)."""
    import os
    import signal

    a = np.random.default_rng(6).random((64, 48, 3)).astype(np.float32)
    write_image(tmp_path / "parent.exr", a, pixel_type="float")  # the parent's pool runs
    pid = os.fork()
    if pid == 0:  # the child: done in 20 s or killed by the alarm
        signal.alarm(20)
        try:
            write_image(tmp_path / "child.exr", a, pixel_type="float")
            ok = np.array_equal(read_image(tmp_path / "child.exr"), a)
        except BaseException:
            ok = False
        os._exit(0 if ok else 1)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    assert np.array_equal(read_image(tmp_path / "parent.exr"), a)  # the parent's pool is back
    assert OpenEXR.global_thread_count() >= 1


def test_bad_write_options(tmp_path):
    with pytest.raises(ArgumentError, match="compression 'lzma'"):
        write_image(tmp_path / "a.exr", np.zeros((2, 2, 3)), compression="lzma")
    with pytest.raises(ArgumentError, match="pixel type 'double'"):
        write_image(tmp_path / "a.exr", np.zeros((2, 2, 3)), pixel_type="double")
    with pytest.raises(ArgumentError, match="bool"):
        write_image(tmp_path / "a.exr", np.zeros((2, 2, 3), bool))
    assert not list(tmp_path.iterdir())


# --- files written by OpenImageIO ----------------------------------------------------------------


@pytest.mark.parametrize(("fmt", "channels"), [("half", 3), ("float", 4), ("half", 1)])
def test_files_written_by_openimageio(tmp_path, fmt, channels):
    image = hdr_image(channels=channels, seed=4)
    path = tmp_path / "oiio.exr"
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(image.shape[1], image.shape[0], channels, fmt)
    if channels == 1:
        spec.channelnames = ("Y",)
    spec.attribute("compression", "piz")
    out.open(str(path), spec)
    out.write_image(image)
    out.close()
    back, meta = read_image(path, with_metadata=True)
    expected = image.astype(np.float16) if fmt == "half" else image
    assert same_bits(back, expected)
    assert meta["stored"] == fmt and meta["compression"] == "piz"


def test_tiled_file_written_by_openimageio(tmp_path):
    image = hdr_image(70, 90, 3, seed=5)
    path = tmp_path / "t.exr"
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(90, 70, 3, "float")
    spec.tile_width = spec.tile_height = 32
    out.open(str(path), spec)
    out.write_image(image)
    out.close()
    back, meta = read_image(path, with_metadata=True)
    assert same_bits(back, image) and meta["storage"] == "tiled"


# --- channel sets and layers ---------------------------------------------------------------------


def test_grey_alpha_becomes_rgba_and_extra_channels_are_listed(tmp_path):
    y = np.arange(6, dtype=np.float32).reshape(2, 3)
    a = np.full((2, 3), 0.5, np.float32)
    image, meta = read_image(write_raw(tmp_path / "ya.exr", {"Y": y, "A": a}), with_metadata=True)
    np.testing.assert_array_equal(image, np.stack([y, y, y, a], -1))
    rgbz = {"R": y, "G": y + 1, "B": y + 2, "Z": a}
    image, meta = read_image(write_raw(tmp_path / "z.exr", rgbz), with_metadata=True)
    np.testing.assert_array_equal(image, np.stack([y, y + 1, y + 2], -1))
    assert meta["ignored_channels"] == ["Z"]


def test_single_unnamed_channel_and_uint(tmp_path):
    depth = np.arange(6, dtype=np.uint32).reshape(2, 3) * 1000003
    image, meta = read_image(write_raw(tmp_path / "u.exr", {"id": depth}), with_metadata=True)
    np.testing.assert_array_equal(image[..., 0], depth.astype(np.float32))
    assert meta["stored"] == "uint" and meta["channels"] == ["id"]


def test_mixed_channel_types(tmp_path):
    r = np.ones((2, 2), np.float16)
    g = np.full((2, 2), 1 / 3, np.float32)
    path = write_raw(tmp_path / "m.exr", {"R": r, "G": g, "B": g})
    image, meta = read_image(path, with_metadata=True)
    assert meta["stored"] == "float/half"
    assert meta["channel_types"] == {"R": "half", "G": "float", "B": "float"}
    assert image[0, 0, 1] == np.float32(1 / 3)


def test_layers(tmp_path):
    planes = {
        f"{layer}.{c}": np.full((2, 2), i + 10 * k, np.float32)
        for k, layer in enumerate(["diffuse", "specular"])
        for i, c in enumerate("RGB")
    }
    path = write_raw(tmp_path / "layers.exr", planes)
    with pytest.raises(UnsupportedError, match="layer= one of 'diffuse', 'specular'"):
        read_image(path)
    image, meta = read_image(path, layer="specular", with_metadata=True)
    np.testing.assert_array_equal(image[0, 0], [10, 11, 12])
    assert meta["layer"] == "specular" and meta["channels"] == [
        "specular.R",
        "specular.G",
        "specular.B",
    ]
    with pytest.raises(ArgumentError, match="no layer 'beauty'"):
        read_image(path, layer="beauty")
    # a single layer is found without being named, and the default layer wins over named ones
    only = write_raw(tmp_path / "one.exr", {k: v for k, v in planes.items() if "diffuse" in k})
    assert read_image(only, with_metadata=True)[1]["layer"] == "diffuse"
    default = {"R": planes["diffuse.R"] + 5, "G": planes["diffuse.G"], "B": planes["diffuse.B"]}
    both = write_raw(tmp_path / "both.exr", {**planes, **default})
    image, meta = read_image(both, with_metadata=True)
    assert meta["layer"] == "" and image[0, 0, 0] == 5


def test_unrecognisable_channel_sets(tmp_path):
    uv = {"U": np.zeros((2, 2), np.float32), "V": np.zeros((2, 2), np.float32)}
    with pytest.raises(UnsupportedError, match="no RGB, RGBA or Y set"):
        read_image(write_raw(tmp_path / "uv.exr", uv))
    ryby = {k: np.zeros((2, 2), np.float32) for k in ("Y", "RY", "BY")}
    with pytest.raises(UnsupportedError, match="luminance-chroma"):
        read_image(write_raw(tmp_path / "ryby.exr", ryby))


def test_data_window_is_reported(tmp_path):
    planes = {c: np.full((3, 4), i, np.float32) for i, c in enumerate("RGB")}
    header = {
        "dataWindow": (np.array([10, 20], np.int32), np.array([13, 22], np.int32)),
        "displayWindow": (np.array([0, 0], np.int32), np.array([99, 49], np.int32)),
    }
    image, meta = read_image(write_raw(tmp_path / "w.exr", planes, header), with_metadata=True)
    assert image.shape == (3, 4, 3)
    assert meta["data_window"] == ((10, 20), (13, 22))
    assert meta["display_window"] == ((0, 0), (99, 49))


def test_decreasing_y_line_order_keeps_row_0_on_top(tmp_path):
    ramp = np.arange(12, dtype=np.float32).reshape(3, 4)
    header = {"lineOrder": OpenEXR.DECREASING_Y}
    path = write_raw(tmp_path / "dec.exr", {"R": ramp, "G": ramp, "B": ramp}, header)
    image = read_image(path)
    np.testing.assert_array_equal(image[..., 0], ramp)
    assert same_bits(image, oiio_read(path)[0])


def test_multipart_file(tmp_path):
    parts = [
        OpenEXR.Part({}, {"R": np.zeros((2, 2), np.float32), "G": np.zeros((2, 2), np.float32),
                          "B": np.zeros((2, 2), np.float32)}, "beauty"),
        OpenEXR.Part({}, {"Z": np.full((2, 2), 7, np.float32)}, "depth"),
    ]  # fmt: skip
    OpenEXR.File(parts).write(str(tmp_path / "mp.exr"))
    image, meta = read_image(tmp_path / "mp.exr", part=1, with_metadata=True)
    assert image.shape == (2, 2, 1) and image[0, 0, 0] == 7 and meta["parts"] == 2
    with pytest.raises(ArgumentError, match="part 2"):
        read_image(tmp_path / "mp.exr", part=2)


# --- corrupt files -------------------------------------------------------------------------------


def small_file(tmp_path):
    write_image(tmp_path / "s.exr", hdr_image(3, 4, 3), compression="none")
    return (tmp_path / "s.exr").read_bytes()


def test_truncated_and_corrupt_files_are_format_errors_and_print_nothing(tmp_path, capfd):
    data = small_file(tmp_path)
    fuzzing.assert_refused(
        tmp_path / "bad.exr", data[: len(data) // 2], "corrupt or truncated OpenEXR"
    )
    fuzzing.assert_refused(tmp_path / "bad.exr", data[:4], None)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_absurd_data_window_is_refused_before_reading(tmp_path):
    planes = {c: np.zeros((1, 1), np.float32) for c in "RGB"}
    path = write_raw(tmp_path / "big.exr", planes)
    with pytest.raises(FormatError, match="exceeds the limit"):
        exr.read(path, max_pixels=0)


@pytest.fixture(scope="module")
def seed_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("exr_seeds")
    seeds = []
    for compression in ("none", "zip", "piz"):
        write_image(folder / "s.exr", hdr_image(3, 5, 4), compression=compression)
        seeds.append((folder / "s.exr").read_bytes())
    return seeds


scratch = fuzzing.scratch_file("f.exr")


@pytest.mark.slow
def test_truncation_at_every_offset(scratch, seed_files):
    for data in seed_files:
        fuzzing.assert_truncations_refused(scratch, data)


@fuzzing.FUZZ
@given(st.binary(max_size=300))
def test_random_bytes(scratch, data):
    fuzzing.decode(scratch, exr.MAGIC + data)


@fuzzing.FUZZ
@given(st.integers(0, 2), fuzzing.edits(400, min_size=1))
def test_mutations_of_valid_files(scratch, seed_files, which, changes):
    fuzzing.decode(scratch, fuzzing.mutate(seed_files[which], changes))


@pytest.mark.parametrize(
    "channels, count",
    [
        ({c: hdr_image(5, 7, 1)[..., 0].astype(np.float16) for c in "RGBA"}, 4),
        ({"Y": hdr_image(5, 7, 1)[..., 0], "A": np.full((5, 7), 0.5, np.float16)}, 4),
        (
            {
                "R": hdr_image(5, 7, 1)[..., 0],
                "G": np.full((5, 7), 2, np.uint32),
                "B": np.zeros((5, 7), np.float16),
                "extra.Z": np.ones((5, 7), np.float32),
            },
            3,
        ),
    ],  # fmt: skip
    ids=["half RGBA", "Y A", "mixed types and an ignored channel"],
)
def test_frame_buffer_and_whole_file_reads_agree(tmp_path, monkeypatch, channels, count):
    """The first part is read through the frame buffer (only the channels returned); the whole
    file interface, which bindings without ``InputFile`` fall back to, gives the same."""
    path = write_raw(tmp_path / "a.exr", channels, {"dataWindow": ((3, -2), (9, 2))})
    image, meta = read_image(path, with_metadata=True)
    monkeypatch.delattr(OpenEXR, "InputFile")
    whole, whole_meta = read_image(path, with_metadata=True)
    assert same_bits(image, whole) and image.shape == (5, 7, count)
    assert meta == whole_meta
