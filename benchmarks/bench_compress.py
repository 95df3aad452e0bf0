"""Time block compression: bakeshop against ispc-texcomp called directly and an uncompressed write.

Inputs: the sunny default probe and the dawn probe (1024x512 latlong, CC0), and a 4096x2048
probe made by upsampling the sunny one (bilinear: real structure at 4x the pixels; its
quality numbers flatter the encoder, its speed does not; "basic" and "slow" are timed on the 1k
probes only). For each BC6H profile:

- "ispc direct": one ``compress_blocks_bc6h`` call on a half-float RGBA surface prepared
  beforehand (the encoder alone, one thread: the wheel's call is single-threaded);
- "bakeshop 1 thread": ``encode_image(workers=1)`` from float32 RGB (conversion to half, RGBA,
  padding, strip cutting included): its excess over "ispc direct" is bakeshop's overhead.
  Both are CPU times of the process (bakeshop's kernels set to one thread), which a shared
  machine's load inflates far less than wall time;
- "bakeshop": the default, strips on both cores (wall time);

then quality (multi-exposure PSNR, log2 RMSE) of bakeshop's output decoded by bakeshop. Also:
the 6x1024 cube with all its mips through ``encode_texture`` (the issue's 3 s target) and
through the whole ``compress_levels`` (encode, decode, measure), an uncompressed half-float
DDS write of the same chain, bakeshop's decoder speed, BC7/RGBD-in-BC7 and BC5 normal maps.

Times are the best of ``REPEATS`` after a warm-up (imports, first-touch page faults), on a
machine shared with other jobs. Run: ``.venv/bin/python benchmarks/bench_compress.py
[bc6h] [cube] [other]`` (all three by default; about five minutes on an idle machine).
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

REPEATS = 3
PROFILES = ("veryfast", "fast", "basic", "slow")


def best(fn, repeats=REPEATS, clock=time.perf_counter):
    """Best of ``repeats`` timings of ``fn()`` after one warm-up: wall time, or with
    ``clock=time.process_time`` the process's CPU time (steadier on a shared machine; right
    for single-threaded runs)."""
    fn()  # warm-up
    times = []
    for _ in range(repeats):
        t = clock()
        out = fn()
        times.append(clock() - t)
    return min(times), out


def cpu(fn, repeats=REPEATS):
    return best(fn, repeats, time.process_time)


def probes():
    from bakeshop import sphere
    from bakeshop.io import read_image

    sunny = read_image(ROOT / "bakeshop" / "data" / "default_probe.hdr")
    dawn = read_image(ROOT / "tests" / "data" / "kiara_1_dawn_1k.hdr")
    big = sphere.remap(sunny, "latlong", "latlong", size=2048, filter="bilinear")
    return {"sunny 1024x512": sunny, "dawn 1024x512": dawn, "sunny 4096x2048 (upsampled)": big}


def bc6h_table():
    import ispc_texcomp as it

    from bakeshop.io.compress import decode_image, encode_image
    from bakeshop.io.compress.quality import log2_rmse, mpsnr

    rows = []
    for name, image in probes().items():
        image = np.minimum(image, 65504).astype(np.float32)
        h, w = image.shape[:2]
        mpx = h * w / 1e6
        half = np.concatenate([image, np.ones_like(image[..., :1])], -1).astype(np.float16)
        surface = it.RGBASurface(half.tobytes(), w, h, w * 8)
        for profile in PROFILES if mpx < 1 else PROFILES[:2]:  # slow profiles: 1k probes
            settings = it.BC6HEncSettings.from_profile(profile)
            direct, _ = cpu(lambda s=settings, f=surface: it.compress_blocks_bc6h(f, s))
            one, _ = cpu(lambda p=profile, i=image: encode_image(i, "bc6h", quality=p, workers=1))
            two, data = best(lambda p=profile, i=image: encode_image(i, "bc6h", quality=p))
            decoded = decode_image(data, "bc6h", w, h)
            rows.append((name, profile, mpx / direct, mpx / one, (one - direct) / direct,
                         mpx / two, mpsnr(image, decoded), log2_rmse(image, decoded)))  # fmt: skip
            print(
                f"| {name} | {profile} | {rows[-1][2]:.2f} | {rows[-1][3]:.2f} | "
                f"{100 * rows[-1][4]:+.1f}% | {rows[-1][5]:.2f} | {rows[-1][6]:.2f} | "
                f"{rows[-1][7]:.4f} |",
                flush=True,
            )
    return rows


def cube_chain():
    from bakeshop import sphere
    from bakeshop.io import read_image
    from bakeshop.io.compress.decode import decode_image
    from bakeshop.io.compress.pipeline import box_mips, compress_levels
    from bakeshop.io.compress.texture import encode_texture
    from bakeshop.io.dds import write_dds, write_dds_blocks

    sunny = read_image(ROOT / "bakeshop" / "data" / "default_probe.hdr")
    cube = sphere.remap(sunny, "latlong", "cube", size=1024, filter="bilinear")
    chain = [np.minimum(level, 65504) for level in box_mips(cube, cube=True)]
    texels = sum(level[..., 0].size for level in chain)
    print(f"\n6x1024 cube, {len(chain)} levels, {texels / 1e6:.2f} Mtexels:", flush=True)
    encode, texture = best(lambda: encode_texture(chain, "bc6h", quality="fast"))
    print(f"| encode_texture, BC6H fast, 2 threads | {encode:.2f} s | {texels / 1e6 / encode:.2f}"
          " Mpx/s |", flush=True)  # fmt: skip
    one, _ = cpu(lambda: encode_texture(chain, "bc6h", quality="fast", workers=1), 1)
    print(f"| encode_texture, BC6H fast, 1 thread, CPU time | {one:.2f} s | "
          f"{texels / 1e6 / one:.2f} Mpx/s |")  # fmt: skip
    whole, result = best(lambda: compress_levels(chain, "bc6h", cube=True), 1)
    print(f"| compress_levels (encode + decode + measure) | {whole:.2f} s | "
          f"{result.report['quality']['mpsnr_db']:.2f} dB |")  # fmt: skip
    decode, _ = best(lambda: texture.decode())
    print(f"| bakeshop decoder, whole chain | {decode:.2f} s | {texels / 1e6 / decode:.1f} Mpx/s |")
    data = texture.face(0, 0)
    face, _ = best(lambda: decode_image(data, "bc6h", 1024, 1024))
    print(
        f"| bakeshop decoder, one 1024 face | {face * 1e3:.1f} ms | {1.048576 / face:.1f} Mpx/s |"
    )
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _ = best(lambda: write_dds_blocks(Path(tmp) / "c.dds", texture))
        raw, _ = best(lambda: write_dds(Path(tmp) / "f.dds", chain, dtype="float16"))
        sizes = [os.path.getsize(Path(tmp) / n) for n in ("c.dds", "f.dds")]
    print(f"| write BC6H DDS (blocks ready) | {blocks * 1e3:.0f} ms | {sizes[0] / 1e6:.1f} MB |")
    print(
        f"| write float16 DDS, uncompressed (peer) | {raw * 1e3:.0f} ms | {sizes[1] / 1e6:.1f} MB |"
    )


def ldr_and_normals():
    import ispc_texcomp as it

    from bakeshop import sphere
    from bakeshop.io import read_image
    from bakeshop.io.compress import encode_image
    from bakeshop.io.compress.pipeline import box_mips, compress_levels
    from bakeshop.normals.encoding import read_normal_map

    print("\nOther formats (bakeshop, 2 threads, one level unless said):", flush=True)
    sunny = read_image(ROOT / "bakeshop" / "data" / "default_probe.hdr")
    cube = sphere.remap(sunny, "latlong", "cube", size=256, filter="area")
    for name in ("rgbd-bc7", "rgbm-bc7", "bc6h"):
        t, result = best(lambda n=name: compress_levels([cube], n, cube=True, overflow="clamp"), 1)
        q = result.report["quality"]
        print(f"| {name}, sunny 6x256 cube | {6 * 256 * 256 / 1e6 / t:.2f} Mpx/s | "
              f"{q['mpsnr_db']:.2f} dB | {q['log2_rmse']:.4f} |")  # fmt: skip
    normals = read_normal_map(ROOT / "tests" / "data" / "scratched_gold_normal_256.png")
    tiled = np.tile(normals, (4, 4, 1))  # 1024x1024
    chain = box_mips(tiled, cube=False, normals=True)
    t, result = best(lambda: compress_levels(chain, "bc5", cube=False, normals=True), 1)
    q = result.report["quality"]
    print(f"| bc5 normals 1024 + mips | {1.398 / t:.2f} Mpx/s | mean {q['angle_mean_deg']:.3f} deg"
          f" | p99 {q['angle_p99_deg']:.2f} deg |")  # fmt: skip
    packed = np.clip((tiled + 1) / 2, 0, 1)
    u8 = np.rint(packed[..., :2] * 255).astype(np.uint8)
    surface = it.RGBASurface(np.ascontiguousarray(u8).tobytes(), 1024, 1024, 2048)
    direct, _ = best(lambda: it.compress_blocks_bc5(surface))
    mine, _ = best(lambda: encode_image(packed[..., :2], "bc5", workers=1))
    print(f"| bc5 1024, ispc direct vs bakeshop 1 thread | {direct * 1e3:.1f} ms | "
          f"{mine * 1e3:.1f} ms |")  # fmt: skip
    rgba = np.concatenate([packed, np.ones_like(packed[..., :1])], -1)
    u8 = np.rint(rgba * 255).astype(np.uint8)
    surface = it.RGBASurface(u8.tobytes(), 1024, 1024)
    settings = it.BC7EncSettings.from_profile("fast")
    direct, _ = best(lambda: it.compress_blocks_bc7(surface, settings), 1)
    mine, _ = best(lambda: encode_image(rgba, "bc7", workers=1), 1)
    print(f"| bc7 fast 1024, ispc direct vs bakeshop 1 thread | {direct:.2f} s | {mine:.2f} s |")


def main():
    sections = sys.argv[1:] or ["bc6h", "cube", "other"]
    import ispc_texcomp

    from bakeshop import threads

    print(
        f"bakeshop compression benchmark; ispc-texcomp {ispc_texcomp.__version__}, "
        f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}"
    )
    if "bc6h" in sections:
        print("\n| probe | BC6H profile | ispc direct Mpx/s | bakeshop 1 thread Mpx/s | overhead "
              "| bakeshop 2 threads Mpx/s | mPSNR dB | log2 RMSE |")  # fmt: skip
        print("|---|---|---|---|---|---|---|---|")
        with threads.limited(1):  # one-thread conversions: their CPU time compares with ISPC's
            bc6h_table()
    if "cube" in sections:
        cube_chain()
    if "other" in sections:
        ldr_and_normals()
    print(f"\nload at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
