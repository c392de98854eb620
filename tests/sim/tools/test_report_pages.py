#!/usr/bin/env python3
"""Every method's report, rendered in headless Chromium (Debian's chromium), as a
person opens it (issue "The calibration lifecycle", item 5): a calibration
stored with --report and a check with --check --report, per method. Each page
must render (a screenshot that is not blank), open with the verdict and the
record (date, version, interface, register map, machine, operator, every input
with its SHA-256, the link to OUT.json), show every figure it names (the PNGs
exist and are drawn) and, for a check, every figure of OUT.json's "check".

usage: test_report_pages.py BIN_DIR
"""
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

FAILURES = []


def check(condition, what):
    if not condition:
        FAILURES.append(what)
        print("FAILED: " + what)


def run(argv, **kw):
    return subprocess.run(argv, capture_output=True, text=True, timeout=300, **kw)


def chromium():
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    return None


def render(browser, page, work, screenshot):
    """The page's DOM after rendering, and (with `screenshot`) a screenshot's
    pixels: each is a Chromium launch of its own, some seconds."""
    url = "file://" + os.path.abspath(page)
    common = [browser, "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
              "--user-data-dir=" + os.path.join(work, "chromium-profile"), "--virtual-time-budget=5000"]
    dom = run(common + ["--dump-dom", url])
    if not screenshot:
        return dom.stdout, None
    shot = os.path.join(work, "shot.png")
    if os.path.exists(shot):
        os.remove(shot)
    run(common + ["--window-size=1000,1400", "--screenshot=" + shot, url])
    pixels = matplotlib.image.imread(shot) if os.path.exists(shot) else None
    return dom.stdout, pixels


def page_checks(browser, report_dir, out_json, verdict, inputs, operator, work, screenshot):
    page = os.path.join(report_dir, "index.html")
    check(os.path.isfile(page), f"{page} exists")
    if not os.path.isfile(page):
        return
    dom, pixels = render(browser, page, work, screenshot)
    if screenshot:
        check(pixels is not None, f"{page}: Chromium made a screenshot")
        if pixels is not None:
            check(float(pixels[..., :3].std()) > 0.02, f"{page}: the rendered page is not blank")
    text = re.sub(r"<[^>]+>", " ", dom)
    check(f"Verdict: {verdict}" in text, f"{page}: opens with the verdict '{verdict}'")
    first_verdict = text.find("Verdict")
    check(0 <= first_verdict < text.find("Summary") if "Summary" in text else first_verdict >= 0,
          f"{page}: the verdict before the summary")
    for word in ("Date", "trueaxis-calibrate", "Interface version (#9006)", "Register map", "Machine (#902)",
                 operator):
        check(word in text, f"{page}: the record holds '{word}'")
    for path in inputs:
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()
        check(f"Input {path} SHA-256 {digest}" in re.sub(r"\s+", " ", text), f"{page}: names {path} with its SHA-256")
    with open(os.path.join(report_dir, "register_map.json"), "rb") as f:
        map_digest = hashlib.sha256(f.read()).hexdigest()
    check(map_digest in text, f"{page}: the register map's SHA-256")
    link = os.path.relpath(os.path.abspath(out_json), os.path.abspath(report_dir))
    check(f"href=\"{link}\"" in dom or f"href='{link}'" in dom, f"{page}: links OUT.json ({link})")
    images = re.findall(r"<img src=\"([^\"]+)\"", dom)
    check(len(images) > 0, f"{page}: shows figures")
    for name in images:
        png = os.path.join(report_dir, name)
        check(os.path.isfile(png), f"{page}: figure {name} exists")
        if os.path.isfile(png):
            check(float(matplotlib.image.imread(png)[..., :3].std()) > 0.01, f"{page}: figure {name} is drawn")
    with open(out_json, encoding="utf-8") as f:
        data = json.load(f)
    if "check" in data:
        for figure in data["check"]["figures"]:
            check(figure["name"] in text, f"{page}: shows check figure {figure['name']}")
        check("Drift since the calibration" in text, f"{page}: shows the drift from the module's log")


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    bin_dir = argv[1]
    browser = chromium()
    if browser is None:
        print("FAILED: no chromium (toolchain/setup.sh installs it)")
        return 1
    work = tempfile.mkdtemp(prefix="trueaxis-report-pages-")
    sim = subprocess.Popen([os.path.join(bin_dir, "trueaxis-sim"), "--port", "0", "--errors", "realistic",
                            "--nv", os.path.join(work, "sim.nv")], stdout=subprocess.PIPE, text=True)
    try:
        port = sim.stdout.readline().strip().rsplit(":", 1)[1]
        calibrate = os.path.join(bin_dir, "trueaxis-calibrate")
        os.chdir(work)
        # A calibration of each method, then a second measurement checked against it.
        for name in ("ball.csv", "ball_again.csv"):
            r = run([os.path.join(bin_dir, "trueaxis-measure-ball"), "--port", port, "--out", name])
            check(r.returncode == 0, "measure the ball: " + r.stderr)
        for seed in ("1", "2"):
            r = run([os.path.join(bin_dir, "trueaxis-measure-gantry"), "--out", f"gantry_{seed}.csv", "--machine",
                     "gantry_machine.csv", "--seed", seed])
            check(r.returncode == 0, "measure the gantry: " + r.stderr)
            r = run([os.path.join(bin_dir, "trueaxis-measure-spindle"), "--out", f"spindle_{seed}.csv", "--machine",
                     "spindle_machine.csv", "--seed", seed])
            check(r.returncode == 0, "measure the spindle: " + r.stderr)
        cases = [("rigidity", ["ball.csv"], ["ball_again.csv"]),
                 ("gantry", ["gantry_1.csv", "gantry_machine.csv"], ["gantry_2.csv", "gantry_machine.csv"]),
                 ("spindle", ["spindle_1.csv", "spindle_machine.csv"], ["spindle_2.csv", "spindle_machine.csv"])]
        for method, first, again in cases:
            for mode, files, extra, verdict in (("calibration", first, ["--store"], "calibration, no tolerance given"),
                                                ("check", again, ["--check"], "pass")):
                args = ["--in", files[0]] + (["--machine", files[1]] if len(files) > 1 else [])
                out, rep = f"{method}_{mode}.json", f"{method}_{mode}_report"
                r = run([calibrate, method] + args + ["--json", out, "--report", rep, "--port", port,
                                                      "--operator", "Ada Lovelace"] + extra)
                check(r.returncode == 0, f"{method} {mode}: exit {r.returncode}: {r.stderr.strip()}")
                if r.returncode == 0:
                    # A screenshot (blank or not) of the check pages; every page's DOM.
                    page_checks(browser, rep, out, verdict, files, "Ada Lovelace", work, mode == "check")
    finally:
        sim.send_signal(signal.SIGTERM)
        sim.wait(timeout=10)
        os.chdir("/")
        shutil.rmtree(work, ignore_errors=True)
    print(f"{len(FAILURES)} failures")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
