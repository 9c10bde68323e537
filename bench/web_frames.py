#!/usr/bin/env python3
"""Frame times of the browser page in headless Chromium against the number of
disks: for each scheme and size, RUNS runs of FRAMES frames (one step each)
after 5 warm-up frames, each run's median stepping and drawing time a frame
(drawing waits for a pixel read back: software WebGL draws on the CPU
here), then the frame rate of the page running on its own for LIVE seconds
(compositing and the plots included). Also the page's load time (navigation until the first scene runs) and the sizes
of carom.wasm and carom.js. Builds the page into BUILD first.
  usage: .venv/bin/python bench/web_frames.py [BUILD] [--sizes 1000 10000 100000] [--runs 3] [--frames 30] [--live 5]"""
import argparse
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "web"))
from browser import REPOSITORY, Page, build_site, open_chromium, serve  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", nargs="?", default=str(REPOSITORY / "build" / "web"))
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--schemes", nargs="+", default=["pairwise", "events"])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--packing", type=float, default=0.5)
    parser.add_argument("--live", type=float, default=5.0, help="seconds the page runs before its frame rate is read")
    args = parser.parse_args()
    site = build_site(args.build)
    for name in ("carom.wasm", "carom.js"):
        print(f"{name}: {(site / name).stat().st_size} bytes")
    browser = open_chromium()
    try:
        with serve(site) as url:
            for scheme in args.schemes:
                for n in args.sizes:
                    for run in range(1, args.runs + 1):
                        start = time.perf_counter()
                        page = Page(browser, f"{url}?n={n}&packing={args.packing}&scheme={scheme}")
                        loaded = time.perf_counter() - start
                        page.js("caromPage.pause()")
                        page.js("caromPage.frames(5)")
                        frames = page.js(f"caromPage.frames({args.frames})")
                        # The page as a user sees it: running, composited, its plots refreshed.
                        page.js("caromPage.play()")
                        time.sleep(args.live)
                        fps = page.js("caromPage.timing().fps")
                        print(f"{scheme} N={n} run{run}: stepping {frames['stepMs']:.2f} ms, drawing "
                              f"{frames['drawMs']:.2f} ms a frame (medians of {args.frames} frames in a row); "
                              f"running: {fps:.1f} frames a second; page ready in {loaded:.2f} s")
    finally:
        browser.quit()


if __name__ == "__main__":
    main()
