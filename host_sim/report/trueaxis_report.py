#!/usr/bin/env python3
"""Reports of trueaxis-calibrate: one page (DIR/index.html) with its figures
(DIR/figure_N.png), from the JSON the module's results were written to.

usage: trueaxis_report.py MODULE OUT.json DIR

MODULE is the method whose report page this draws (rigidity, gantry, spindle:
trueaxis-calibrate's method table names it): methods/MODULE/host/report.py. A module holds TITLE and
draw(data, report), which fills a page.Report; page.py is the shape every
report shares. DIR must exist (trueaxis-calibrate makes it); the module's
figures beyond OUT.json's fixed keys, DIR/module_figures.json, are merged into
the data when present. Exit 0, or 2 on bad usage.
"""
import importlib
import importlib.util
import hashlib
import json
import os
import re
import sys

# No __pycache__ beside the modules in the source tree.
sys.dont_write_bytecode = True

HERE = os.path.dirname(os.path.abspath(__file__))
METHODS = os.path.join(HERE, os.pardir, os.pardir, "methods")


def report_module(name):
    """The report page of method `name`: methods/NAME/host/report.py of this
    repository (its folder, as the one list names it), or None."""
    if not re.fullmatch(r"[a-z][a-z_]*", name):
        return None
    path = os.path.join(METHODS, name, "host", "report.py")
    if not os.path.isfile(path):
        return None
    sys.path.insert(0, HERE)  # the pages import page.py from here
    spec = importlib.util.spec_from_file_location(f"trueaxis_report_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def sha256_of(path):
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 16), b""):
            digest.update(block)
    return digest.hexdigest()


def num(v, spec):
    return "not a number" if v is None else format(v, spec)


def stored_calibration_text(judged):
    """The stored calibration a check judged, in one line: its table sequence,
    when it was stored, its record's SHA-256 (as the module exports it), and
    why a part is missing."""
    seq = judged.get("table_sequence")
    parts = [f"table sequence {seq}" if seq is not None else "table sequence unknown",
             f"stored {judged['stored_time_utc']} UTC" if judged.get("stored_time_utc") else "store date unknown"]
    if judged.get("record_sha256"):
        parts.append(f"{judged.get('record', 'record')} ({judged.get('record_bytes')} bytes as the module exports it) "
                     f"SHA-256 {judged['record_sha256']}")
    text = "; ".join(parts)
    return text + (f" ({judged['note']})" if judged.get("note") else "")


def record(data, report):
    """What makes the page a record: the verdict first, then who, when, with what
    (trueaxis-calibrate's "record", DIR/module_figures.json), and --check's
    figures, each with its deviation, sigma and tolerance, and their drift over
    the checks the module has logged."""
    rec = data.get("record")
    if rec is None:
        return
    verdict = rec.get("verdict") or "calibration, no tolerance given"
    machine = rec.get("machine_id", 0)
    name = rec.get("machine_name") or ""
    machine_text = f"{machine:.0f}" if machine else "not set (#902 machine_id)"
    if name:
        machine_text += f"; named {name} (--machine-name)"
    rows = [("Verdict", verdict), ("Date", rec.get("date", "")), ("trueaxis", rec.get("version", "")),
            ("Interface version (#9006)", f"{rec.get('interface_version', 0):g}"),
            ("Machine (#902)", machine_text),
            ("Operator", rec.get("operator") or "not given (--operator NAME)")]
    map_file = os.path.join(report.directory, rec.get("register_map", "register_map.json"))
    rows.append(("Register map", "SHA-256 " + sha256_of(map_file) + " (register_map.json, trueaxis-map --json)"
                 if os.path.isfile(map_file) else "not recorded"))
    for path in rec.get("inputs", []):
        rows.append(("Input " + path, "SHA-256 " + sha256_of(path) if os.path.isfile(path) else "not found"))
    for given in data.get("taken_as_given", []):  # MACHINE values no data of this run tested
        rows.append(("Taken as given", given))
    judged = (data.get("check") or {}).get("stored_calibration")
    if judged is not None:
        rows.append(("Stored calibration judged", stored_calibration_text(judged)))
    out_json = rec.get("out_json", "")
    link = os.path.relpath(os.path.abspath(out_json), os.path.abspath(rec.get("report_dir") or "."))
    report.record(rows, verdict, link)
    check = data.get("check")
    if check is not None:
        report.table(f"Check against the stored calibration: {check['verdict']}",
                     ["figure", "stored", "measured", "deviation", "sigma", "tolerance", "unit", "verdict"],
                     [[f["name"], num(f["stored"], ".4g"), num(f["measured"], ".4g"), num(f["deviation"], ".4g"),
                       num(f["sigma"], ".2g"), num(f["tolerance"], ".4g"), f["unit"], f["verdict"]]
                      for f in check["figures"]])
    drift = data.get("drift")
    if drift is not None:
        report.table("Drift since the calibration, from the module's measuring log (trueaxis-calibrate log)",
                     ["figure", "trend"],
                     [[d["figure"], d["text"].split(": ", 1)[1]] for d in drift] or [["-", "no check logged yet"]])


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
    record(data, report)
    module.draw(data, report)
    report.write()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
