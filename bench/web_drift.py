#!/usr/bin/env python3
"""The energy drift the browser page shows (docs/web.md, "In a lesson"):
3 000 disks at packing 0.6, 10 steps a frame for 60 frames, in each scheme;
prints the steps, the collisions and the total energy's relative change
(caromPage.driftRelative). The page steps the native CPU engine's bits, so
these are the engine's figures too.
  usage: .venv/bin/python bench/web_drift.py [BUILD] [--query "n=3000&packing=0.6&speed=10"] [--frames 60]"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "web"))
from browser import REPOSITORY, Page, build_site, open_chromium, serve  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", nargs="?", default=str(REPOSITORY / "build" / "web"))
    parser.add_argument("--query", default="n=3000&packing=0.6&speed=10")
    parser.add_argument("--frames", type=int, default=60)
    args = parser.parse_args()
    site = build_site(args.build)
    browser = open_chromium()
    try:
        with serve(site) as url:
            for scheme in ("pairwise", "events", "simultaneous"):
                page = Page(browser, f"{url}?{args.query}&scheme={scheme}")
                page.js("caromPage.pause()")
                start = page.js("caromPage.sim.observables().steps")
                page.js(f"caromPage.frames({args.frames})")
                o = page.js("caromPage.sim.observables()")
                print(f"{scheme}: {o['steps'] - start:.0f} steps ({o['steps']:.0f} since the start), "
                      f"{o['collisions']:.0f} collisions, drift {page.js('caromPage.driftRelative()'):+.2e}")
    finally:
        browser.quit()


if __name__ == "__main__":
    main()
