#!/usr/bin/env python3
"""The gantry report's figures and tables say what they promise (issue 17,
"Why": the gantry figure 5 legend covers a bar; item 6: every figure with its
sigma, noise never shown as geometry, every table column with its unit and
sigma).

usage: test_report_gantry.py REPORT_DIR   (host_sim/report)

Draws the report of a synthetic M2 result (OUT.json with the keys of
docs/INTERFACE.md "Additions", and the module's extra figures) into a temporary
directory and checks: no legend covers a bar and every legend lies within its
figure; the flatness and straightness table gives the noise floor and the form
error with its sigma; every column of every table but the names names its unit;
the sub-machine figures table gives each figure with its sigma; a figure the
module could not give (-1: a stored table from before it; a key an older
OUT.json lacks) reads "n/a", never -1000. Exit 0 when all hold.
"""
import copy
import os
import re
import sys
import tempfile

sys.path.insert(0, sys.argv[1])
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "host"))

import report as gantry  # noqa: E402  (methods/gantry/host/report.py)
from page import Report  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def synthetic():
    subs, extra = [], []
    for n in range(1, 5):
        subs.append({"id": n, "origin_mm": [100.0 * n, 200.0, 300.0], "origin_sigma_mm": 0.004 + 0.001 * n,
                     "x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0], "master_axis": "y",
                     # squareness of mixed signs and sizes, so that bars reach every corner of the axes
                     "squareness_arcsec": {"xy": 28.0 * (-1) ** n, "yz": -12.0 + 9.0 * n, "zx": 30.0 - 4.0 * n},
                     "a_c_offset_mm": 0.015 + 0.008 * n, "a_c_angle_deg": 90.0 + 0.005 * (n - 2.5),
                     "global_T_sub": [1, 0, 0, 100.0 * n, 0, 1, 0, 200, 0, 0, 1, 300, 0, 0, 0, 1],
                     "squareness_sigma_arcsec": {"xy": 1.2, "yz": 2.5, "zx": 0.8},
                     "a_c_offset_sigma_mm": 0.0021, "a_c_angle_sigma_deg": 0.00061,
                     "angle_sigma_arcsec": [1.1, 0.9, 1.4]})
        # straightness and circle RMS: the first bars the tallest, where a legend inside would sit
        extra.append({"id": n, "angle_sigma_arcsec": [1.1, 0.9, 1.4],
                      "straightness_mm": [0.040 - 0.005 * n, 0.030, 0.020 + 0.004 * n],
                      "c_circle_rms_mm": 0.012 + 0.001 * n, "a_circle_rms_mm": 0.016 - 0.001 * n})
    glob = {"origin_mm": [1.0, 2.0, 3.0], "x": [1.0, 0.0, 0.0], "y": [0.0, 1.0, 0.0], "z": [0.0, 0.0, 1.0],
            "bed_flatness_mm": 0.1105, "gantry_straightness_mm": 0.0946,
            "bed_flatness_noise_floor_mm": 0.1064, "gantry_straightness_noise_floor_mm": 0.1122,
            "bed_form_error_mm": 0.0031, "bed_form_error_sigma_mm": 0.0042,
            "gantry_form_error_mm": 0.0, "gantry_form_error_sigma_mm": 0.0051}
    return {"method": "gantry", "global": glob, "sub_machines": subs, "global_origin_sigma_mm": 0.003,
            "global_angle_sigma_arcsec": [0.5, 0.6, 0.7], "sub_machine_figures": extra}


class Checked(Report):
    """A Report that checks each figure's legends before saving it, as drawn."""

    limits = {}  # figure number: its axes' y limits, as drawn

    def figure(self, fig, caption):
        number = self.figures + 1
        Checked.limits[number] = [ax.get_ylim() for ax in fig.axes]
        fig.tight_layout()
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            legend = ax.get_legend()
            if legend is None:
                continue
            box = legend.get_window_extent(renderer)
            check(fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1,
                  f"figure {number}: the legend is cut off by the figure's edge")
            for bar in ax.patches:
                b = bar.get_window_extent(renderer)
                if b.width > 0 and b.height > 0 and box.overlaps(b):
                    failures.append(f"figure {number}: the legend covers a bar")
                    break
        super().figure(fig, caption)


def tables(page):
    """{title: (headers, rows)} of the page's tables (the summary's rows as rows)."""
    out = {}
    for m in re.finditer(r"<h2>(.*?)</h2><table[^>]*>(.*?)</table>", page):
        heads = re.findall(r"<th>(.*?)</th>", m.group(2))
        rows = [re.findall(r"<td>(.*?)</td>", r) for r in re.findall(r"<tr>(.*?)</tr>", m.group(2))]
        out[m.group(1)] = (heads, [r for r in rows if r])
    return out


def draw(data, d):
    report = Checked(d, "gantry")
    gantry.draw(data, report)
    report.write()
    return open(os.path.join(d, "index.html"), encoding="utf-8").read(), report.figures


with tempfile.TemporaryDirectory() as d:
    page, figures = draw(synthetic(), d)
    check(figures >= 6, f"{figures} figures, not 6")
    # Figure 6, right: the bed's form error 3.1 um +- 4.2 um: the error bar reaches 7.3 um.
    check(len(Checked.limits.get(6, [])) == 2 and Checked.limits[6][1][1] >= 7.3,
          f"figure 6: the form error's sigma is not drawn to scale: {Checked.limits.get(6)}")
    t = tables(page)
    flat = next((v for k, v in t.items() if k.startswith("Flatness and straightness")), None)
    check(flat is not None, f"no flatness and straightness table: {list(t)}")
    if flat is not None:
        heads, rows = flat
        check(any("noise floor" in h for h in heads), f"the flatness table has no noise floor column: {heads}")
        check(any("form error" in h for h in heads), f"the flatness table has no form error column: {heads}")
        check(len(rows) == 2 and rows[0][2] == "106.4" and rows[1][2] == "112.2",
              f"the noise floors are not the result's: {rows}")
        check(all(r[3].count("+-") == 1 for r in rows), f"a form error without its sigma: {rows}")
        check(rows[0][3] == "3.1 +- 4.2", f"the bed's form error reads {rows[0][3]}")
    subs = next((v for k, v in t.items() if k.startswith("Sub-machine figures")), None)
    check(subs is not None, "no sub-machine figures table")
    if subs is not None:
        check(all("+-" in c for r in subs[1] for c in r[1:]), f"a sub-machine figure without its sigma: {subs[1]}")
        check(subs[1][0][1] == "-28.0 +- 1.2", f"sp1's xy squareness reads {subs[1][0][1]}")
        check(subs[1][0][4] == "23.0 +- 2.1", f"sp1's A-to-C offset reads {subs[1][0][4]}")
    names = {"frame", "sub-machine", "master", "figure"}
    for title, (heads, rows) in t.items():
        if title == "Summary":
            continue
        for h in heads:
            check(h in names or re.search(r"\((.*?)\)", h), f"table '{title}': column '{h}' names no unit")
    frames = next((v for k, v in t.items() if k == "Frames"), None)
    check(frames is not None and any("1-sigma" in h and "arcsec" in h for h in frames[0]),
          "the Frames table does not give the axes' 1-sigma")
    summary = dict(re.findall(r"<tr><th>(.*?)</th><td>(.*?)</td></tr>", page))
    check("noise floor 106.4 um" in summary.get("bed flatness (peak-to-valley)", ""),
          f"the summary's bed flatness has no noise floor: {summary}")
    check(summary.get("bed form error (noise-corrected RMS, 1 sigma)") == "3.1 +- 4.2 um",
          f"the summary's bed form error: {summary.get('bed form error (noise-corrected RMS, 1 sigma)')}")

# A table stored before the figures (-1) and an OUT.json without the new keys.
for what, data in (("-1 (not stored)", "minus"), ("keys absent", "absent")):
    result = synthetic()
    keys = ("bed_flatness_noise_floor_mm", "gantry_straightness_noise_floor_mm", "bed_form_error_mm",
            "bed_form_error_sigma_mm", "gantry_form_error_mm", "gantry_form_error_sigma_mm")
    sub_keys = ("squareness_sigma_arcsec", "a_c_offset_sigma_mm", "a_c_angle_sigma_deg", "angle_sigma_arcsec")
    for k in keys:
        if data == "minus":
            result["global"][k] = -1.0
        else:
            del result["global"][k]
    for s in result["sub_machines"]:
        for k in sub_keys:
            if data == "minus":
                s[k] = {"xy": -1.0, "yz": -1.0, "zx": -1.0} if k == "squareness_sigma_arcsec" else (
                    [-1.0] * 3 if k == "angle_sigma_arcsec" else -1.0)
            else:
                del s[k]
    with tempfile.TemporaryDirectory() as d:
        try:
            page, _ = draw(copy.deepcopy(result), d)
        except Exception as e:  # noqa: BLE001
            failures.append(f"{what}: the report fails: {e!r}")
            continue
        check("-1000" not in page and "-1.0 +-" not in page, f"{what}: -1 drawn as a figure")
        check("n/a" in page, f"{what}: the figures not given do not read n/a")

for f in failures:
    print("FAIL", f)
print(f"{'ok' if not failures else 'FAILED'}: gantry report")
sys.exit(1 if failures else 0)
