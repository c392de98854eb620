#!/usr/bin/env python3
"""Reports of trueaxis-calibrate: one page (DIR/index.html) with its figures
(DIR/figure_N.png), from the JSON the module's results were written to.

usage: trueaxis_report.py MODULE OUT.json DIR

MODULE is the method's report module beside this script (rigidity, gantry,
spindle: trueaxis-calibrate's method table names it). A module holds TITLE and
draw(data, report), which fills a page.Report; page.py is the shape every
report shares. DIR must exist (trueaxis-calibrate makes it); the module's
figures beyond OUT.json's fixed keys, DIR/module_figures.json, are merged into
the data when present. Exit 0, or 2 on bad usage.
"""
import importlib
import json
import os
import re
import sys

# No __pycache__ beside the modules in the source tree.
sys.dont_write_bytecode = True

HERE = os.path.dirname(os.path.abspath(__file__))


def report_module(name):
    """The report module `name` beside this script, or None."""
    if not re.fullmatch(r"[a-z][a-z_]*", name) or name in ("page", "trueaxis_report"):
        return None
    if not os.path.isfile(os.path.join(HERE, name + ".py")):
        return None
    sys.path.insert(0, HERE)
    return importlib.import_module(name)


def main(argv):
    module = report_module(argv[1]) if len(argv) == 4 else None
    if module is None:
        print("usage: trueaxis_report.py MODULE OUT.json DIR (MODULE: a report module beside this script)",
              file=sys.stderr)
        return 2
    from page import Report  # after report_module put HERE on the path

    with open(argv[2], encoding="utf-8") as f:
        data = json.load(f)
    extras = os.path.join(argv[3], "module_figures.json")
    if os.path.exists(extras):
        with open(extras, encoding="utf-8") as f:
            data.update(json.load(f))
    report = Report(argv[3], f"trueaxis report: {module.TITLE}")
    module.draw(data, report)
    report.write()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
