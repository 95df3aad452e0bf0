"""Make the pictures and the comparison table of docs/photographs.md.

A synthetic stack of the embedded default probe with a Buie sun (the test stack of
tests/photo/test_sun.py: seven 8-bit brackets, 1/4000 s to 1 s, a gamma-2.2 camera with a
shoulder and noise) is merged by bakeshop and by OpenCV's CalibrateDebevec + MergeDebevec.

Pictures (docs/images/): photographs_stack.png (the brackets), photographs_response.png (the
recovered curves against the truth), photographs_merge.png (the merges and their errors),
photographs_confidence.png (votes and status), photographs_sun.png (the sun's profile),
photographs_unwrap.png (mirror-ball photos, their unwraps and the two-view merge). The table of
the comparison is printed as Markdown.

Run: ``.venv/bin/python docs/images/photographs_figures.py`` (about a minute).
"""

from __future__ import annotations

import io
import math
import sys
from pathlib import Path

import cv2
import matplotlib

matplotlib.use("Agg")
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from bakeshop.image import exposure, to_srgb8  # noqa: E402
from bakeshop.photo import (  # noqa: E402
    Circle,
    best_yaw,
    log2_rmse,
    make_stack,
    merge_stack,
    merge_views,
    multi_exposure_psnr,
    recover_response,
    recover_sun,
    relative_scale,
    unwrap,
)
from tests.photo import synthetic  # noqa: E402

HERE = Path(__file__).resolve().parent
TIMES = 1 / 4000 * 4.0 ** np.arange(7)
GAIN = 0.18 * 60 / 0.5
DPI = 100


def say(line: str) -> None:
    sys.stdout.write(line + "\n")


def save(fig: Figure, name: str) -> None:
    FigureCanvasAgg(fig)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    Image.open(buffer).convert("RGB").save(HERE / name, optimize=True)


def picture(image, ev=0.0):
    return to_srgb8(exposure(np.maximum(image, 0), ev))


def exposure_label(t):
    return f"1/{1 / t:.0f} s" if t < 1 else f"{t:.2g} s"


def main() -> None:
    probe, sky, truth_irr = synthetic.sunny_probe()
    frames = synthetic.shoot(probe, TIMES, gain=GAIN)
    stack = make_stack(frames, TIMES)

    # --- the stack -------------------------------------------------------------------------
    fig = Figure(figsize=(12, 3.3))
    for j, (t, f) in enumerate(zip(TIMES, frames, strict=True)):
        ax = fig.add_subplot(2, 4, j + 1)
        ax.imshow(f[::2, ::2])
        ax.set_title(exposure_label(t), fontsize=9)
        ax.axis("off")
    ax = fig.add_subplot(2, 4, 8)
    ax.imshow(picture(probe * GAIN / 60, 0)[::2, ::2])
    ax.set_title("the truth (linear, shown at 1/60 s)", fontsize=9)
    ax.axis("off")
    fig.suptitle("Seven 8-bit brackets, 2 stops apart: the sun is clipped even at 1/4000 s")
    fig.tight_layout()
    save(fig, "photographs_stack.png")

    # --- responses -----------------------------------------------------------------------
    debevec = recover_response(stack.codes, stack.exposures)
    robertson = recover_response(stack.codes, stack.exposures, method="robertson")
    images = [np.ascontiguousarray(f[..., ::-1]) for f in stack.codes]
    t32 = stack.exposures.astype(np.float32)
    cv_curve = cv2.createCalibrateDebevec().process(images, t32)[:, 0, ::-1]
    cv_hdr = cv2.createMergeDebevec().process(
        images, t32, cv2.createCalibrateDebevec().process(images, t32)
    )[..., ::-1]
    codes = np.arange(256) / 255
    truth_curve = synthetic.camera_inverse(codes)
    sel = (codes >= 0.1) & (codes <= 0.95)

    def aligned(curve):
        c = np.asarray(curve, np.float64)
        return c / np.exp(np.log(c[sel] / truth_curve[sel, None]).mean(0))

    fig = Figure(figsize=(11, 4))
    ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    ax.semilogy(codes * 255, truth_curve, "k", lw=3, alpha=0.3, label="truth")
    curves = {
        "bakeshop Debevec-Malik": aligned(debevec.table(8, 3)),
        "bakeshop Robertson": aligned(robertson.table(8, 3)),
        "OpenCV CalibrateDebevec": aligned(cv_curve),
    }
    styles = {
        "bakeshop Debevec-Malik": "C0",
        "bakeshop Robertson": "C2",
        "OpenCV CalibrateDebevec": "C3",
    }
    for name, c in curves.items():
        ax.semilogy(codes * 255, c[:, 1], styles[name], lw=1, label=name)
        err = c / truth_curve[:, None] - 1
        bx.plot(codes[1:] * 255, 100 * err[1:, 1], styles[name], lw=1, label=name)
        say(f"| {name} | {100 * np.abs(err[sel]).max():.2f} % |")
    ax.set_xlabel("8-bit code")
    ax.set_ylabel("linear exposure X (green)")
    ax.legend(fontsize=8)
    ax.set_title("Recovered inverse responses")
    bx.axhspan(-2, 2, color="0.9")
    bx.axvspan(0.10 * 255, 0.95 * 255, color="0.95")
    bx.set_ylim(-8, 8)
    bx.set_xlabel("8-bit code")
    bx.set_ylabel("error against the truth, % (green)")
    bx.set_title("Error (grey band: the 2 % bound over codes 10-95 %)")
    fig.tight_layout()
    save(fig, "photographs_response.png")

    # --- merges ----------------------------------------------------------------------------
    merged = merge_stack(stack, debevec)
    seen = merged.votes > 0
    recovered, status, found = recover_sun(merged.radiance, merged.status, "latlong")
    ours = recovered / relative_scale(merged.radiance, probe, seen)
    clipped_merge = merged.radiance / relative_scale(merged.radiance, probe, seen)
    theirs = cv_hdr / relative_scale(cv_hdr, probe, seen)
    say("")
    say("| merge | mPSNR (dB) | log2 RMSE (stops) | sun's irradiance kept |")
    say("|---|---|---|---|")
    for name, img in (
        ("bakeshop", ours),
        ("bakeshop, --sun off", clipped_merge),
        ("OpenCV", theirs),
    ):
        kept = (
            synthetic.sun_irradiance(img, sky)
            @ [0.2126, 0.7152, 0.0722]
            / (truth_irr @ [0.2126, 0.7152, 0.0722])
        )
        say(
            f"| {name} | {multi_exposure_psnr(img, probe, mask=seen):.2f} | "
            f"{log2_rmse(img, probe, mask=seen):.4f} | {100 * kept:.1f} % |"
        )
    fig = Figure(figsize=(12, 6.2))
    err_ours = np.abs(np.log2(np.maximum(ours, 1e-9) / probe)).mean(-1)
    err_theirs = np.abs(np.log2(np.maximum(theirs, 1e-9) / probe)).mean(-1)
    panels = [
        (picture(ours, -1), "bakeshop merge (tone-mapped, -1 EV)"),
        (picture(theirs, -1), "OpenCV MergeDebevec (-1 EV)"),
    ]
    for k, (img, title) in enumerate(panels):
        ax = fig.add_subplot(2, 2, k + 1)
        ax.imshow(img)
        ax.set_title(title, fontsize=10)
        ax.axis("off")
    for k, (err, title) in enumerate(((err_ours, "bakeshop"), (err_theirs, "OpenCV"))):
        ax = fig.add_subplot(2, 2, k + 3)
        shown = ax.imshow(err, cmap="magma", vmin=0, vmax=0.1)
        ax.set_title(f"|log2 error| of {title} (0 to 0.1 stop)", fontsize=10)
        ax.axis("off")
        fig.colorbar(shown, ax=ax, fraction=0.025)
    fig.tight_layout()
    save(fig, "photographs_merge.png")

    # --- confidence --------------------------------------------------------------------------
    fig = Figure(figsize=(12, 3.4))
    ax = fig.add_subplot(1, 2, 1)
    shown = ax.imshow(merged.votes, cmap="viridis", vmin=0, vmax=len(TIMES))
    ax.set_title("frames that voted (R of the confidence map)", fontsize=10)
    ax.axis("off")
    fig.colorbar(shown, ax=ax, fraction=0.025)
    d = synthetic.latlong_dirs(*probe.shape[:2]) @ synthetic.SUN_DIRECTION
    ys, xs = np.nonzero(d > math.cos(math.radians(4)))
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    bx = fig.add_subplot(1, 4, 3)
    bx.imshow(merged.status[y0:y1, x0:x1], cmap="viridis", vmin=0, vmax=3, interpolation="nearest")
    bx.set_title("status near the sun, merged:\nteal (1) = clipped in every frame", fontsize=9)
    bx.axis("off")
    cx = fig.add_subplot(1, 4, 4)
    cx.imshow(status[y0:y1, x0:x1], cmap="viridis", vmin=0, vmax=3, interpolation="nearest")
    cx.set_title(
        f"after the sun is modelled:\nyellow (3) = modelled ({found.texels} texels)", fontsize=9
    )
    cx.axis("off")
    fig.tight_layout()
    save(fig, "photographs_confidence.png")

    # --- the sun's profile -----------------------------------------------------------------
    ang = np.degrees(np.arccos(np.clip(d, -1, 1)))
    near = ang < 12
    fig = Figure(figsize=(7, 4.2))
    ax = fig.add_subplot(1, 1, 1)
    lum = {
        "truth": probe,
        "bakeshop (aureole fit, disk modelled)": ours,
        "clipped merge (--sun off)": clipped_merge,
        "OpenCV": theirs,
    }
    for (name, img), style in zip(lum.items(), ("ko", "C0.", "C1.", "C3."), strict=True):
        y = img[near] @ np.array([0.2126, 0.7152, 0.0722])
        size, alpha = (5, 0.15) if name == "truth" else (2, 0.7)
        ax.loglog(ang[near], y, style, ms=size, alpha=alpha, label=name)
    ax.axvline(found.clipped_radius_deg, color="0.5", ls="--", lw=0.8)
    ax.text(found.clipped_radius_deg * 1.05, 3, "clipped in\nevery frame", fontsize=8)
    ax.set_xlabel("degrees from the sun")
    ax.set_ylabel("luminance of each texel")
    ax.set_title(
        f"The sun kept: bakeshop fits slope {found.aureole_slope:.2f} "
        f"(chi {found.circumsolar_ratio:.3f})"
    )
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, "photographs_sun.png")

    # --- mirror ball ---------------------------------------------------------------------------
    turn = np.radians(90)
    rot = np.array(
        [[math.cos(turn), 0, math.sin(turn)], [0, 1, 0], [-math.sin(turn), 0, math.cos(turn)]]
    )
    env = synthetic.default_probe()

    def environment(dvec):
        # the default probe looked up by DESIGN's latlong formula (bilinear), in its own frame
        h, w = env.shape[:2]
        phi = np.arctan2(dvec[..., 0], -dvec[..., 2])
        theta = np.arccos(np.clip(dvec[..., 1], -1, 1))
        x = (phi / (2 * np.pi) + 0.5) * w - 0.5
        y = theta / np.pi * h - 0.5
        from scipy.ndimage import map_coordinates

        return np.stack(
            [map_coordinates(env[..., c], [y, x], order=1, mode="wrap") for c in range(3)], -1
        )

    def blocker(dvec):
        return dvec @ np.array([0, 0, 1.0]) > math.cos(math.radians(12))

    circle_a, circle_b = Circle(400.4, 300.7, 280.2), Circle(390.6, 310.3, 270.8)
    view_a = synthetic.ball_photo(600, 800, circle_a.x, circle_a.y, circle_a.radius, environment,
                                  supersample=2, background=0.2, blocker=blocker)  # fmt: skip
    view_b = synthetic.ball_photo(620, 780, circle_b.x, circle_b.y, circle_b.radius,
                                  lambda v: environment(v @ rot.T), supersample=2, background=0.2,
                                  blocker=blocker)  # fmt: skip
    yaw, plus, minus = best_yaw([view_a, view_b], [circle_a, circle_b], convention="physical")
    single = unwrap(view_a, circle_a, size=256, convention="physical")
    both, _ = merge_views([view_a, view_b], [circle_a, circle_b], yaws_deg=[0, yaw], size=256,
                          convention="physical")  # fmt: skip
    hdrshop = unwrap(view_a, circle_a, size=256)
    fig = Figure(figsize=(12, 6.6))
    panels = [
        (picture(view_a, 1), "photo A (the photographer at the ball's centre)"),
        (picture(view_b, 1), f"photo B, 90 deg around (found: {yaw:+.0f} deg)"),
        (picture(single, 1), "A unwrapped, physical convention"),
        (picture(both, 1), "A and B merged: photographer and rim gone"),
        (picture(hdrshop, 1), "A unwrapped, HDRShop's convention (default)"),
        (picture(env[::2, ::2], 1), "the probe the ball reflects"),
    ]
    for k, (img, title) in enumerate(panels):
        ax = fig.add_subplot(2, 3, k + 1)
        ax.imshow(img)
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    save(fig, "photographs_unwrap.png")


if __name__ == "__main__":
    main()
