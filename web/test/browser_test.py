#!/usr/bin/env python3
"""The viewer in a real browser: headless Chromium (SwiftShader WebGL2) opens the page with
?selftest=1 from a server on 127.0.0.1 that this test starts and stops itself; the page's JSON
(the one it writes into <pre id="selftest">, posted back to the server) is checked against the
native cw4d command line:

  * f-vector and volume of every section of a fixed list of models, placements and planes
    (built-ins, dropped 4OFF files, G4MF files passed as bytes, a degenerate plane) equal those
    `cw4d slice` prints of the same model or file;
  * a sweep's layers equal the native slices at the same offsets;
  * the GPU tetrahedral path covers the same pixels as the CPU path (IoU >= 0.97), both with
    the tetrahedra the WebAssembly core makes and with the GPU buffers (.json + .bin) of the
    native `cw4d tetrahedralize`, which this test writes and serves; the core's tetrahedra
    (cw4d_tetra in WebAssembly) are those buffers' tetrahedra, entry by entry;
  * the catalogue lists every family of `cw4d list`, the CGAL ones marked unavailable;
  * bad input gives one-line errors; a bad G4MF file the same message as `cw4d info` gives for
    the same bytes, and the model loaded before stays loaded;
  * the one-file page of `cw4d view`, opened from disk (file://, --dump-dom), shows the section
    `cw4d slice` makes of the same placed model (a built-in and a .g4b file), and bad
    `cw4d view` requests exit 1 with one error line and no file.

The G4MF files are made here: `cw4d convert` of two Miratope files (.g4tf and .g4b), two
samples of tests/data/g4mf written without cw4d (--g4mf-samples), and bad files cut from them.

It also prints the slice time of the WebAssembly core beside the native `cw4d bench` figure
for the same models (reported, not asserted: speed is measured, never a test condition).

usage: browser_test.py --site build-web/web/site --cw4d build/apps/cw4d
                       --samples tests/data/miratope [--g4mf-samples tests/data/g4mf]
                       [--report out.json]
"""
import argparse
import http.server
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time


FAILURES = []


def fail(message, fatal=True):
    print(f"browser_test: FAIL: {message}", file=sys.stderr)
    FAILURES.append(message)
    if fatal:
        sys.exit(1)


class Server(http.server.ThreadingHTTPServer):
    daemon_threads = True

    def __init__(self, site, generated):
        self.site = site
        self.generated = generated
        self.result = None
        self.done = threading.Event()
        super().__init__(("127.0.0.1", 0), Handler)


class Handler(http.server.SimpleHTTPRequestHandler):
    def __init__(self, request, client_address, server):
        super().__init__(request, client_address, server, directory=server.site)

    def translate_path(self, path):
        # /generated/...: the files this test made (the native GPU buffers).
        clean = path.split("?")[0].split("#")[0]
        if clean.startswith("/generated/"):
            name = os.path.basename(clean)
            return os.path.join(self.server.generated, name)
        return super().translate_path(path)

    def do_POST(self):
        if self.path.split("?")[0] != "/selftest-result":
            self.send_error(404)
            return
        length = int(self.headers.get("Content-Length", "0"))
        self.server.result = self.rfile.read(length).decode("utf-8")
        self.send_response(204)
        self.end_headers()
        self.server.done.set()

    def log_message(self, *args):
        pass


def chromium_command(chromium, profile, url):
    return [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
            "--no-first-run", "--disable-background-networking", "--disable-component-update",
            "--disable-sync", "--disable-extensions", "--mute-audio",
            f"--user-data-dir={profile}", "--use-gl=angle", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--window-size=1200,800", url]


# The native GPU buffers the page's BUFFER_CASES read (web/js/selftest.js).
BUFFER_MODELS = {"120-cell": "120-cell", "tesseract": "tesseract", "tiger": "tiger:2,2,0.6,12"}
# Those whose UVW must match the core's exactly (coordinates without libm functions).
UVW_EXACT = {"120-cell", "tesseract"}


def uvw_note(same):
    differ = same.get("uvwMirrored", 0) + same.get("uvwOther", 0)
    return f", {differ} UVW components differ ({same.get('uvwMirrored', 0)} mirrored)" \
        if differ else ""


# The G4MF files the page's G4MF_CASES and G4MF_BAD read (web/js/selftest.js): the native
# `cw4d convert` of Miratope files, samples of tests/data/g4mf, and bad files cut from them.
G4MF_CONVERTED = {"icositetrachoron.g4tf": "regular/Icositetrachoron.off",
                  "cantellated-icositetrachoron.g4b":
                      "convex uniform/Cantellated icositetrachoron.off"}
G4MF_SAMPLES = ["tesseract-two-surfaces.g4b", "pentachoron-tetra.g4tf",
                "tesseract-external.g4tf"]  # the last without its .bin: refused by the page


def make_g4mf_files(args, generated):
    for name, source in G4MF_CONVERTED.items():
        out = os.path.join(generated, name)
        run = subprocess.run([args.cw4d, "convert", os.path.join(args.samples, source), "-o", out],
                             capture_output=True, text=True)
        if run.returncode != 0 or not os.path.isfile(out):
            fail(f"cw4d convert {source} -o {name} exited {run.returncode}: {run.stderr.strip()}")
    for name in G4MF_SAMPLES:
        shutil.copy(os.path.join(args.g4mf_samples, name), os.path.join(generated, name))
    with open(os.path.join(generated, "icositetrachoron.g4tf"), "rb") as f:
        text = f.read()
    with open(os.path.join(generated, "cantellated-icositetrachoron.g4b"), "rb") as f:
        binary = f.read()
    if binary[:4] != b"G4MF" or b"\0" not in binary:
        fail("cw4d convert wrote a .g4b without the G4MF magic or without zero bytes")
    with open(os.path.join(generated, "bad-json.g4tf"), "wb") as f:
        f.write(text[:len(text) // 2])  # the JSON stops in the middle
    with open(os.path.join(generated, "truncated.g4b"), "wb") as f:
        f.write(binary[:len(binary) // 2])  # the header announces more bytes than there are


def run_page(args, generated):
    for name, spec in BUFFER_MODELS.items():
        out = os.path.join(generated, name + ".bin")
        run = subprocess.run([args.cw4d, "tetrahedralize", spec, "-o", out], capture_output=True,
                             text=True)
        if run.returncode != 0:
            fail(f"cw4d tetrahedralize {spec} exited {run.returncode}: {run.stderr.strip()}")
    make_g4mf_files(args, generated)
    server = Server(os.path.abspath(args.site), generated)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    profile = tempfile.mkdtemp(prefix="cw4d-chromium-")
    port = server.server_address[1]
    url = f"http://127.0.0.1:{port}/index.html?selftest=1&report=1&buffers=generated"
    browser = subprocess.Popen(chromium_command(args.chromium, profile, url),
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               start_new_session=True)
    try:
        if not server.done.wait(args.timeout):
            fail(f"the page posted no result within {args.timeout} s")
    finally:
        try:
            os.killpg(browser.pid, signal.SIGTERM)
            browser.wait(20)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            os.killpg(browser.pid, signal.SIGKILL)
            browser.wait()
        server.shutdown()
        server.server_close()
        shutil.rmtree(profile, ignore_errors=True)
    return json.loads(server.result)


COUNT = re.compile(r"(\d+) (vertex|vertices|edges?|faces?|cells?|rank-\d+ elements?)")


def native_slice(args, tmp, case, offset, generated=None):
    model = case["spec"]
    if case.get("g4mf"):
        model = os.path.join(generated, case["g4mf"])
    elif case.get("file"):
        name = os.path.basename(case["file"])
        found = [os.path.join(d, name) for d, _, files in os.walk(args.samples) if name in files]
        if len(found) != 1:
            fail(f"{name}: expected one copy under {args.samples}, found {found}")
        model = found[0]
    cmd = [args.cw4d, "slice", model, "--normal", ",".join(repr(float(x)) for x in case["normal"]),
           "--offset", repr(float(offset)), "-o", os.path.join(tmp, "section.obj")]
    for plane, deg in case["rotate"]:
        cmd += ["--rotate", f"{plane}:{deg!r}"]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"{' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    line = run.stdout.strip().splitlines()[0]
    head = line.split(": ", 1)[1]
    counts = [int(n) for n, _ in COUNT.findall(head.split(", volume")[0])]
    volume = float(re.search(r"volume (\S+)", head).group(1))
    return counts, volume, line


def close(a, b):
    # `cw4d slice` prints the volume with six significant digits.
    return abs(a - b) <= 1e-5 * max(abs(b), 1e-9) + 1e-12


def native_bench_us(args, model):
    run = subprocess.run([args.cw4d, "bench", model, "--seconds", "1"], capture_output=True,
                         text=True)
    if run.returncode != 0:
        fail(f"cw4d bench '{model}' exited {run.returncode}: {run.stderr.strip()}")
    m = re.search(r"slice, hot path \(Slicer\)\s+([\d.]+) us", run.stdout)
    if not m:
        fail(f"cw4d bench printed no hot-path time: {run.stdout}")
    return float(m.group(1))


def check_view(args, tmp, case, label, bad_requests=False):
    """`cw4d view` writes one file that opens from disk (file://, no server) and shows the same
    section as `cw4d slice` of the same placed model."""
    page = os.path.join(tmp, "view.html")
    cmd = [args.cw4d, "view", case["spec"], "--normal", ",".join(map(str, case["normal"])),
           "--offset", str(case["offset"]), "-o", page,
           "--template", os.path.join(args.site, "cw4d-view.html")]
    for plane, deg in case["rotate"]:
        cmd += ["--rotate", f"{plane}:{deg}"]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"{' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    if bad_requests:
        check_bad_view_requests(args, tmp)
    profile = tempfile.mkdtemp(prefix="cw4d-chromium-")
    try:
        dump = subprocess.run(
            chromium_command(args.chromium, profile, "file://" + os.path.abspath(page))[:-1] +
            ["--virtual-time-budget=20000", "--dump-dom", "file://" + os.path.abspath(page)],
            capture_output=True, text=True, timeout=300)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    fv = re.search(r'id="fvector">\(([\d, ]+)\)<', dump.stdout)
    vol = re.search(r'id="volume">([^<]+)<', dump.stdout)
    if not fv or not vol:
        status = re.search(r'id="status"[^>]*>([^<]*)<', dump.stdout)
        fail(f"the page of cw4d view {label} shows no section (status: "
             f"{status.group(1) if status else dump.stdout[:300]!r})")
    # The model picker names the model shown (it once said "5-cell" on every such page).
    picked = re.findall(r'<option value="[^"]*" selected="">([^<]*)<', dump.stdout)
    if len(picked) != 1 or not picked[0].startswith(case["spec"]):
        fail(f"the model picker of the cw4d view page shows {picked}, not {case['spec']}",
             fatal=False)
    counts, volume, line = native_slice(args, tmp, case, case["offset"])
    shown = [int(x) for x in fv.group(1).split(",")]
    if shown != counts or not close(float(vol.group(1)), volume):
        fail(f"cw4d view {label} page shows ({fv.group(1)}), volume {vol.group(1)}; "
             f"native '{line}'", fatal=False)
    return 1


def check_bad_view_requests(args, tmp):
    # Bad requests: exit 1 (usage) with one error line and no file written.
    good = {"-o": os.path.join(tmp, "bad.html"), "--normal": "0,0,0,1",
            "--template": os.path.join(args.site, "cw4d-view.html")}
    for bad, why in [({"--template": os.path.join(tmp, "missing.html")}, "missing"),
                     ({"-o": os.path.join(tmp, "view.txt")}, ".html"),
                     ({"--rotate": "xq:10"}, "xq")]:
        opts = {**good, **bad}
        argv = [args.cw4d, "view", "24-cell"] + [x for kv in opts.items() for x in kv]
        r = subprocess.run(argv, capture_output=True, text=True)
        lines = r.stderr.strip().splitlines()
        written = os.path.exists(opts["-o"])
        if r.returncode != 1 or len(lines) != 1 or why not in lines[0] or written:
            fail(f"{' '.join(argv)}: exit {r.returncode}, stderr {r.stderr!r}, file written: "
                 f"{written}", fatal=False)


def check_g4mf_errors(args, generated, shown):
    """Each bad G4MF file: the page shows one line naming the file, keeps the model it had, and
    the line is the native CLI's message for the same bytes (`cw4d info NAME`, run in the folder
    of the file so that both name it alike); the external buffer the page cannot have is said so."""
    if sorted(shown) != sorted(["bad-json.g4tf", "truncated.g4b", "tesseract-external.g4tf"]):
        fail(f"the page tried the bad G4MF files {sorted(shown)}")
    for name, got in shown.items():
        err = got["error"]
        if not err or "\n" in err or name not in err or not got["kept"]:
            fail(f"{name}: the page's error is {err!r}, the loaded model kept: {got['kept']}",
                 fatal=False)
            continue
        if "external" in name:
            if "external" not in err:
                fail(f"{name}: the page's error does not say the buffer is external: {err!r}",
                     fatal=False)
            continue
        run = subprocess.run([os.path.abspath(args.cw4d), "info", name], capture_output=True, text=True,
                             cwd=generated)
        lines = run.stderr.strip().splitlines()
        if run.returncode == 0 or len(lines) != 1 or not lines[0].endswith(err):
            fail(f"{name}: the page says {err!r}; cw4d info exits {run.returncode} with "
                 f"{run.stderr.strip()!r}", fatal=False)
    return len(shown)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--site", required=True)
    ap.add_argument("--cw4d", required=True)
    ap.add_argument("--samples", required=True)
    ap.add_argument("--g4mf-samples", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "g4mf"))
    ap.add_argument("--chromium", default="chromium")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--report", help="write the measured figures as JSON here")
    args = ap.parse_args()

    with tempfile.TemporaryDirectory(prefix="cw4d-buffers-") as generated:
        check_all(args, generated)


def check_all(args, generated):
    t0 = time.monotonic()
    page = run_page(args, generated)
    page_seconds = time.monotonic() - t0
    if not page.get("ok"):
        fail(f"the page's selftest failed: {page.get('error')}")

    checked = 0
    with tempfile.TemporaryDirectory(prefix="cw4d-browser-") as tmp:
        g4mf_cases = [c for c in page["cases"] if c.get("g4mf")]
        if sorted(c["g4mf"] for c in g4mf_cases) != sorted(
                list(G4MF_CONVERTED) + [n for n in G4MF_SAMPLES if "external" not in n]):
            fail(f"the page opened the G4MF files {[c['g4mf'] for c in g4mf_cases]}")
        for case in g4mf_cases:
            # The whole model as the page read it against `cw4d info` of the same file.
            path = os.path.join(generated, case["g4mf"])
            info = subprocess.run([args.cw4d, "info", path, "--json"], capture_output=True,
                                  text=True)
            if info.returncode != 0:
                fail(f"cw4d info {path} exited {info.returncode}: {info.stderr.strip()}")
            native_fv = json.loads(info.stdout)["fvector"]
            if case["modelFvector"] != native_fv:
                fail(f"{case['g4mf']}: the page read f-vector {case['modelFvector']}, "
                     f"cw4d info {native_fv}", fatal=False)
        for case in page["cases"]:
            counts, volume, line = native_slice(args, tmp, case, case["offset"], generated)
            label = f"{case['spec'] or case['file'] or case['g4mf']} {case['rotate']} " \
                    f"n={case['normal']} d={case['offset']}"
            if case["fvector"] != counts:
                fail(f"{label}: WASM f-vector {case['fvector']} volume {case['volume']!r}, "
                     f"native '{line}'", fatal=False)
            elif not close(case["volume"], volume):
                fail(f"{label}: WASM volume {case['volume']!r}, native '{line}'", fatal=False)
            if case.get("twin"):
                # The same model as a built-in or as the nOFF file it was converted from.
                twin = dict(case, g4mf=None, spec=case["twin"], file=None)
                if case["twin"].endswith(".off"):
                    twin.update(spec=None, file=case["twin"])
                t_counts, t_volume, t_line = native_slice(args, tmp, twin, case["offset"])
                if case["fvector"] != t_counts or not close(case["volume"], t_volume):
                    fail(f"{label}: WASM f-vector {case['fvector']} volume {case['volume']!r}, "
                         f"native of its twin {case['twin']}: '{t_line}'", fatal=False)
            if len(case["normal"]) == 4 and case["triangles"] <= 0:
                fail(f"{label}: no triangles")  # (3D models: the section is an outline)
            checked += 1
        sweep = page["sweep"]
        for layer in sweep["layers"]:
            counts, volume, line = native_slice(args, tmp, sweep, layer["offset"])
            if layer["fvector"] != counts or not close(layer["volume"], volume):
                fail(f"sweep layer d={layer['offset']}: WASM {layer}, native '{line}'", fatal=False)
            checked += 1
        checked += check_view(args, tmp, {"spec": "24-cell", "rotate": [["xw", 40], ["xy", 15], [
            "zw", -25]], "normal": [1, 0, 1, 2], "offset": 0.35}, "24-cell", bad_requests=True)
        # A G4MF file (binary) as the model of `cw4d view`.
        checked += check_view(args, tmp, {
            "spec": os.path.join(generated, "cantellated-icositetrachoron.g4b"),
            "rotate": [["yw", 7], ["xz", 20]], "normal": [0, 0, 1, 1], "offset": 0.05},
            "cantellated-icositetrachoron.g4b")

    for g in page["gpu"]:
        if g["skippedCells"] != 0 or g["tets"] <= 0:
            fail(f"GPU path of {g['spec']}: {g['tets']} tetrahedra, {g['skippedCells']} cells left out")
        if g["cpuPixels"] < 1000:
            fail(f"GPU comparison of {g['spec']}: the CPU path covers only {g['cpuPixels']} pixels")
        if not g["iou"] >= 0.97:
            fail(f"GPU path of {g['spec']}: IoU {g['iou']:.4f} with the CPU path (< 0.97)",
                 fatal=False)

    if len(page["buffers"]) != len(BUFFER_MODELS):
        fail(f"the page compared {len(page['buffers'])} native GPU buffers, not {len(BUFFER_MODELS)}")
    for g in page["buffers"]:
        if g["cpuPixels"] < 1000 or not g["iou"] >= 0.97:
            fail(f"native GPU buffer of {g['spec']} ({g['tets']} tetrahedra): IoU {g['iou']:.4f}, "
                 f"CPU pixels {g['cpuPixels']}", fatal=False)
        # The WebAssembly core's tetrahedra (cw4d_tetra) are the native CLI's, entry by entry:
        # counts, cells, corners and normals (float32 of the same doubles, to 1e-6). UVW must
        # agree too on the models whose coordinates need no libm function (UVW_EXACT); on the
        # others (the tiger's come from sin and cos, whose last bits differ between
        # emscripten's libm and glibc's) the components that differ are reported, not failed.
        same = g.get("same")
        if not same or "error" in same:
            fail(f"no comparison of the core's tetrahedra with the native buffer of {g['spec']}: "
                 f"{same}", fatal=False)
            continue
        if same["skippedCells"] != 0 or same["count"] != same["nativeCount"] or same["cells"] != 0:
            fail(f"the core's tetrahedra of {g['spec']} are not the native CLI's: {same}",
                 fatal=False)
        elif max(same["corners"], same["normals"]) > 1e-6 or \
                (g["spec"] in UVW_EXACT and same["uvwMirrored"] + same["uvwOther"] != 0):
            fail(f"the core's tetrahedra of {g['spec']} differ from the native CLI's: {same}",
                 fatal=False)
        checked += 1

    listed = subprocess.run([args.cw4d, "list"], capture_output=True, text=True, check=True)
    native_specs = {re.split(r"\s{2,}", l.strip())[0] for l in listed.stdout.splitlines() if l.strip()}
    wasm_specs = {c["spec"] for c in page["catalogue"]}
    if native_specs != wasm_specs:
        fail(f"catalogue differs from `cw4d list`: only native {sorted(native_specs - wasm_specs)}, "
             f"only WASM {sorted(wasm_specs - native_specs)}")
    unavailable = sorted(c["spec"] for c in page["catalogue"] if not c["available"])
    if not unavailable:
        fail("the catalogue marks no family as unavailable (the CGAL ones are not built)")
    g4mf_entries = [c for c in page["catalogue"] if ".g4tf" in c["spec"]]
    if len(g4mf_entries) != 1 or not g4mf_entries[0]["available"]:
        fail(f"the catalogue does not list G4MF files as available: {g4mf_entries}")

    errors = page["errors"]
    for key, text in errors.items():
        if not text or "\n" in text:
            fail(f"error '{key}' is not one non-empty line: {text!r}")
    if "no-such-model" not in errors["spec"] or "bad.4off" not in errors["off"] or \
            "text.g4tf" not in errors["g4mfNotBytes"]:
        fail(f"error lines do not name their input: {errors}")
    checked_errors = check_g4mf_errors(args, generated, page["g4mfErrors"])

    bench = []
    for b in page["bench"]:
        native = native_bench_us(args, b["spec"])
        bench.append({"model": b["spec"], "wasm_us": b["us"], "native_us": native,
                      "ratio": b["us"] / native})
    print(f"browser_test: {checked} sections match the native CLI; GPU/CPU IoU " +
          ", ".join(f"{g['spec']} {g['iou']:.4f}" for g in page["gpu"]) +
          "; native GPU buffers " +
          ", ".join(f"{g['spec']} {g['iou']:.4f}" for g in page["buffers"]) +
          "; the core's tetrahedra = the native buffers' (" +
          ", ".join(f"{g['spec']} {g['tets']}" + uvw_note(g.get("same") or {})
                    for g in page["buffers"]) + ")" +
          f"; {checked_errors} bad G4MF files give the native error line"
          f"; unavailable in WASM: {', '.join(unavailable)}; page ran {page_seconds:.1f} s")
    for b in bench:
        print(f"browser_test: slice hot path {b['model']}: WASM {b['wasm_us']:.1f} us, native "
              f"{b['native_us']:.1f} us, WASM/native {b['ratio']:.2f}x")
    if FAILURES:
        sys.exit(1)
    if args.report:
        with open(args.report, "w") as f:
            json.dump({"bench": bench, "gpu": page["gpu"], "buffers": page["buffers"],
                       "page_seconds": page_seconds}, f, indent=2)


if __name__ == "__main__":
    main()
