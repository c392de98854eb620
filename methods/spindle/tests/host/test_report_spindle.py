#!/usr/bin/env python3
"""The spindle report's figures and tables say what they promise (issue 17,
"Why": a constant sigma drawn against an axis offset of 1e-13, an invisible
band, one sigma line hiding another, per-angle tables without their sigmas).

usage: test_report_spindle.py REPORT_DIR   (host_sim/report)

Draws the report of a synthetic M4 result (a constant theta_e sigma, equal x
and y tool-tip sigmas, bands far narrower than the curves) into a temporary
directory and checks: every sigma panel starts at 0 with plain tick labels (no
offset), the top panel says that the bands are narrower than the lines and how
wide they are, sigma lines that coincide are drawn in distinct styles, and the
per-angle table gives every figure with its sigma. Exit 0 when all hold.
"""
import math
import os
import sys
import tempfile

sys.path.insert(0, sys.argv[1])
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "host"))

import report as spindle  # noqa: E402  (methods/spindle/host/report.py)
from page import Report, plt  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def synthetic():
    per = []
    for k in range(72):
        phi = 5.0 * k
        t = math.radians(phi)
        per.append({"phi_deg": phi,
                    "theta_e_arcsec": 38.0 + 17.0 * math.sin(t), "theta_e_sigma_arcsec": 0.0048,
                    "d_e_mm": 0.02 + 0.005 * math.cos(t), "d_e_sigma_mm": 9e-6,
                    "tool_tip_error_mm": [0.06 + 0.02 * math.sin(t), -0.09 + 0.02 * math.cos(t), 1e-7],
                    "tool_tip_error_sigma_mm": [1.03e-5, 1.03e-5, 2e-9]})
    params = {"o_x_mm": {"value": 0.001, "sigma": 2e-6}, "a_x": {"value": 1e-4, "sigma": 2e-8}}
    return {"method": "spindle", "per_angle": per, "parameters": params, "tool_length_mm": 250.0,
            "theta_e_max_arcsec": 55.0, "d_e_max_mm": 0.025, "evaluations": 3, "model_ball_mm": [100.0, 150.0],
            "fit": {"noise_sigma_mm": 1.5e-5, "synchronous_rms_mm": 5e-5, "rms_mm": 6e-5, "samples": 288},
            "mean_tool_tip_error_mm": [0.06, -0.09, 0.0], "mean_tool_tip_error_sigma_mm": [1e-5, 1e-5, 2e-9]}


# The sigma panel of with_sigma, drawn as the report draws it.
x = [5.0 * k for k in range(72)]
fig = spindle.with_sigma(x, [("theta_e", [38.0 + 17.0 * math.sin(math.radians(v)) for v in x], [0.0048] * 72)],
                         "arcsec", "arcsec", 1.0)
top, bottom = fig.axes
fig.canvas.draw()
check(bottom.get_ylim()[0] == 0.0, f"the sigma panel starts at {bottom.get_ylim()[0]}, not 0")
check(bottom.get_ylim()[1] >= 0.0048, "the sigma panel does not reach the sigma")
check(bottom.yaxis.get_offset_text().get_text() == "", "the sigma axis has an offset: "
      + bottom.yaxis.get_offset_text().get_text())
notes = [t.get_text() for t in top.texts]
check(any("narrower than the lines" in n and "0.0048" in n for n in notes),
      f"the top panel does not say how wide the invisible band is: {notes}")
plt.close(fig)

fig = spindle.with_sigma(x, [(n, [10.0 * k + v for v in x], [0.0103] * 72) for k, n in enumerate("xyz")],
                         "um", "nm", 1000.0)
styles = [(line.get_linestyle(), line.get_linewidth()) for line in fig.axes[1].get_lines()]
check(len(set(styles)) == 3, f"coinciding sigma lines are drawn alike: {styles}")
plt.close(fig)

# The page's per-angle table: every figure with its sigma.
with tempfile.TemporaryDirectory() as d:
    report = Report(d, "spindle")
    spindle.draw(synthetic(), report)
    report.write()
    page = open(os.path.join(d, "index.html"), encoding="utf-8").read()
    table = page[page.index("Per spindle angle"):]
    first_row = table[table.index("<tr><td>"):table.index("</tr>", table.index("<tr><td>"))]
    cells = first_row.replace("<tr>", "").split("</td>")[:-1]
    check(len(cells) == 6, f"the per-angle row has {len(cells)} cells")
    check(all("+-" in c for c in cells[1:]), f"a per-angle figure without its sigma: {cells}")

for f in failures:
    print("FAIL", f)
print(f"{'ok' if not failures else 'FAILED'}: spindle report")
sys.exit(1 if failures else 0)
