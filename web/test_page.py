#!/usr/bin/env python3
"""The browser test of the web page: headless Chromium, driven through chromedriver's
HTTP API (WebDriver) with the standard library only.

    python3 web/test_page.py [--site out/site] [--native BIN] [--screenshot screenshots/web.png]

Serves the site (`scripts/build_site.sh`) on 127.0.0.1, loads `?scene=pull_off&run=1`, waits for
the page's `#status` to read `finished`, reads its `#result` (the run's summary JSON) and checks
it against the native build's `decohesion run scenes/pull_off.toml --summary … --threads 1`,
twice:

- against the native portable kernels (`DECOHESION_ISA=portable`: no fused multiply-add), bit
  for bit: the page's wasm32 build runs the same kernels, vectorised with WebAssembly SIMD
  (simd128, f64x2), which has no FMA either (.cargo/config.toml), so the same IEEE operations
  in the same order: the same scene, mesh and interface, every glued node ruptured, the state
  counts, steps, time of full rupture, peak reaction and energies equal (for a scene whose
  material takes no logarithm, as the pull-off's SVK: a neo-Hookean's `ln` is glibc's natively
  and Rust's libm in wasm32, which may differ in the last bit; the tread's results differ so by
  1e-12 at most, with or without SIMD in the page);
- against the native default build, within round-off (relative 1e-9; see `TOLERANCE`): its
  element kernels use AVX2/AVX-512 with fused multiply-adds when the CPU has them
  (physics/src/kernels/simd.rs), so F_int differs in the last bits at each step and the
  difference grows with the run. The differences measured are printed.

Then the links (`--links`, on by default): `?scene=pull_off&set=…&set=…&run=1` against
`decohesion run scenes/pull_off.toml --set … --set …`, and a lesson step opened by its link,
`?lesson=cohesive_law&step=4&run=1&hide=history,view&projector=1` (as a class would open it),
against the native run of its scene with the overrides of the lesson's steps 1 to 4 (read from
`lessons/cohesive_law.md`), with the same checks; the same step embedded as a course page would
(`&embed=1`, in an 800×500 window: the embeddable view), with the same checks, the page's
link to the book gone, and the 3-D view at least 40 % of the frame's width and half its height
(the page's `#layout`); and `embed=yes`, which the page must refuse with a message naming it.

Before the browser, the module itself (`check_kernel_sizes`): no function of the physics'
element kernels (`decohesion_physics::kernels::`) is larger than `KERNEL_BODY_LIMIT` bytes of
WebAssembly, so that a first load of the page does not run its step in V8's baseline code while
the optimising compiler works through a kernel for every law (docs: performance log, "Where the
page's step goes").

Saves a screenshot of the page at the end of each run. Exit status 0 when every check passes.
"""

import argparse
import tomllib
import urllib.parse
import base64
import functools
import http.server
import json
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

# Relative difference admitted between the page and the native run (round-off, see above): the
# measured differences on the 7³ pull-off are printed by every run of this test.
TOLERANCE = 1e-9

CHROME_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    # WebGL2 without a GPU: ANGLE on SwiftShader (software), which Chromium refuses for WebGL
    # unless told it may.
    "--use-gl=angle",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--window-size=1500,950",
]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve(directory):
    """A static server of `directory` on 127.0.0.1 (a thread); returns its port."""
    handler = functools.partial(QuietHandler, directory=directory)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server.server_address[1]


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".wasm": "application/wasm", ".js": "text/javascript"}

    def log_message(self, *args):
        pass


class WebDriver:
    """The few WebDriver commands the test needs, over chromedriver's HTTP API."""

    def __init__(self, port):
        self.base = f"http://127.0.0.1:{port}"
        self.session = None

    def call(self, method, path, body=None, timeout=60):
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return json.load(r)["value"]
        except urllib.error.HTTPError as e:
            raise RuntimeError(f"{method} {path}: {e.code} {e.read().decode()[:2000]}") from None

    def start(self, binary, profile):
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": binary,
                                   "args": CHROME_FLAGS + [f"--user-data-dir={profile}"]},
            "goog:loggingPrefs": {"browser": "ALL"},
        }}}
        self.session = self.call("POST", "/session", caps, timeout=120)["sessionId"]

    def s(self, path):
        return f"/session/{self.session}{path}"

    def get(self, url):
        self.call("POST", self.s("/url"), {"url": url})

    def script(self, js):
        return self.call("POST", self.s("/execute/sync"), {"script": js, "args": []})

    def window(self, width, height):
        self.call("POST", self.s("/window/rect"), {"width": width, "height": height})

    def screenshot(self, path):
        png = base64.b64decode(self.call("GET", self.s("/screenshot")))
        os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        with open(path, "wb") as f:
            f.write(png)

    def console(self):
        try:
            return self.call("POST", self.s("/se/log"), {"type": "browser"})
        except RuntimeError:
            return []

    def quit(self):
        if self.session:
            try:
                self.call("DELETE", self.s(""))
            except (RuntimeError, OSError):
                pass


def wait_for(what, condition, timeout):
    start = time.monotonic()
    while time.monotonic() - start < timeout:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    raise TimeoutError(f"{what} did not happen within {timeout} s")


def native_summary(binary, scene, sets=(), isa=None):
    """`decohesion run scene --summary … --threads 1` with the overrides `sets`; `isa` sets
    `DECOHESION_ISA` (the kernels' build), else the environment's choice."""
    env = dict(os.environ)
    if isa is not None:
        env["DECOHESION_ISA"] = isa
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "summary.json")
        overrides = [a for s in sets for a in ("--set", s)]
        subprocess.run([binary, "run", scene, "--summary", out, "--threads", "1", "--quiet",
                        *overrides], check=True, stdout=subprocess.DEVNULL, env=env)
        with open(out) as f:
            return json.load(f)


def compare(page, native, tolerance=TOLERANCE):
    """The checks, the quantities within relative `tolerance` (0: equal); returns the failures
    (empty when the page agrees with the native run)."""
    failures = []
    for key in ["scene", "nodes", "elements", "interface_nodes", "status"]:
        if page[key] != native[key]:
            failures.append(f"{key}: page {page[key]!r}, native {native[key]!r}")
    if page["final_counts"] != native["final_counts"]:
        failures.append(f"final counts: page {page['final_counts']}, native {native['final_counts']}")
    if page["final_counts"]["ruptured"] != page["interface_nodes"]:
        failures.append(f"not every glued node ruptured: {page['final_counts']}")
    quantities = {
        "steps": lambda s: s["steps"],
        "time of full rupture [s]": lambda s: s["time_full_rupture"],
        "peak reaction [N]": lambda s: s["peak_reactions"][0]["force"],
        "damage dissipated [J]": lambda s: s["energies"]["damage_dissipated"],
        "friction dissipated [J]": lambda s: s["energies"]["friction_dissipated"],
        "external work [J]": lambda s: s["energies"]["external_work"],
    }
    for name, get in quantities.items():
        a, b = get(page), get(native)
        rel = abs(a - b) / max(abs(b), 1e-300)
        print(f"  {name:28} page {a!r:>24}  native {b!r:>24}  relative difference {rel:.2e}")
        if tolerance == 0 and a != b:
            failures.append(f"{name}: page {a!r}, native {b!r}: not bit for bit")
        elif name != "friction dissipated [J]" and not rel <= tolerance:
            failures.append(f"{name}: page {a}, native {b} (relative {rel:.2e} > {tolerance})")
    return failures


def lesson_sets(path, step):
    """The overrides in force at step `step` (1-based) of a lesson file: every `set` of the
    `step` blocks of its steps 1 to `step`, in order."""
    with open(path) as f:
        text = f.read()
    sets = []
    for section in text.split("\n## ")[1:step + 1]:
        if "```step\n" in section:
            block = section.split("```step\n", 1)[1].split("\n```", 1)[0]
            sets += tomllib.loads(block).get("set", [])
    return sets


def run_page(wd, url, timeout, screenshot):
    """Loads `url`, waits for the run's end and returns the page's summary (exits on failure)."""
    loaded = time.monotonic()
    wd.get(url)
    status = wait_for(
        "the run's end",
        lambda: (lambda s: s if s not in ("loading", "ready", "running") else None)(
            wd.script("return document.getElementById('status').textContent")),
        timeout)
    print(f"test_page: {url}: {status} {time.monotonic() - loaded:.1f} s after loading")
    if status != "finished":
        for entry in wd.console():
            print("  console:", entry.get("message", entry))
        sys.exit(f"test_page: the page says `{status}`")
    page = json.loads(wd.script("return document.getElementById('result').textContent"))
    time.sleep(1.0)  # the plots settle over a few frames after a run
    wd.screenshot(screenshot)
    print(f"test_page: screenshot {screenshot}")
    return page


# The largest body (bytes of WebAssembly) admitted for a function of the element kernels. V8's
# optimising compiler took 1.3–1.6 ms per KB of body on the 2-core test machine in a page's
# first run (257 KB of the chunk loop 402 ms, 51 KB of a lane kernel holding every law 67 ms:
# performance log, 2026-11-29), on background threads that share the cores with the run, which
# goes on in the baseline code meanwhile. 48 KB (≈ 70 ms, the order of the 7³ pull-off's whole
# step) admits one law's kernel and refuses the functions that inlined every law's.
KERNEL_BODY_LIMIT = 48 * 1024


def _leb128(b, i):
    """The unsigned LEB128 number at `b[i:]` and the index after it."""
    value = shift = 0
    while True:
        byte = b[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return value, i


def function_sizes(path):
    """{name: body bytes} of the functions a WebAssembly module defines (names from its `name`
    section; `#index` for a function without one)."""
    with open(path, "rb") as f:
        b = f.read()
    i, imported, bodies, names = 8, 0, [], {}
    while i < len(b):
        section = b[i]
        size, i = _leb128(b, i + 1)
        end = i + size
        if section == 2:  # imports: functions defined come after the imported ones
            n, j = _leb128(b, i)
            for _ in range(n):
                for _ in range(2):  # module and field names
                    length, j = _leb128(b, j)
                    j += length
                kind = b[j]
                j += 1
                if kind == 0:  # function: its type index
                    imported += 1
                    _, j = _leb128(b, j)
                elif kind in (1, 2):  # table (its element type first) or memory: limits
                    j += kind == 1
                    flags, j = _leb128(b, j)
                    _, j = _leb128(b, j)
                    if flags & 1:
                        _, j = _leb128(b, j)
                elif kind == 3:  # global: value type, mutability
                    j += 2
                elif kind == 4:  # tag: attribute, type index
                    _, j = _leb128(b, j + 1)
        elif section == 10:  # code: one size-prefixed body per defined function
            n, j = _leb128(b, i)
            for _ in range(n):
                length, j = _leb128(b, j)
                bodies.append(length)
                j += length
        elif section == 0:  # custom: the `name` section's function names (subsection 1)
            length, j = _leb128(b, i)
            if b[j:j + length] == b"name":
                j += length
                while j < end:
                    sub, (length, j) = b[j], _leb128(b, j + 1)
                    if sub == 1:
                        n, k = _leb128(b, j)
                        for _ in range(n):
                            index, k = _leb128(b, k)
                            size_name, k = _leb128(b, k)
                            names[index] = b[k:k + size_name].decode("utf-8", "replace")
                            k += size_name
                    j += length
        i = end
    return {names.get(imported + k, f"#{imported + k}"): n for k, n in enumerate(bodies)}


def check_kernel_sizes(wasm):
    """Exits naming the element kernels' functions over `KERNEL_BODY_LIMIT`; prints the largest."""
    sizes = {name: n for name, n in function_sizes(wasm).items()
             if name.startswith("decohesion_physics::kernels::")}
    if not sizes:
        sys.exit(f"test_page: {wasm}: no function named decohesion_physics::kernels::… "
                 "(the module must keep its name section)")
    largest = max(sizes, key=sizes.get)
    print(f"test_page: {len(sizes)} kernel functions in {wasm}, the largest "
          f"{sizes[largest]} bytes ({largest}; at most {KERNEL_BODY_LIMIT})")
    over = [f"{name}: {n} bytes" for name, n in sorted(sizes.items(), key=lambda x: -x[1])
            if n > KERNEL_BODY_LIMIT]
    if over:
        sys.exit(f"test_page: {wasm}: kernel functions over {KERNEL_BODY_LIMIT} bytes, which "
                 "a first load runs in baseline code while V8 optimises them:\n  "
                 + "\n  ".join(over))


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    target = os.environ.get("CARGO_TARGET_DIR", os.path.expanduser("~/.cache/decohesion-target"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--site", default=os.path.join(root, "out/site"))
    ap.add_argument("--native", default=os.path.join(target, "release/decohesion"))
    ap.add_argument("--screenshot", default=os.path.join(root, "screenshots/web.png"))
    ap.add_argument("--chromium", default="/usr/bin/chromium")
    ap.add_argument("--chromedriver", default="/usr/bin/chromedriver")
    ap.add_argument("--scene", default="pull_off")
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--links", action=argparse.BooleanOptionalAction, default=True,
                    help="also open a `set=` link and a lesson's link and compare them")
    args = ap.parse_args()
    for path in [os.path.join(args.site, "index.html"), args.native, args.chromium,
                 args.chromedriver]:
        if not os.path.exists(path):
            sys.exit(f"test_page: {path} is missing (scripts/build_site.sh builds the site; "
                     "apt-get install chromium chromium-driver gives the browser)")

    def scene_file(name):
        return os.path.join(root, f"scenes/{name}.toml")

    def natives(scene, sets=()):
        """The native summaries: (default build, portable build or None if the scene's
        material takes a logarithm: no bit-for-bit check then)."""
        with open(scene_file(scene), "rb") as f:
            svk = tomllib.load(f).get("material", {}).get("model") == "svk"
        portable = native_summary(args.native, scene_file(scene), sets, isa="portable")
        return native_summary(args.native, scene_file(scene), sets), portable if svk else None

    check_kernel_sizes(os.path.join(args.site, "decohesion_bg.wasm"))
    native, portable = natives(args.scene)
    site_port = serve(args.site)
    driver_port = free_port()
    chromedriver = subprocess.Popen([args.chromedriver, f"--port={driver_port}"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wd = WebDriver(driver_port)
    try:
        wait_for("chromedriver", lambda: _ready(wd), 30)
        with tempfile.TemporaryDirectory() as profile:
            wd.start(args.chromium, profile)
            url = f"http://127.0.0.1:{site_port}/?scene={args.scene}&run=1"
            page = run_page(wd, url, args.timeout, args.screenshot)
            linked = []
            if args.links:
                shot = os.path.splitext(args.screenshot)[0]
                sets = ["mesh.cells=[3,3,3]", "interface.law.u_r=0.005"]
                query = urllib.parse.urlencode(
                    [("scene", "pull_off")] + [("set", s) for s in sets] + [("run", "1")])
                url = f"http://127.0.0.1:{site_port}/?{query}"
                linked.append((url, run_page(wd, url, args.timeout, f"{shot}_set.png"),
                               natives("pull_off", sets)))
                sets = lesson_sets(os.path.join(root, "lessons/cohesive_law.md"), 4)
                # As a class would open it: the history and the 3-D view hidden, projector mode.
                url = (f"http://127.0.0.1:{site_port}/?lesson=cohesive_law&step=4&run=1"
                       "&hide=history,view&projector=1")
                linked.append((url, run_page(wd, url, args.timeout, f"{shot}_lesson.png"),
                               natives("pull_off", sets)))
                # Embedded in a course page's <iframe> of 800×500: the embeddable view.
                wd.window(800, 500)
                url = (f"http://127.0.0.1:{site_port}/?lesson=cohesive_law&step=4&run=1"
                       "&embed=1")
                linked.append((url, run_page(wd, url, args.timeout, f"{shot}_embed.png"),
                               natives("pull_off", sets)))
                if wd.script("return document.getElementById('book') !== null"):
                    sys.exit(f"test_page: {url}: the embedded page still links to the book")
                check_embedded_layout(wd, url)
                url = f"http://127.0.0.1:{site_port}/?scene=pull_off&embed=yes"
                wd.get(url)
                status = wait_for("the refusal", lambda: (lambda s: s if s != "loading" else None)(
                    wd.script("return document.getElementById('status').textContent")), 60)
                print(f"test_page: {url}: {status}")
                if not (status.startswith("failed:") and "embed=yes" in status):
                    sys.exit(f"test_page: {url}: not refused with a message naming embed=yes")
            wd.quit()
    finally:
        chromedriver.terminate()
        chromedriver.wait(10)

    print(f"test_page: {args.scene}, {page['elements']} hex8, one thread each:")
    print(f"  wall time (set-up and run)   page {page['wall_seconds']:.3f} s, "
          f"native {native['wall_seconds']:.3f} s")
    print(f"  time inside step()           page {page['step_wall_seconds']:.3f} s, "
          f"native {native['step_wall_seconds']:.3f} s "
          f"({page['ns_per_element_step']:.0f} vs {native['ns_per_element_step']:.0f} "
          f"ns per element-step)")
    failures = []
    for url, p, (n, n_portable) in [("the page", page, (native, portable))] + linked:
        if n_portable is not None:
            print(f"test_page: {url} against the native portable build (bit for bit):")
            failures += [f"{url}, portable: {f}" for f in compare(p, n_portable, tolerance=0)]
        print(f"test_page: {url} against the native default build (round-off):")
        failures += [f"{url}: {f}" for f in compare(p, n)]
    if failures:
        print("test_page: FAILED\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("test_page: the page's results equal the native portable build's bit for bit (SVK "
          "scenes) and the default build's within round-off")


def check_embedded_layout(wd, url):
    """The embeddable view keeps a usable 3-D view in the small frame: its panel within the
    frame, the picture within its panel and at least 40 % of the frame's width and half its
    height (`#layout`, written by the page: rectangles [x, y, width, height] in points). A first
    version moved the panel past the frame's right edge, a 50-point strip of it showing, while
    the picture kept the panel's width: hence the panel's rectangle."""
    layout = json.loads(wd.script("return document.getElementById('layout').textContent"))
    page, panel, view = layout["page"], layout["view3d_panel"], layout["view3d"]
    print(f"test_page: {url}: the page {page}, the 3-D view's panel {panel}, its picture {view} "
          "([x, y, width, height] in points)")
    if panel is None or view is None:
        sys.exit(f"test_page: {url}: the embedded page draws no 3-D view")

    def within(inner, outer):
        return (inner[0] >= outer[0] - 0.5 and inner[1] >= outer[1] - 0.5
                and inner[0] + inner[2] <= outer[0] + outer[2] + 0.5
                and inner[1] + inner[3] <= outer[1] + outer[3] + 0.5)

    if not within(panel, page):
        sys.exit(f"test_page: {url}: the 3-D view's panel {panel} leaves the frame {page}")
    if not within(view, panel):
        sys.exit(f"test_page: {url}: the 3-D view {view} leaves its panel {panel}")
    if view[2] < 0.4 * page[2] or view[3] < 0.5 * page[3]:
        sys.exit(f"test_page: {url}: the 3-D view is {view[2]:.0f} × {view[3]:.0f} points in a "
                 f"{page[2]:.0f} × {page[3]:.0f} frame (at least 40 % of its width and half "
                 "its height asked)")


def _ready(wd):
    try:
        return wd.call("GET", "/status", timeout=2).get("ready")
    except OSError:
        return False


if __name__ == "__main__":
    main()
