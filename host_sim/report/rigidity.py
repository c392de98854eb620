"""The report of `trueaxis-calibrate rigidity` (M3): the rigidity figure with
its 1-sigma band, the rotation vector's components, the A positioning error
and the C-circle residuals against A, and the per-pose table.
"""
from page import fmt, plt

TITLE = "AC-axis rigidity (M3)"


def draw(data, report):
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
