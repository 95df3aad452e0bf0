"""The browser viewer's frame time: ``bakeshop view`` of a bake in Debian's Chromium, headless,
WebGL2 on SwiftShader (no GPU), at 1280x720; each frame read back one pixel, so the time is the
GPU process's drawing, not the JavaScript call.

Playwright drives the system's Chromium (no browser download): ``pip install playwright``.

Run: ``make demo && .venv/bin/python benchmarks/bench_view.py [BAKE_DIR]``.
"""

from __future__ import annotations

import os
import shutil
import sys
import time

from bakeshop.preview import read_bake
from bakeshop.preview.server import serve

FRAMES = 3
ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox"]


def main(folder: str = "demo") -> None:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        sys.exit("bench_view: no Chromium (Debian: apt-get install chromium)")
    print(f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}; {chromium}")
    viewer = serve(read_bake(folder))
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 720})
            print(f"browser: {browser.version}")
            for scene in ("sky", "balls", "golf"):
                url = f"{viewer.url}?scene={scene}&width=1280&height=720&ui=0&frames={FRAMES}"
                started = time.perf_counter()
                page.goto(url, timeout=600_000)
                page.wait_for_function("document.body.dataset.frameMs", timeout=600_000)
                total = time.perf_counter() - started
                ms = float(page.evaluate("document.body.dataset.frameMs"))
                print(f"{scene:6s} 1280x720  page to {FRAMES + 1} frames {total:6.1f} s   "
                      f"frame {ms:8.1f} ms (mean of {FRAMES})")  # fmt: skip
            browser.close()
    finally:
        viewer.close()


if __name__ == "__main__":
    main(*sys.argv[1:])
