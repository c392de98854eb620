#!/usr/bin/env python3
"""Every program in build/host/bin answers --help and --version as people
expect (host_sim/program/include/trueaxis/sim/program.hpp).

usage: test_commands.py BIN_DIR REGISTER_MAP_JSON

Each executable in BIN_DIR is run with --help and with --version (no shell,
10 s each, stdin closed) and falls under one naming rule:

- the product's programs, trueaxis-*, and the benches, bench_*: --help exits 0
  and its first line is "usage: NAME ..."; --version exits 0 and prints exactly
  one line, "NAME VERSION (interface N, source REV)", N the interface version
  of the register map, REV the same for every program (one build, one tree);
- test programs, test_* and *_tests: --help exits 0 with a line that is not
  blank (Catch2's start with one). Their --version is not checked: Catch2 v2
  has none (it exits 255), and test programs are not the product's commands.
- anything else fails: a new program has to choose its rule.

A program that is missing from the product's list below fails too, so one that
stops being built is noticed. Prints one line per failure; exit 1 on any, else 0.
"""
import json
import os
import re
import subprocess
import sys

PRODUCT = ["trueaxis-sim", "trueaxis-level", "trueaxis-calibrate", "trueaxis-measure-ball",
           "trueaxis-measure-gantry", "trueaxis-measure-spindle", "trueaxis-map", "trueaxis-var"]


def run(path, arg):
    """(exit code, stdout) of `path arg`, or (None, why) when it does not end in time."""
    try:
        done = subprocess.run([path, arg], stdin=subprocess.DEVNULL, capture_output=True, timeout=10)
    except subprocess.TimeoutExpired:
        return None, "still running after 10 s"
    return done.returncode, done.stdout.decode("utf-8", "replace")


def first_line(text):
    return text.split("\n", 1)[0]


def check(bin_dir, interface):
    failures = []
    revisions = {}
    names = sorted(n for n in os.listdir(bin_dir)
                   if os.path.isfile(os.path.join(bin_dir, n)) and os.access(os.path.join(bin_dir, n), os.X_OK))
    for name in PRODUCT:
        if name not in names:
            failures.append(f"{name}: not in {bin_dir}")
    for name in names:
        path = os.path.join(bin_dir, name)
        product = name.startswith("trueaxis-") or name.startswith("bench_")
        test = name.startswith("test_") or name.endswith("_tests")
        if not product and not test:
            failures.append(f"{name}: follows no naming rule (trueaxis-*, bench_*, test_*, *_tests)")
            continue
        code, out = run(path, "--help")
        if code != 0:
            failures.append(f"{name} --help: exit {code}: {first_line(out)}")
        elif product and not first_line(out).startswith(f"usage: {name}"):
            failures.append(f"{name} --help: the first line is not 'usage: {name} ...': {first_line(out)!r}")
        elif test and not out.strip():
            failures.append(f"{name} --help: printed nothing")
        if not product:
            continue
        code, out = run(path, "--version")
        match = re.fullmatch(re.escape(name) + r" (\d+\.\d+\.\d+) \(interface (\d+), source (\S+)\)\n", out or "")
        if code != 0:
            failures.append(f"{name} --version: exit {code}: {first_line(out)}")
        elif match is None:
            failures.append(f"{name} --version: not one line 'NAME VERSION (interface N, source REV)': {out!r}")
        elif int(match.group(2)) != interface:
            failures.append(f"{name} --version: interface {match.group(2)}, the map's is {interface}")
        else:
            revisions.setdefault((match.group(1), match.group(3)), []).append(name)
    if len(revisions) > 1:
        failures.append("programs disagree on the version or the source: " +
                        "; ".join(f"{v} {r}: {', '.join(n)}" for (v, r), n in sorted(revisions.items())))
    return names, failures


def main(argv):
    if len(argv) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    with open(argv[2], encoding="utf-8") as f:
        interface = json.load(f)["interface_version"]
    names, failures = check(argv[1], interface)
    for line in failures:
        print(line)
    print(f"test_commands: {len(names)} programs, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
