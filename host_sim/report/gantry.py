"""The report of `trueaxis-calibrate gantry` (M2): the frames' origin and
orientation uncertainties, each sub-machine's squareness, A-to-C offset and
angle, straightness and circle residuals, the machine's own figures, and the
frames and global_T_sub tables.
"""
from page import fmt, plt

TITLE = "gantry frames (M2)"


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


def draw(data, report):
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
