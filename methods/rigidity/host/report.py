"""The report of `trueaxis-calibrate rigidity` (M3): the rigidity figure with
its 1-sigma band, the rotation vector's components, the A positioning error
with its 1-sigma, the C-circle RMS with its 1-sigma against the RMS the ball
noise alone would give, and the per-pose table (every figure with its unit and
its sigma).

A pose's C-circle RMS within 3 sigma of its noise floor is marked "noise": it
measures the instrument, not the machine (docs/GUIDE.md "M3: what the C-circle
RMS means").
"""
from page import fmt, plt

TITLE = "AC-axis rigidity (M3)"


def noise_dominated(p):
    """The C-circle RMS is within 3 sigma of what the ball noise alone gives."""
    return p["c_circle_rms_mm"] <= p["c_circle_rms_noise_floor_mm"] + 3.0 * p["c_circle_rms_sigma_mm"]


def draw(data, report):
    poses = data["poses"]
    a = [p["a_deg"] for p in poses]
    r = [p["rigidity_arcsec"] for p in poses]
    rs = [p["rigidity_sigma_arcsec"] for p in poses]
    worst = max(range(len(poses)), key=lambda i: r[i])
    worst_rms = max(poses, key=lambda p: p["c_circle_rms_mm"])
    noisy = [p for p in poses if noise_dominated(p)]
    axis = data["a_axis"]
    ball_noise = data.get("ball_noise_mm", float("nan"))
    report.summary([
        ("A poses", str(len(poses))),
        ("largest rigidity figure", f"{fmt(r[worst], 2)} +- {fmt(rs[worst], 2)} arcsec (1 sigma) at A = {fmt(a[worst], 3)} deg"),
        ("A axis point (mm)", ", ".join(fmt(v, 4) for v in axis["point_mm"])),
        ("A axis direction", ", ".join(fmt(v, 8) for v in axis["direction"])),
        ("C-to-A offset", f"{fmt(data.get('c_to_a_offset_mm', float('nan')), 4)} mm"),
        ("C-to-A squareness", f"{fmt(data.get('c_to_a_squareness_arcsec', float('nan')), 2)} arcsec"),
        ("largest C-circle RMS", f"{fmt(worst_rms['c_circle_rms_mm'] * 1000, 3)} +- "
                                 f"{fmt(worst_rms['c_circle_rms_sigma_mm'] * 1000, 3)} um (1 sigma); noise alone "
                                 f"{fmt(worst_rms['c_circle_rms_noise_floor_mm'] * 1000, 3)} um"),
        ("C circles at the noise floor", f"{len(noisy)} of {len(poses)} poses (RMS within 3 sigma of the RMS the "
                                         f"stated ball noise of {fmt(ball_noise * 1000, 3)} um alone gives: "
                                         "instrument noise, not machine geometry)"),
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
    ax.errorbar(a, [p["a_positioning_error_arcsec"] for p in poses],
                yerr=[p["a_positioning_error_sigma_arcsec"] for p in poses], marker="o", capsize=3)
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("arcsec")
    ax.grid(True, alpha=0.3)
    report.figure(fig, "A-axis positioning error: the actual turn from the reference pose minus the commanded "
                       "difference in A (positive in the direction of increasing A), with 1-sigma error bars "
                       "from the circle fits' own scatter (0 at the reference pose, by definition).")

    fig, ax = plt.subplots(figsize=(7, 3.2))
    x = list(range(len(poses)))
    ax.bar(x, [p["c_circle_rms_mm"] * 1000 for p in poses],
           yerr=[p["c_circle_rms_sigma_mm"] * 1000 for p in poses], capsize=3, label="C-circle RMS, 1 sigma")
    ax.plot(x, [p["c_circle_rms_noise_floor_mm"] * 1000 for p in poses], "k_", markersize=28, mew=2,
            label="RMS the ball noise alone gives")
    ax.set_xticks(x)
    ax.set_xticklabels([str(round(v, 3)) + (" (noise)" if noise_dominated(p) else "") for v, p in zip(a, poses)],
                       fontsize=8)
    ax.set_xlabel("commanded A (deg)")
    ax.set_ylabel("um")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    report.figure(fig, "C-circle residuals: RMS 3-D distance of each pose's ball positions from its fitted circle, "
                       "with its 1-sigma, against the RMS the stated ball noise alone would give at that sample "
                       "count (the black mark). A pose marked (noise) is within 3 sigma of that floor: its RMS "
                       "is the instrument's noise and says nothing about the machine's geometry.")

    rows = []
    for p in poses:
        rows.append([fmt(p["a_deg"], 3)] + [fmt(v, 2) for v in p["rotation_vector_arcsec"]]
                    + [fmt(v, 2) for v in p["rotation_vector_sigma_arcsec"]]
                    + [fmt(p["rigidity_arcsec"], 2), fmt(p["rigidity_sigma_arcsec"], 2),
                       fmt(p["a_positioning_error_arcsec"], 2), fmt(p["a_positioning_error_sigma_arcsec"], 2),
                       fmt(p["c_circle_rms_mm"] * 1000, 3), fmt(p["c_circle_rms_sigma_mm"] * 1000, 3),
                       fmt(p["c_circle_rms_noise_floor_mm"] * 1000, 3),
                       "noise" if noise_dominated(p) else "geometry"])
    report.table("Per pose (sigmas are 1 sigma)",
                 ["A (deg)", "rx (arcsec)", "ry (arcsec)", "rz (arcsec)", "rx sigma (arcsec)",
                  "ry sigma (arcsec)", "rz sigma (arcsec)", "rigidity (arcsec)", "rigidity sigma (arcsec)",
                  "A error (arcsec)", "A error sigma (arcsec)", "C rms (um)", "C rms sigma (um)",
                  "C rms noise alone (um)", "C rms is"], rows)
