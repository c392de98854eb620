#!/usr/bin/env python3
"""The canary's host layers in the copy with the canary (run_canary.cmake):
trueaxis-calibrate canary against a trueaxis-sim started here (127.0.0.1 port
0), with --store and --report, its OUT.json and report page; the stored sum
read back by a second run's --check; and `trueaxis-calibrate plan canary`.
Exit 0 when every layer holds the canary.

usage: check_canary_flow.py BIN_DIR WORK_DIR
"""
import json
import os
import subprocess
import sys


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    samples = os.path.join(work, "values.csv")
    with open(samples, "w") as f:
        f.write("value\n1.5\n-0.25\n4.0\n")
    sim = subprocess.Popen([os.path.join(bin_dir, "trueaxis-sim"), "--port", "0", "--nv", os.path.join(work, "nv")],
                           stdout=subprocess.PIPE, text=True)
    failures = []
    try:
        port = None
        for line in sim.stdout:
            if "listening on " in line:
                port = line.strip().rsplit(":", 1)[1]
                break
        if port is None:
            print("canary flow: trueaxis-sim did not start")
            return 1
        calibrate = os.path.join(bin_dir, "trueaxis-calibrate")
        out = os.path.join(work, "out.json")
        report = os.path.join(work, "report")
        run = subprocess.run([calibrate, "canary", "--in", samples, "--json", out, "--report", report, "--store",
                              "--port", port], capture_output=True, text=True, timeout=120)
        print(run.stdout + run.stderr, end="")
        if run.returncode != 0:
            failures.append(f"trueaxis-calibrate canary --store --report exited {run.returncode}")
        else:
            with open(out) as f:
                data = json.load(f)
            if data.get("method") != "canary" or data.get("sum") != 10.5:
                failures.append(f"OUT.json is {data}, not the canary's sum 10.5 (gain 2 x 5.25)")
            page = os.path.join(report, "index.html")
            if not os.path.isfile(page) or "Canary" not in open(page).read():
                failures.append("the report page has no canary page")
        var = subprocess.run([os.path.join(bin_dir, "trueaxis-var"), "--port", port, "run", "9854"],
                             capture_output=True, text=True, timeout=60)
        print(var.stdout + var.stderr, end="")
        if var.returncode != 0 or "5.25" not in var.stdout:
            failures.append("the stored sum (9854) is not 5.25")
        plan = subprocess.run([calibrate, "plan", "canary", "--values", "2", "--noise", "0.5"],
                              capture_output=True, text=True, timeout=120)
        print(plan.stdout + plan.stderr, end="")
        if plan.returncode != 0 or "sum" not in plan.stdout:
            failures.append(f"trueaxis-calibrate plan canary exited {plan.returncode}")
        helped = subprocess.run([calibrate, "plan", "--help"], capture_output=True, text=True, timeout=60)
        if "canary    --values" not in helped.stdout:
            failures.append("plan --help does not list the canary's options")
    finally:
        sim.terminate()
        sim.wait(timeout=10)
    for f in failures:
        print("canary flow:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
