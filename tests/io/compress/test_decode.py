"""bakeshop's decoders against the specification's own examples, hand-built blocks, and
OpenImageIO's decoding of the same files (ISPC's blocks, written as DDS)."""

import numpy as np
import OpenImageIO as oiio
import pytest

from bakeshop.io.compress import decode_image, encode_image
from bakeshop.io.compress.decode import decode_blocks, srgb_to_linear
from bakeshop.io.compress.formats import FORMATS
from bakeshop.io.compress.texture import encode_texture
from bakeshop.io.dds import write_dds_blocks
from tests.io.compress.conftest import SUNNY, hdr_chain, ldr_chain
from tests.io.compress.tolerances import BPTC_EXACT, S3TC_INTEGER_DECODER, UNORM8_FLOAT


def block_from_bits(bits: dict[int, int]) -> np.ndarray:
    """A 128-bit block with the given bit positions set to the given values (others 0)."""
    value = 0
    for position, bit in bits.items():
        value |= bit << position
    return np.frombuffer(value.to_bytes(16, "little"), np.uint8).reshape(1, 16)


def put(bits: dict, start: int, count: int, value: int) -> int:
    """Write ``value`` into ``count`` bits from ``start`` (LSB first); return the next position."""
    for k in range(count):
        bits[start + k] = (value >> k) & 1
    return start + count


# --- the specification's worked examples ------------------------------------------------------


def test_bc7_mode2_example_of_the_specification():
    """Khronos Data Format 1.4, section 18.1 (note): in mode 2 with partition 6, texel (1, 2)
    (index 9) is in subset 1 and its two index bits are block bits 115 and 116."""
    bits = {2: 1}  # mode 2: bits 0, 1 zero, bit 2 one
    put(bits, 3, 6, 6)  # partition 6
    # colour endpoints: 5 bits per channel, 6 endpoints per channel (R, then G, then B)
    position = 9
    for _channel in range(3):
        for endpoint in range(6):
            position = put(bits, position, 5, 31 if endpoint == 3 else 0)
    assert position == 99  # where the spec's table says the indices start
    put(bits, 115, 2, 3)  # texel 9 -> index 3 -> weight 64 -> endpoint 3 (all 255)
    texels = decode_blocks(block_from_bits(bits), FORMATS["bc7"])[0]
    assert np.all(texels[9, :3] == 1.0) and texels[9, 3] == 1.0
    others = np.delete(texels, 9, axis=0)
    assert np.all(others[:, :3] == 0.0)


def test_bc1_example_of_the_specification():
    """Khronos Data Format 1.4, S3TC figure bc1: colour0 (29/31, 60/63, 1/31), colour1
    (20/31, 2/63, 30/31); 29 > 20 gives two interpolated colours; swapped, one and black."""
    c0 = 29 << 11 | 60 << 5 | 1
    c1 = 20 << 11 | 2 << 5 | 30
    rgb0 = np.array([29 / 31, 60 / 63, 1 / 31])
    rgb1 = np.array([20 / 31, 2 / 63, 30 / 31])
    codes = 0b11_10_01_00  # texels 0..3 use codes 0, 1, 2, 3
    block = np.array([c0 & 255, c0 >> 8, c1 & 255, c1 >> 8, codes, 0, 0, 0], np.uint8).reshape(1, 8)
    t = decode_blocks(block, FORMATS["bc1"])[0]
    want = [rgb0, rgb1, (2 * rgb0 + rgb1) / 3, (rgb0 + 2 * rgb1) / 3]
    np.testing.assert_allclose(t[:4, :3], want, atol=1e-7)
    assert np.all(t[:4, 3] == 1)
    swapped = np.array([c1 & 255, c1 >> 8, c0 & 255, c0 >> 8, codes, 0, 0, 0], np.uint8)
    t = decode_blocks(swapped.reshape(1, 8), FORMATS["bc1"])[0]
    np.testing.assert_allclose(t[2, :3], (rgb0 + rgb1) / 2, atol=1e-7)
    assert np.all(t[3] == 0)  # BC1 with alpha: code 3 is transparent black
    t = decode_blocks(np.concatenate([np.zeros(8, np.uint8), swapped]).reshape(1, 16),
                      FORMATS["bc3"])[0]  # fmt: skip
    np.testing.assert_allclose(t[3, :3], (rgb1 + 2 * rgb0) / 3, atol=1e-7)  # BC3: always 4 colours


def test_bc4_values_follow_the_rgtc_tables():
    """RGTC: red0 > red1 gives six interpolated values; otherwise four plus 0 and 1."""
    for r0, r1 in ((200, 40), (40, 200)):
        codes = sum(i << (3 * i) for i in range(8))
        block = np.array([r0, r1, *codes.to_bytes(6, "little")], np.uint8).reshape(1, 8)
        got = decode_blocks(block, FORMATS["bc4"])[0, :8, 0]
        if r0 > r1:
            want = [r0, r1] + [((8 - i) * r0 + (i - 1) * r1) / 7 for i in range(2, 8)]
        else:
            want = [r0, r1] + [((6 - i) * r0 + (i - 1) * r1) / 5 for i in range(2, 6)] + [0, 255]
        np.testing.assert_allclose(got, np.array(want) / 255, atol=1e-7)


def test_bc6h_mode3_block_by_hand():
    """Mode 3 (10-bit endpoints, no transform): unsigned unquantisation
    ((x << 15) + 0x4000) >> 9, interpolation and (i * 31) >> 6, worked out here by hand."""
    bits = {0: 1, 1: 1}  # mode 3 = 00011 in the low five bits
    e0, e1 = (100, 300, 1023), (900, 0, 512)
    position = 5
    for c in range(3):
        position = put(bits, position, 10, e0[c])
    for c in range(3):
        position = put(bits, position, 10, e1[c])
    assert position == 65
    position = put(bits, 65, 3, 0)  # texel 0: anchor, three bits
    for _ in range(15):
        position = put(bits, position, 4, 15)  # the others: index 15 (weight 64 -> E1)

    def unq(x):
        return 0 if x == 0 else 0xFFFF if x == 1023 else ((x << 15) + 0x4000) >> 9

    def half(v):
        return np.array([(v * 31) >> 6], np.uint16).view(np.float16).astype(np.float32)[0]

    t = decode_blocks(block_from_bits(bits), FORMATS["bc6h"])[0]
    assert [t[0, c] for c in range(3)] == [half(unq(v)) for v in e0]
    assert [t[5, c] for c in range(3)] == [half(unq(v)) for v in e1]


def test_reserved_blocks_decode_to_zero():
    bc6h = block_from_bits({0: 1, 1: 1, 4: 1, 2: 1})  # mode 0b10111 = 23: reserved
    assert np.all(decode_blocks(bc6h, FORMATS["bc6h"]) == 0)
    assert np.all(decode_blocks(np.zeros((1, 16), np.uint8), FORMATS["bc7"]) == 0)


# --- against OpenImageIO ----------------------------------------------------------------------


def oiio_levels(path):
    """Every mip level of a 2-D DDS as OpenImageIO decodes it (float)."""
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    levels = []
    m = 0
    while inp.seek_subimage(0, m):
        levels.append(inp.read_image(0, m, 0, inp.spec().nchannels, "float"))
        m += 1
    inp.close()
    return levels


FORMAT_CASES = [
    ("bc6h", BPTC_EXACT),
    ("bc7", UNORM8_FLOAT),
    ("bc1", S3TC_INTEGER_DECODER),
    ("bc3", S3TC_INTEGER_DECODER),
    ("bc4", S3TC_INTEGER_DECODER),
    ("bc5", S3TC_INTEGER_DECODER),
]


@pytest.mark.parametrize("name,tolerance", FORMAT_CASES)
@pytest.mark.parametrize("width,height", [(64, 32), (37, 19)])
def test_every_level_matches_openimageio(tmp_path, name, tolerance, width, height):
    """ISPC's blocks of every level down to 1x1 (2x2 and 1x1 are padded blocks), written as DDS,
    decoded by OpenImageIO and by bakeshop."""
    if name == "bc6h":
        level0 = hdr_chain(1, 64, cube=False)[0][:height, :width]
    else:
        level0 = ldr_chain(2, 64, cube=False)[0][:height, :width]
    from bakeshop.io.compress.pipeline import box_mips

    texture = encode_texture(box_mips(level0, cube=False), name, quality="fast")
    write_dds_blocks(tmp_path / "t.dds", texture)
    theirs = oiio_levels(tmp_path / "t.dds")
    ours = texture.decode()
    assert len(theirs) == len(ours) == max(width, height).bit_length()
    for m, (a, b) in enumerate(zip(theirs, ours, strict=True)):
        assert a.shape[:2] == b.shape[:2], m
        c = b.shape[2]
        np.testing.assert_allclose(b, a[..., :c], rtol=0, atol=tolerance, err_msg=f"level {m}")


def test_bc7_srgb_matches_openimageio_before_the_transfer_function(tmp_path):
    """OpenImageIO returns the stored (sRGB-encoded) values of BC7_UNORM_SRGB; bakeshop returns
    them linear, as a sampler does: the stored values agree exactly."""
    level0 = ldr_chain(3, 32, cube=False)[0]
    texture = encode_texture([level0], "bc7-srgb")
    write_dds_blocks(tmp_path / "s.dds", texture)
    theirs = oiio_levels(tmp_path / "s.dds")[0]
    raw = decode_blocks(np.frombuffer(texture.levels[0], np.uint8).reshape(-1, 16),
                        FORMATS["bc7-srgb"])  # fmt: skip
    raw = raw.reshape(8, 8, 4, 4, 4).transpose(0, 2, 1, 3, 4).reshape(32, 32, 4)
    np.testing.assert_allclose(raw, theirs, rtol=0, atol=UNORM8_FLOAT)
    ours = texture.decode()[0]
    np.testing.assert_allclose(ours[..., :3], srgb_to_linear(theirs[..., :3]), atol=1e-6)


def test_signed_bc6h_matches_openimageio(tmp_path):
    """bakeshop's own signed encoder's blocks (negative values included) decode the same in
    OpenImageIO (DXGI_FORMAT_BC6H_SF16) as in bakeshop."""
    level0 = hdr_chain(4, 32, cube=False)[0]
    level0[: level0.shape[0] // 2] *= -1
    texture = encode_texture([level0], "bc6h-signed")
    write_dds_blocks(tmp_path / "sf.dds", texture)
    theirs = oiio_levels(tmp_path / "sf.dds")[0]
    ours = texture.decode()[0]
    np.testing.assert_array_equal(ours, theirs[..., :3])
    assert (ours < 0).any() and np.isfinite(ours).all()


def test_real_probe_bc6h_matches_openimageio(tmp_path):
    from bakeshop.io import read_image

    image = np.minimum(read_image(SUNNY)[:128, 448:704], 65504)
    data = encode_image(image, "bc6h")
    texture = encode_texture([image], "bc6h")
    assert texture.levels[0] == data
    write_dds_blocks(tmp_path / "p.dds", texture)
    np.testing.assert_array_equal(
        decode_image(data, "bc6h", 256, 128), oiio_levels(tmp_path / "p.dds")[0]
    )
