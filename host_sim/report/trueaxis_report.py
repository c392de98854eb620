#!/usr/bin/env python3
"""Reports of trueaxis-calibrate: one page (index.html) with plots, from the
JSON the module's results were written to. Plots are drawn by matplotlib
(Debian's python3-matplotlib), never by hand.

usage: trueaxis_report.py METHOD OUT.json DIR

DIR must exist (trueaxis-calibrate makes it). The shape every method's report shares: a title, a summary table (what an
integrator files), figures with a caption each (what a metrology engineer
reads), and the per-sample table. A method adds one function below.
"""
import html
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


class Report:
    def __init__(self, directory, title):
        self.directory = directory
        self.title = title
        self.parts = []
        self.figures = 0

    def summary(self, rows):
        body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows)
        self.parts.append(f"<h2>Summary</h2><table class='summary'>{body}</table>")

    def figure(self, fig, caption):
        self.figures += 1
        name = f"figure_{self.figures}.png"
        fig.tight_layout()
        fig.savefig(os.path.join(self.directory, name), dpi=110)
        plt.close(fig)
        self.parts.append(f"<figure><img src='{name}' alt='{html.escape(caption)}'>"
                          f"<figcaption>Figure {self.figures}. {html.escape(caption)}</figcaption></figure>")

    def table(self, title, headers, rows):
        head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in rows)
        self.parts.append(f"<h2>{html.escape(title)}</h2><table><tr>{head}</tr>{body}</table>")

    def write(self):
        style = ("body{font-family:sans-serif;max-width:60em;margin:2em auto}"
                 "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
                 "text-align:right}table.summary th{text-align:left}figure{margin:1.5em 0}"
                 "img{max-width:100%}figcaption{font-size:90%;color:#333}")
        page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(self.title)}</title>"
                f"<style>{style}</style></head><body><h1>{html.escape(self.title)}</h1>"
                + "".join(self.parts) + "</body></html>\n")
        with open(os.path.join(self.directory, "index.html"), "w", encoding="utf-8") as f:
            f.write(page)


def fmt(v, digits=3):
    return f"{v:.{digits}f}"


def rigidity(data, report):
    poses = data["poses"]
    a = [p["a_deg"] for p in poses]
    r = [p["rigidity_arcsec"] for p in poses]
    rs = [p["rigidity_sigma_arcsec"] for p in poses]
    worst = max(range(len(poses)), key=lambda i: r[i])
    axis = data["a_axis"]
    report.summary([
        ("A poses", str(len(poses))),
        ("largest rigidity figure", f"{fmt(r[worst], 2)} +- {fmt(rs[worst], 2)} arcsec (1 sigma) at A = {fmt(a[worst], 3)} deg"),
        ("A axis point (mm)", ", ".join(fmt(v, 4) for v in axis["point_mm"])),
        ("A axis direction", ", ".join(fmt(v, 8) for v in axis["direction"])),
        ("C-to-A offset", f"{fmt(data.get('c_to_a_offset_mm', float('nan')), 4)} mm"),
        ("C-to-A squareness", f"{fmt(data.get('c_to_a_squareness_arcsec', float('nan')), 2)} arcsec"),
        ("largest C-circle RMS", f"{fmt(max(p['c_circle_rms_mm'] for p in poses) * 1000, 3)} um"),
    ])

    fig, ax = plt.subplots(figsize=(7, 3.6))
    lo = [x - s for x, s in zip(r, rs)]
    hi = [x + s for x, s in zip(r, rs)]
    ax.fill_between(a, lo, hi, alpha=0.3, label="1-sigma band")
    ax.plot(a, r, "o-", label="rigidity |rotation vector|")
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("arcsec")
    ax.grid(True, alpha=0.3)
    ax.legend()
    report.figure(fig, "Rigidity figure (norm of the rotation vector between the actual and the theoretical "
                       "table frame) against A, with its 1-sigma band from the data's own scatter.")

    fig, ax = plt.subplots(figsize=(7, 3.6))
    for k, name in enumerate("xyz"):
        ax.errorbar(a, [p["rotation_vector_arcsec"][k] for p in poses],
                    yerr=[p["rotation_vector_sigma_arcsec"][k] for p in poses], marker="o", capsize=3,
                    label=f"{name} component")
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("arcsec")
    ax.grid(True, alpha=0.3)
    ax.legend()
    report.figure(fig, "The three components of the rotation vector log(R_actual R_theory^T), machine "
                       "coordinates, with 1-sigma error bars.")

    fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.plot(a, [p["a_positioning_error_arcsec"] for p in poses], "o-")
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("arcsec")
    ax.grid(True, alpha=0.3)
    report.figure(fig, "A-axis positioning error: the actual turn from the reference pose minus the commanded "
                       "difference in A (positive in the direction of increasing A).")

    fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.bar([str(round(x, 3)) for x in a], [p["c_circle_rms_mm"] * 1000 for p in poses])
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("um")
    ax.grid(True, axis="y", alpha=0.3)
    report.figure(fig, "C-circle residuals: RMS 3-D distance of each pose's ball positions from its fitted circle.")

    rows = []
    for p in poses:
        rows.append([fmt(p["a_deg"], 3)] + [fmt(v, 2) for v in p["rotation_vector_arcsec"]]
                    + [fmt(v, 2) for v in p["rotation_vector_sigma_arcsec"]]
                    + [fmt(p["rigidity_arcsec"], 2), fmt(p["rigidity_sigma_arcsec"], 2),
                       fmt(p["a_positioning_error_arcsec"], 2), fmt(p["c_circle_rms_mm"] * 1000, 3)])
    report.table("Per pose", ["A (deg)", "rx", "ry", "rz", "sx", "sy", "sz", "rigidity", "sigma",
                              "A error", "C rms (um)"], rows)


def grouped_bars(ax, labels, series, ylabel):
    """Bars of several series side by side per label; series: [(name, values), ...]."""
    width = 0.8 / max(len(series), 1)
    for k, (name, values) in enumerate(series):
        ax.bar([i + (k - (len(series) - 1) / 2) * width for i in range(len(labels))], values, width, label=name)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels)
    ax.set_ylabel(ylabel)
    ax.axhline(0.0, color="black", linewidth=0.6)
    ax.grid(True, axis="y", alpha=0.3)
    if len(series) > 1:
        ax.legend()


def gantry(data, report):
    glob = data["global"]
    subs = data["sub_machines"]
    # The module's figures beyond OUT.json (module_figures.json), by sub-machine id.
    extra = {f["id"]: f for f in data.get("sub_machine_figures", [])}
    nan3 = [float("nan")] * 3

    def fig_of(sub, key, default):
        return extra.get(sub["id"], {}).get(key, default)

    labels = [f"sp{s['id']}" for s in subs]
    worst = max(subs, key=lambda s: s["origin_sigma_mm"]) if subs else None
    square = [(abs(v), s["id"], k) for s in subs for k, v in s["squareness_arcsec"].items()]
    rows = [
        ("sub-machines", ", ".join(str(s["id"]) for s in subs)),
        ("global origin O (tracker frame, mm)", ", ".join(fmt(v, 4) for v in glob["origin_mm"])),
        ("global origin 1-sigma", f"{fmt(data.get('global_origin_sigma_mm', float('nan')) * 1000, 1)} um"),
        ("bed flatness (peak-to-valley)", f"{fmt(glob['bed_flatness_mm'] * 1000, 1)} um"),
        ("gantry straightness (peak-to-valley)", f"{fmt(glob['gantry_straightness_mm'] * 1000, 1)} um"),
    ]
    if worst is not None:
        rows.append(("largest origin 1-sigma", f"{fmt(worst['origin_sigma_mm'] * 1000, 1)} um (sp{worst['id']})"))
    if square:
        v, sid, pair = max(square)
        rows.append(("largest squareness error", f"{fmt(v, 1)} arcsec (sp{sid}, {pair})"))
    report.summary(rows)

    fig, ax = plt.subplots(figsize=(7, 3.2))
    grouped_bars(ax, labels + ["global"],
                 [("origin 1-sigma", [s["origin_sigma_mm"] * 1000 for s in subs]
                   + [data.get("global_origin_sigma_mm", float("nan")) * 1000])], "um")
    report.figure(fig, "Origin uncertainty: the 1-sigma radial uncertainty of each sub-machine's origin O_sp "
                       "(global frame, the global frame's own uncertainty included) and of the global origin O, "
                       "from the fits' residuals.")

    fig, ax = plt.subplots(figsize=(7, 3.4))
    angle = [fig_of(s, "angle_sigma_arcsec", nan3) for s in subs] + [data.get("global_angle_sigma_arcsec", nan3)]
    grouped_bars(ax, labels + ["global"],
                 [(f"about {n}", [a[k] for a in angle]) for k, n in enumerate(("x'", "y'", "z'"))], "arcsec")
    report.figure(fig, "Orientation uncertainty: 1-sigma of each frame's rotation about its own axes "
                       "(sub-machines in the global frame, the global frame in the tracker's).")

    fig, ax = plt.subplots(figsize=(7, 3.4))
    grouped_bars(ax, labels, [(pair, [s["squareness_arcsec"][pair] for s in subs]) for pair in ("xy", "yz", "zx")],
                 "arcsec")
    report.figure(fig, "Squareness of each sub-machine's linear axes: the measured angle of each pair minus 90 deg, "
                       "before orthonormalisation.")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8, 3.2))
    ax1.bar(labels, [s["a_c_offset_mm"] * 1000 for s in subs])
    ax1.set_ylabel("um")
    ax1.set_title("A-to-C offset", fontsize=10)
    ax1.grid(True, axis="y", alpha=0.3)
    ax2.bar(labels, [(s["a_c_angle_deg"] - 90.0) * 3600.0 for s in subs])
    ax2.axhline(0.0, color="black", linewidth=0.6)
    ax2.set_ylabel("arcsec")
    ax2.set_title("A-to-C angle minus 90 deg", fontsize=10)
    ax2.grid(True, axis="y", alpha=0.3)
    report.figure(fig, "The head's A and C axes: the length of their common perpendicular, and the angle between "
                       "their directions minus 90 deg.")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.4))
    grouped_bars(ax1, labels, [(n, [fig_of(s, "straightness_mm", nan3)[k] * 1000 for s in subs])
                               for k, n in enumerate("xyz")], "um")
    ax1.set_title("straightness, worst pass (peak-to-valley)", fontsize=10)
    grouped_bars(ax2, labels, [(n, [fig_of(s, key, float("nan")) * 1000 for s in subs])
                               for n, key in (("C", "c_circle_rms_mm"), ("A", "a_circle_rms_mm"))], "um")
    ax2.set_title("circle residuals (RMS)", fontsize=10)
    report.figure(fig, "Each sub-machine's linear axes (twice the largest distance of a pass from its fitted line, "
                       "worst pass) and its C and A circles (RMS 3-D distance of the points from the fitted circle).")

    fig, ax = plt.subplots(figsize=(5, 3.0))
    ax.bar(["bed flatness", "gantry straightness"],
           [glob["bed_flatness_mm"] * 1000, glob["gantry_straightness_mm"] * 1000])
    ax.set_ylabel("um")
    ax.grid(True, axis="y", alpha=0.3)
    report.figure(fig, "The machine's own figures: the spread of the pads' distances from their fitted plane, and "
                       "twice the largest distance of a gantry pass from its fitted line (worst pass).")

    def vec(v, digits):
        return ", ".join(fmt(x, digits) for x in v)

    table = [["global (tracker frame)", vec(glob["origin_mm"], 4), "", "", vec(glob["x"], 8), vec(glob["y"], 8),
              vec(glob["z"], 8)]]
    for s in subs:
        table.append([f"sp{s['id']} (global frame)", vec(s["origin_mm"], 4), fmt(s["origin_sigma_mm"] * 1000, 1),
                      s["master_axis"], vec(s["x"], 8), vec(s["y"], 8), vec(s["z"], 8)])
    report.table("Frames", ["frame", "origin (mm)", "origin sigma (um)", "master", "x axis", "y axis", "z axis"],
                 table)
    rows = []
    for s in subs:
        t = s["global_T_sub"]
        rows.append([f"sp{s['id']}"] + [" ".join(fmt(v, 9 if c < 3 else 4) for c, v in enumerate(t[4 * r:4 * r + 4]))
                                        for r in range(3)])
    report.table("global_T_sub (sub-machine coordinates into the global frame; rows 1-3, the last is 0 0 0 1)",
                 ["sub-machine", "row 1", "row 2", "row 3"], rows)


ARCSEC_PER_RAD = 180.0 * 3600.0 / math.pi


def with_sigma(x, series, unit, sigma_unit, sigma_scale):
    """Curves over x with their 1-sigma bands (top), and the 1-sigma itself
    (bottom: a band far narrower than the curve is lost at the curve's scale).
    series: [(label, values, sigmas), ...] already in `unit`."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5.0), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    for label, y, s in series:
        top.fill_between(x, [a - b for a, b in zip(y, s)], [a + b for a, b in zip(y, s)], alpha=0.3)
        top.plot(x, y, "-", label=label)
        bottom.plot(x, [v * sigma_scale for v in s], "-", label=f"{label} 1-sigma")
    top.set_ylabel(unit)
    bottom.set_ylabel(sigma_unit)
    bottom.set_xlabel("spindle angle phi (deg, M19 zero, M03 positive)")
    bottom.set_xlim(0, 360)
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, ncol=3)
    return fig


def spindle(data, report):
    per = data["per_angle"]
    params = data["parameters"]
    fit = data.get("fit", {})
    phi = [p["phi_deg"] for p in per]
    tool = data.get("tool_length_mm", float("nan"))
    tip = [p["tool_tip_error_mm"] for p in per]
    tip_s = [p.get("tool_tip_error_sigma_mm", [0.0] * 3) for p in per]
    radial = [math.hypot(t[0], t[1]) for t in tip]
    worst = max(range(len(per)), key=lambda i: radial[i])
    mean = data.get("mean_tool_tip_error_mm", [float("nan")] * 3)
    mean_s = data.get("mean_tool_tip_error_sigma_mm", [float("nan")] * 3)
    report.summary([
        ("samples", f"{fit.get('samples', float('nan')):.0f} ball centres, {data['evaluations']} model evaluations"),
        ("largest theta_e", f"{fmt(data['theta_e_max_arcsec'], 2)} arcsec"),
        ("largest d_e", f"{fmt(data['d_e_max_mm'] * 1000, 3)} um"),
        (f"largest tool-tip error across the axis (tool {fmt(tool, 1)} mm)",
         f"{fmt(radial[worst] * 1000, 3)} um at phi = {fmt(phi[worst], 1)} deg"),
        ("tool-tip error over a revolution (mean, x y z)",
         ", ".join(f"{fmt(m * 1000, 3)} um +- {fmt(s * 1e6, 1)} nm" for m, s in zip(mean, mean_s))),
        ("probe noise (1 sigma per axis)",
         f"{fmt(fit.get('noise_sigma_mm', float('nan')) * 1e6, 1)} nm, "
         + ("from the repeats of an angle" if fit.get("noise_from_repeats") else
            "from every residual (one revolution: form error included, intervals conservative)")),
        ("synchronous RMS (form error the model does not hold)",
         f"{fmt(fit.get('synchronous_rms_mm', float('nan')) * 1e6, 1)} nm"),
        ("gauge line below O1 / balls below the gauge line",
         f"{fmt(data.get('model_gauge_mm', float('nan')), 3)} mm / "
         + ", ".join(fmt(b, 3) for b in data.get("model_ball_mm", [])) + " mm"),
        ("bearing spacing (informative)",
         f"{fmt(data.get('bearing_spacing_mm', float('nan')), 3)} mm: the analyser sees the tool line, not the "
         "bearings, so the model does not use it"),
    ])

    fig = with_sigma(phi, [("theta_e", [p["theta_e_arcsec"] for p in per],
                            [p.get("theta_e_sigma_arcsec", 0.0) for p in per])], "arcsec", "arcsec", 1.0)
    report.figure(fig, "theta_e over a revolution: the angle between the ideal axis (machine Z through O1, towards "
                       "the tool) and the tool axis at each spindle angle, with its 1-sigma band; below, the 1-sigma.")

    fig = with_sigma(phi, [("d_e", [p["d_e_mm"] * 1000 for p in per],
                            [p.get("d_e_sigma_mm", 0.0) * 1000 for p in per])], "um", "nm", 1000.0)
    report.figure(fig, "d_e over a revolution: the length of the common perpendicular of the ideal axis and the "
                       "tool axis, with its 1-sigma band; below, the 1-sigma.")

    fig = plt.figure(figsize=(9, 4.2))
    ax1 = fig.add_subplot(1, 2, 1, projection="polar")
    closed = list(range(len(per))) + [0]
    ax1.plot([math.radians(phi[i]) for i in closed], [radial[i] * 1000 for i in closed], "-o", markersize=2)
    ax1.set_theta_zero_location("E")
    ax1.set_title("|tip error across the axis| (um) against phi", fontsize=10)
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot([tip[i][0] * 1000 for i in closed], [tip[i][1] * 1000 for i in closed], "-", label="tip error, phi 0..360")
    ax2.plot([tip[0][0] * 1000], [tip[0][1] * 1000], "o", label="phi = 0")
    ax2.plot([mean[0] * 1000], [mean[1] * 1000], "+", markersize=12, label="mean over a revolution")
    ax2.plot([0], [0], "k.", label="ideal tip")
    ax2.set_xlabel("x (um)")
    ax2.set_ylabel("y (um)")
    ax2.set_aspect("equal", adjustable="datalim")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    report.figure(fig, f"The tool-tip error (actual minus ideal tip, analyser frame) at tool length {fmt(tool, 1)} mm "
                       "over a revolution: its size across the axis as a polar plot against the spindle angle, and the "
                       "tip's x-y path. The controller subtracts it.")

    fig = with_sigma(phi, [(name, [t[k] * 1000 for t in tip], [s[k] * 1000 for s in tip_s])
                           for k, name in enumerate("xyz")], "um", "nm", 1000.0)
    report.figure(fig, "The tool-tip error's components over a revolution with their 1-sigma bands, and below the "
                       "1-sigma (z moves with the tilt squared: its sigma is tiny). Axial errors the analyser cannot "
                       "see (a longer holder, bearing spacing) are in none of them: the tool-length offset holds those.")

    fig, ax = plt.subplots(figsize=(6, 3.0))
    figures = [("probe noise (1 sigma)", fit.get("noise_sigma_mm", float("nan"))),
               ("synchronous RMS", fit.get("synchronous_rms_mm", float("nan"))),
               ("RMS of every sample", fit.get("rms_mm", float("nan")))]
    ax.bar([n for n, _ in figures], [v * 1e6 for _, v in figures])
    ax.set_ylabel("nm")
    ax.grid(True, axis="y", alpha=0.3)
    report.figure(fig, "The fit's residuals: the probe noise per axis the intervals use, the RMS 3-D residual of the "
                       "angle means (form error repeating every revolution, which the model does not hold and which "
                       "does not move it), and the RMS 3-D residual of every sample.")

    rows = []
    for name, p in params.items():
        v, s = p["value"], p["sigma"]
        if name.endswith("_mm"):
            rows.append([name, f"{v:.6f} mm", f"{s * 1e6:.2f} nm", f"{v - 3 * s:.6f} .. {v + 3 * s:.6f} mm"])
        else:
            a, sa = v * ARCSEC_PER_RAD, s * ARCSEC_PER_RAD
            rows.append([name, f"{v:.3e} ({a:.3f} arcsec)", f"{sa:.3f} arcsec",
                         f"{a - 3 * sa:.3f} .. {a + 3 * sa:.3f} arcsec"])
    report.table("The model's parameters (o: O1 as the analyser sees it; a: the spindle axis; e, w: the tool line "
                 "off the axis at the gauge line, and its direction; a and w in small-angle arc-seconds)",
                 ["parameter", "value", "1-sigma", "3-sigma interval"], rows)
    rows = []
    for p in per:
        rows.append([fmt(p["phi_deg"], 1), f"{fmt(p['theta_e_arcsec'], 3)} +- {fmt(p.get('theta_e_sigma_arcsec', 0), 3)}",
                     f"{fmt(p['d_e_mm'] * 1000, 4)} +- {fmt(p.get('d_e_sigma_mm', 0) * 1000, 4)}"]
                    + [fmt(v * 1000, 4) for v in p["tool_tip_error_mm"]])
    report.table("Per spindle angle", ["phi (deg)", "theta_e (arcsec)", "d_e (um)", "tip x (um)", "tip y (um)",
                                       "tip z (um)"], rows)


METHODS = {"rigidity": ("AC-axis rigidity (M3)", rigidity), "gantry": ("gantry frames (M2)", gantry),
           "spindle": ("spindle tool axis (M4)", spindle)}


def main(argv):
    if len(argv) != 4 or argv[1] not in METHODS:
        print("usage: trueaxis_report.py rigidity|gantry|spindle OUT.json DIR", file=sys.stderr)
        return 2
    title, draw = METHODS[argv[1]]
    with open(argv[2], encoding="utf-8") as f:
        data = json.load(f)
    # Figures the module computed beyond OUT.json's fixed keys, written beside
    # the report by trueaxis-calibrate.
    extras = os.path.join(argv[3], "module_figures.json")
    if os.path.exists(extras):
        with open(extras, encoding="utf-8") as f:
            data.update(json.load(f))
    report = Report(argv[3], f"trueaxis report: {title}")
    draw(data, report)
    report.write()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
