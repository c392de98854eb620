#!/usr/bin/env python3
"""The stack analysis held against a measurement: runs a target bench that
paints the stack (bench_gantry.cpp prints "stack measured: ROOT N bytes" for
Module::step() over macro 9823 and for gantry::sub_point_mm), analyses the same
build with tools/stack_report.py, and fails unless every measured root is
analysed at no less than was measured (the analysis is a bound). Prints both
figures and the analysis's margin. ctest runs it as stack_measured_gantry.

    python3 tests/target/stack_cross_check.py BUILD_DIR [--elf IMAGE ...] -- BENCH_COMMAND...
"""
import contextlib
import io
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import stack_report  # noqa: E402

MEASURED = re.compile(r"^stack measured: (\S+) (\d+) bytes", re.M)


def main(argv):
    if "--" not in argv or argv.index("--") < 1:
        print(__doc__, file=sys.stderr)
        return 2
    split = argv.index("--")
    report_args, bench = argv[:split], argv[split + 1:]
    run = subprocess.run(bench, capture_output=True, text=True, timeout=600)
    output = run.stdout + run.stderr
    if run.returncode != 0:
        print(output)
        print(f"stack_cross_check: the bench failed (exit {run.returncode})", file=sys.stderr)
        return 1
    measured = [(m.group(1), int(m.group(2))) for m in MEASURED.finditer(output)]
    if not measured:
        print(output)
        print("stack_cross_check: the bench printed no 'stack measured:' line", file=sys.stderr)
        return 1

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        rc = stack_report.main(report_args + ["--json"])
    doc = json.loads(out.getvalue())
    if rc == 2:
        print("\n".join(doc["errors"]))
        print("stack_cross_check: the analysis failed", file=sys.stderr)
        return 1
    analysed = {r["root"]: r.get("bytes") for r in doc["roots"]}

    ok = True
    print(f"  {'root':28} {'measured':>9} {'analysed':>9} {'margin':>7}")
    for root, m in measured:
        a = analysed.get(root)
        if a is None:
            print(f"  {root:28} {m:>9} {'?':>9}   not a root of tools/stack_report.py")
            ok = False
            continue
        verdict = "" if a >= m else "   ANALYSIS BELOW THE MEASUREMENT"
        ok = ok and a >= m
        print(f"  {root:28} {m:>9} {a:>9} {a - m:>7}{verdict}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
