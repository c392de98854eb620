#!/usr/bin/env python3
"""The project's Python lint: pyflakes (Debian's pyflakes3) over every .py file
of the repository but the build folders. Exit 0 when it finds nothing; 1 with
its findings (FILE:LINE:COL message) otherwise; 2 when pyflakes is missing.
A name a module exports for another program (LinuxCNC's remap handlers) is
listed in its __all__, which pyflakes reads as a use.

usage: lint_python.py ROOT            every .py below ROOT
       lint_python.py --self-test     a file with an unused import must fail
"""
import os
import subprocess
import sys
import tempfile

PYFLAKES = "/usr/bin/pyflakes3"


def python_files(root):
    for top, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not (d.startswith("build") or d.startswith(".")))
        for name in sorted(files):
            if name.endswith(".py"):
                yield os.path.join(top, name)


def lint(paths):
    run = subprocess.run([PYFLAKES, *paths], capture_output=True, text=True)
    print(run.stdout + run.stderr, end="")
    return 0 if run.returncode == 0 else 1


def self_test():
    with tempfile.TemporaryDirectory() as work:
        bad = os.path.join(work, "bad.py")
        with open(bad, "w") as f:
            f.write("import os\n")
        if lint(list(python_files(work))) != 1:
            print("lint_python: an unused import passed")
            return 1
    print("lint_python: a finding fails the lint")
    return 0


def main():
    if not os.path.exists(PYFLAKES):
        print(f"lint_python: {PYFLAKES} is missing (toolchain/setup.sh installs pyflakes3)")
        return 2
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    files = list(python_files(sys.argv[1]))
    status = lint(files)
    if status == 0:
        print(f"lint_python: {len(files)} files, no findings")
    return status


if __name__ == "__main__":
    sys.exit(main())
