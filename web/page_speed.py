#!/usr/bin/env python3
"""Times a scene in the web page against the native build, one thread each (no checks: the
browser test is `web/test_page.py`; this one only measures, for the performance log).

    python3 web/page_speed.py --site out/site [--site out/other] --native BIN \
        [--scene pull_off] [--runs 5]

Each round loads `?scene=NAME&run=1` afresh in headless Chromium (the flags and window size of
the browser test: software WebGL) from every site given, in turn, and runs
`decohesion run scenes/NAME.toml --summary … --threads 1` natively, so that the builds compared
share the machine's load. Per run it prints the summary's wall time (set-up and run), the time
inside `step()`, ns per element-step, and the page's slices of steps (its console line:
pictures drawn ≈ slices); then the medians and ranges, the median per stage of the step
(`stage_seconds`), and the medians of the per-round ratios of ns per element-step: each site
against the first site and against native. `DECOHESION_ISA` in the environment picks the native
kernels (e.g. `portable`: no FMA, as in the page).

All rounds share one browser profile unless `--cold`: then every page load gets a fresh profile,
as a student's first visit does. The difference matters: a profile that has run the page before
holds the engine's optimised code of the module (V8's code cache), a first load runs the step in
the engine's baseline code until its optimising compiler has compiled the hot functions, on
background threads that share the cores with the run (docs: performance log).
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_page  # noqa: E402


def page_run(wd, url, timeout):
    wd.get(url)
    test_page.wait_for(
        "the run's end",
        lambda: wd.script("return document.getElementById('status').textContent")
        not in ("loading", "ready", "running"),
        timeout)
    status = wd.script("return document.getElementById('status').textContent")
    if status != "finished":
        sys.exit(f"page_speed: {url}: {status}")
    s = json.loads(wd.script("return document.getElementById('result').textContent"))
    slices = None
    for entry in wd.console():
        m = re.search(r"(\d+) steps in (\d+) frames", entry.get("message", ""))
        if m:
            slices = int(m.group(2))
    return s, slices


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--site", action="append", required=True)
    ap.add_argument("--native", required=True)
    ap.add_argument("--scene", default="pull_off")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=300.0)
    ap.add_argument("--cold", action="store_true",
                    help="a fresh browser profile for every page load (a first visit)")
    ap.add_argument("--chromium", default="/usr/bin/chromium")
    ap.add_argument("--chromedriver", default="/usr/bin/chromedriver")
    args = ap.parse_args()
    scene = os.path.join(root, f"scenes/{args.scene}.toml")
    ports = [test_page.serve(site) for site in args.site]
    driver_port = test_page.free_port()
    chromedriver = subprocess.Popen([args.chromedriver, f"--port={driver_port}"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    results = {site: [] for site in args.site}
    results["native"] = []
    wd = test_page.WebDriver(driver_port)
    try:
        test_page.wait_for("chromedriver", lambda: test_page._ready(wd), 30)
        with tempfile.TemporaryDirectory() as profile:
            if not args.cold:
                wd.start(args.chromium, profile)
            for r in range(args.runs):
                for site, port in zip(args.site, ports):
                    url = f"http://127.0.0.1:{port}/?scene={args.scene}&run=1"
                    if args.cold:
                        with tempfile.TemporaryDirectory() as fresh:
                            wd.start(args.chromium, fresh)
                            s, slices = page_run(wd, url, args.timeout)
                            wd.quit()
                    else:
                        s, slices = page_run(wd, url, args.timeout)
                    results[site].append((s, slices))
                    print(f"round {r + 1} {site}: wall {s['wall_seconds']:.3f} s, step "
                          f"{s['step_wall_seconds']:.3f} s, {s['ns_per_element_step']:.0f} ns/el-step, "
                          f"{s['steps']} steps, {slices} slices", flush=True)
                n = test_page.native_summary(args.native, scene)
                results["native"].append((n, None))
                print(f"round {r + 1} native: wall {n['wall_seconds']:.3f} s, step "
                      f"{n['step_wall_seconds']:.3f} s, {n['ns_per_element_step']:.0f} ns/el-step",
                      flush=True)
                time.sleep(0.5)
            if not args.cold:
                wd.quit()
    finally:
        chromedriver.terminate()
        chromedriver.wait(10)
    print(f"page_speed: {args.scene}, {args.runs} rounds, medians (ranges):")
    for name, runs in results.items():
        cols = []
        for key in ["wall_seconds", "step_wall_seconds", "ns_per_element_step"]:
            v = [s[key] for s, _ in runs]
            cols.append(f"{key} {statistics.median(v):.4g} ({min(v):.4g}–{max(v):.4g})")
        slices = [n for _, n in runs if n is not None]
        if slices:
            cols.append(f"slices {statistics.median(slices):g}")
        print(f"  {name}: " + ", ".join(cols))
    print("median seconds per stage of the step:")
    for name, runs in results.items():
        stages = runs[0][0]["stage_seconds"]
        print(f"  {name}: " + ", ".join(
            f"{k} {statistics.median(s['stage_seconds'][k] for s, _ in runs):.4f}" for k in stages))
    print("medians of the per-round ratios of ns per element-step (range):")
    ns = {name: [s["ns_per_element_step"] for s, _ in runs] for name, runs in results.items()}
    for name in args.site:
        for base in [args.site[0], "native"]:
            if base == name:
                continue
            r = [b / a if base != "native" else a / b for a, b in zip(ns[name], ns[base])]
            what = "faster than" if base != "native" else "times the time of"
            print(f"  {name} {what} {base}: {statistics.median(r):.2f}× ({min(r):.2f}–{max(r):.2f})")


if __name__ == "__main__":
    main()
