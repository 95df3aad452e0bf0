"""Make the pictures and tables of docs/normals.md.

Pictures (docs/images/): normals_combine.png (macro, detail, combined), normals_methods.png
(where each method differs from the exact blend on the real maps), normals_groundtruth.png
(the analytic surface and the error of exact and RNM for construction (b)),
normals_transfer.png (a dot pattern transferred into a torus' UV layout, three projections).
Tables (printed as Markdown): the ground-truth error of every method for each construction.

Run: ``.venv/bin/python docs/images/normals_figures.py [DETAIL]``. The macro map is the Khronos
NormalTangentTest map in tests/data; DETAIL is the whole tileable 1K normal map of cgbookcase's
Scratched Gold 01 (CC0, https://www.cgbookcase.com/textures/scratched-gold-01; tests/data holds
only crops of it, which do not tile), by default tests/data/Scratched_gold_01_1K_Normal.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # tests.normals.groundtruth and benchmarks/bench_normals

from bakeshop.normals.blend import METHODS, blend  # noqa: E402
from bakeshop.normals.encoding import encode_normals, read_normal_map  # noqa: E402
from bakeshop.normals.height import height_to_normal  # noqa: E402
from bakeshop.normals.tiling import place_detail  # noqa: E402
from bakeshop.normals.transfer import transfer_detail  # noqa: E402
from tests.normals import groundtruth as gt  # noqa: E402

DATA = ROOT / "tests" / "data"
#: the tileable detail map (see the module notes), given on the command line or in tests/data.
DETAIL = Path(sys.argv[1]) if len(sys.argv) > 1 else DATA / "Scratched_gold_01_1K_Normal.png"
OUT = Path(__file__).resolve().parent


def out(line: str) -> None:
    sys.stdout.write(line + "\n")


def angle(a, b):
    return gt.angular_error(np.asarray(a, np.float64), np.asarray(b, np.float64))


#: a full-resolution window around one of the macro map's bumps
CROP = (slice(150, 534), slice(330, 714))
STRENGTH = 3.0


def combine_figures():
    macro = read_normal_map(DATA / "NormalTangentTest_Normal.png")
    detail = read_normal_map(DETAIL, convention="dx")
    placed = place_detail(detail, macro.shape[:2], tile=2)  # one detail texel per macro texel
    results = {m: blend(macro, placed, method=m, strength=STRENGTH) for m in METHODS}
    shown = blend(np.broadcast_to(np.float32([0, 0, 1]), placed.shape), placed, strength=STRENGTH)
    fig, ax = plt.subplots(1, 3, figsize=(9, 3.2), dpi=100)
    panels = [
        ("macro (NormalTangentTest)", macro),
        (f"detail, tile 2, strength {STRENGTH:g}", shown),
        ("exact blend", results["exact"]),
    ]
    for a, (title, img) in zip(ax, panels, strict=True):
        a.imshow(np.clip(encode_normals(img[CROP]), 0, 1))
        a.set_title(title, fontsize=9)
        a.axis("off")
    fig.tight_layout()
    fig.savefig(OUT / "normals_combine.png")
    plt.close(fig)

    others = [m for m in METHODS if m not in ("exact", "sg")]
    fig, ax = plt.subplots(1, len(others), figsize=(2.2 * len(others), 2.6), dpi=90)
    for a, m in zip(ax, others, strict=True):
        diff = angle(results[m][CROP], results["exact"][CROP])
        im = a.imshow(diff, cmap="magma", vmin=0, vmax=4)
        on_bumps = angle(macro, np.float32([0, 0, 1])) > 5
        mean = angle(results[m], results["exact"])[on_bumps].mean()
        a.set_title(f"{m}: {mean:.2f}° on bumps", fontsize=8)
        a.axis("off")
    fig.colorbar(im, ax=ax, shrink=0.8, label="degrees from exact")
    fig.savefig(OUT / "normals_methods.png", bbox_inches="tight")
    plt.close(fig)


def groundtruth_tables():
    out("\n| method | (a) mean | (a) max | (b) mean | (b) max | (c) mean | (c) max |")
    out("|---|---|---|---|---|---|---|")
    errors = {}
    for c in gt.CONSTRUCTIONS:
        macro, det, truth = gt.maps(c, size=256, tiles=96)
        errors[c] = {m: angle(blend(macro, det, method=m), truth) for m in METHODS}
    for m in METHODS:
        cells = [f"{errors[c][m].mean():.3f} | {errors[c][m].max():.2f}" for c in gt.CONSTRUCTIONS]
        out(f"| {m} | " + " | ".join(cells) + " |")
    out("\n(b) as the detail gets finer (same slopes, smaller heights): mean / max degrees")
    out("| tiles | " + " | ".join(METHODS) + " |")
    out("|---|" + "---|" * len(METHODS))
    for tiles in (24, 96, 384):  # 1024 points a side: no aliasing of the finest detail
        macro, det, truth = gt.maps("uv", size=1024, tiles=tiles)
        e = {m: angle(blend(macro, det, method=m), truth) for m in METHODS}
        out(
            f"| {tiles} | "
            + " | ".join(f"{e[m].mean():.3f} / {e[m].max():.2f}" for m in METHODS)
            + " |"
        )
    macro, det, truth = gt.maps("uv", size=256, tiles=96)
    h, _, _ = gt.macro_height(
        *np.meshgrid((np.arange(256) + 0.5) / 256, ((np.arange(256) + 0.5) / 256)[::-1])
    )
    fig, ax = plt.subplots(1, 3, figsize=(9, 3.0), dpi=90)
    ax[0].imshow(h, cmap="gray")
    ax[0].set_title("macro height H(u, v)", fontsize=9)
    for a, m in zip(ax[1:], ("exact", "rnm"), strict=True):
        im = a.imshow(angle(blend(macro, det, method=m), truth), cmap="magma", vmin=0, vmax=3)
        a.set_title(f"(b): {m} error", fontsize=9)
    for a in ax:
        a.axis("off")
    fig.colorbar(im, ax=ax, shrink=0.8, label="degrees")
    fig.savefig(OUT / "normals_groundtruth.png", bbox_inches="tight")
    plt.close(fig)


def dots(size=256, per_side=4):
    """A tileable height map of round dots and its normal map (shows projection distortion)."""
    c = (np.arange(size) + 0.5) / size * per_side
    x, y = np.meshgrid(c % 1 - 0.5, c % 1 - 0.5)
    height = np.clip(1 - (x * x + y * y) / 0.09, 0, None) ** 0.5
    return height_to_normal(height.astype(np.float32), strength=12)


def transfer_figure():
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_normals import torus

    mesh = torus()
    fig, ax = plt.subplots(1, 3, figsize=(9, 3.2), dpi=100)
    for a, projection in zip(ax, ("uv2", "box", "triplanar"), strict=True):
        tile = 0.25 if projection == "uv2" else 1.0
        n, _ = transfer_detail(mesh, dots(), (512, 512), projection=projection, tile=tile)
        a.imshow(np.clip(encode_normals(n), 0, 1))
        a.set_title(f"torus UV layout, {projection}", fontsize=9)
        a.axis("off")
    fig.tight_layout()
    fig.savefig(OUT / "normals_transfer.png")
    plt.close(fig)


if __name__ == "__main__":
    if not DETAIL.is_file():
        sys.exit(
            f"normals_figures.py: {DETAIL}: not found; download the 1K normal map of "
            "https://www.cgbookcase.com/textures/scratched-gold-01 and give its path"
        )
    combine_figures()
    groundtruth_tables()
    transfer_figure()
