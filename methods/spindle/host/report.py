"""The report of `trueaxis-calibrate spindle` (M4): theta_e, d_e and the
tool-tip error over a revolution with their 1-sigma, the tip's path, the fit's
residuals, and the parameter and per-angle tables.
"""
import math

from page import fmt, plt

TITLE = "spindle tool axis (M4)"


ARCSEC_PER_RAD = 180.0 * 3600.0 / math.pi


STYLES = ["-", "--", ":"]  # distinct, so that equal sigmas (x and y) do not hide one another


def with_sigma(x, series, unit, sigma_unit, sigma_scale):
    """Curves over x with their 1-sigma bands (top), and the 1-sigma itself
    (bottom: a band far narrower than the curve is lost at the curve's scale;
    the top panel then says so and how wide it is). series: [(label, values,
    sigmas), ...] already in `unit`."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5.0), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    widest = 0.0
    span = 0.0
    for k, (label, y, s) in enumerate(series):
        style = STYLES[k % len(STYLES)]
        top.fill_between(x, [a - b for a, b in zip(y, s)], [a + b for a, b in zip(y, s)], alpha=0.3)
        top.plot(x, y, style, label=label)
        bottom.plot(x, [v * sigma_scale for v in s], style, linewidth=2.2 - 0.6 * k, label=f"{label} 1-sigma")
        widest = max([widest] + [2 * abs(v) for v in s])
        span = max([span] + [abs(v) for v in y])
    if span > 0 and widest < 0.02 * span:
        top.text(0.01, 0.02, f"1-sigma bands narrower than the lines (at most +-{widest / 2 * sigma_scale:.3g} "
                 f"{sigma_unit}): see below", transform=top.transAxes, fontsize=8)
    top.set_ylabel(unit)
    # The sigma from 0 up, in plain numbers: a constant sigma is a flat line, not an offset axis at 1e-13.
    largest = max([0.0] + [v * sigma_scale for _, _, s in series for v in s])
    bottom.set_ylim(0.0, largest * 1.3 if largest > 0 else 1.0)
    bottom.ticklabel_format(axis="y", style="plain", useOffset=False)
    bottom.set_ylabel(sigma_unit)
    bottom.set_xlabel("spindle angle phi (deg, M19 zero, M03 positive)")
    bottom.set_xlim(0, 360)
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, ncol=3, loc="upper right")
    return fig


def draw(data, report):
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
        tip_sigma = p.get("tool_tip_error_sigma_mm", [float("nan")] * 3)
        rows.append([fmt(p["phi_deg"], 1), f"{fmt(p['theta_e_arcsec'], 3)} +- {fmt(p.get('theta_e_sigma_arcsec', 0), 3)}",
                     f"{fmt(p['d_e_mm'] * 1000, 4)} +- {fmt(p.get('d_e_sigma_mm', 0) * 1000, 4)}"]
                    + [f"{fmt(v * 1000, 4)} +- {fmt(e * 1000, 4)}" for v, e in zip(p["tool_tip_error_mm"], tip_sigma)])
    report.table("Per spindle angle (each figure +- its 1-sigma)",
                 ["phi (deg)", "theta_e (arcsec)", "d_e (um)", "tip x (um)", "tip y (um)", "tip z (um)"], rows)
