"""The report of `trueaxis-calibrate gantry` (M2): the frames' origin and
orientation uncertainties, each sub-machine's squareness, A-to-C offset and
angle with their 1-sigma, straightness and circle residuals, the machine's own
figures (peak-to-valley beside the noise floor the tracker's noise alone would
give, and the noise-corrected form error with its 1-sigma), and the frames,
figures and global_T_sub tables, every column with its unit and sigma.

A figure the module could not give (an older OUT.json without the key, or -1:
a stored table from before the figure) is drawn as nothing and written "n/a".
"""
import math

from page import fmt, plt

TITLE = "gantry frames (M2)"
NAN = float("nan")


def known(v):
    """A figure, or NaN where OUT.json lacks it or the module says "not stored" (-1)."""
    return NAN if v is None or v < 0 else v


def one(v, scale, digits):
    """A figure in the display unit (scale), or 'n/a' where it is not known."""
    v = known(v)
    return "n/a" if math.isnan(v) else fmt(v * scale, digits)


def pm(v, s, scale, digits):
    """'v +- s' in the display unit (scale); v may be negative (an angle), NaN or None: not
    known; s a sigma (None or -1: not known)."""
    v, s = NAN if v is None else v, known(s)
    if math.isnan(s):
        return "n/a" if math.isnan(v) else f"{fmt(v * scale, digits)} +- n/a"
    return f"{fmt(v * scale, digits)} +- {fmt(s * scale, digits)}"


def errors(values, scale=1.0):
    """Error bars of sigmas (not known: none), or None where none is known
    (matplotlib refuses error bars that are all NaN)."""
    e = [known(v) * scale for v in values]
    return None if all(math.isnan(v) for v in e) else e


def grouped_bars(ax, labels, series, ylabel, sigmas=None, sigma_scale=1.0):
    """Bars of several series side by side per label; series: [(name, values), ...],
    sigmas: their 1-sigma per series (error bars, times sigma_scale), or None. The legend stands
    outside the axes (right of them), so it never covers a bar."""
    width = 0.8 / max(len(series), 1)
    for k, (name, values) in enumerate(series):
        yerr = None if sigmas is None else errors(sigmas[k], sigma_scale)
        ax.bar([i + (k - (len(series) - 1) / 2) * width for i in range(len(labels))], values, width, label=name,
               yerr=yerr, capsize=3 if yerr is not None else 0, error_kw={"elinewidth": 0.9})
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels)
    ax.set_ylabel(ylabel)
    ax.axhline(0.0, color="black", linewidth=0.6)
    ax.grid(True, axis="y", alpha=0.3)
    if len(series) > 1:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)


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
        ("bed flatness (peak-to-valley)", f"{fmt(glob['bed_flatness_mm'] * 1000, 1)} um "
         f"(noise floor {one(glob.get('bed_flatness_noise_floor_mm'), 1000, 1)} um)"),
        ("bed form error (noise-corrected RMS, 1 sigma)",
         f"{pm(known(glob.get('bed_form_error_mm')), glob.get('bed_form_error_sigma_mm'), 1000, 1)} um"),
        ("gantry straightness (peak-to-valley)", f"{fmt(glob['gantry_straightness_mm'] * 1000, 1)} um "
         f"(noise floor {one(glob.get('gantry_straightness_noise_floor_mm'), 1000, 1)} um)"),
        ("gantry form error (noise-corrected RMS, 1 sigma)",
         f"{pm(known(glob.get('gantry_form_error_mm')), glob.get('gantry_form_error_sigma_mm'), 1000, 1)} um"),
    ]
    if worst is not None:
        rows.append(("largest origin 1-sigma", f"{fmt(worst['origin_sigma_mm'] * 1000, 1)} um (sp{worst['id']})"))
    if square:
        v, sid, pair = max(square)
        sub = next(x for x in subs if x["id"] == sid)
        sigma = sub.get("squareness_sigma_arcsec", {}).get(pair)
        rows.append(("largest squareness error", f"{pm(v, sigma, 1, 1)} arcsec (1 sigma; sp{sid}, {pair})"))
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
    pairs = ("xy", "yz", "zx")
    grouped_bars(ax, labels, [(pair, [s["squareness_arcsec"][pair] for s in subs]) for pair in pairs], "arcsec",
                 [[s.get("squareness_sigma_arcsec", {}).get(pair) for s in subs] for pair in pairs])
    report.figure(fig, "Squareness of each sub-machine's linear axes: the measured angle of each pair minus 90 deg, "
                       "before orthonormalisation; error bars 1 sigma (from the passes' fits).")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(8, 3.2))
    ax1.bar(labels, [s["a_c_offset_mm"] * 1000 for s in subs],
            yerr=errors([s.get("a_c_offset_sigma_mm") for s in subs], 1000), capsize=3)
    ax1.set_ylabel("um")
    ax1.set_title("A-to-C offset", fontsize=10)
    ax1.grid(True, axis="y", alpha=0.3)
    ax2.bar(labels, [(s["a_c_angle_deg"] - 90.0) * 3600.0 for s in subs],
            yerr=errors([s.get("a_c_angle_sigma_deg") for s in subs], 3600.0), capsize=3)
    ax2.axhline(0.0, color="black", linewidth=0.6)
    ax2.set_ylabel("arcsec")
    ax2.set_title("A-to-C angle minus 90 deg", fontsize=10)
    ax2.grid(True, axis="y", alpha=0.3)
    report.figure(fig, "The head's A and C axes: the length of their common perpendicular, and the angle between "
                       "their directions minus 90 deg; error bars 1 sigma (from the circles' fits; the offset's "
                       "is that of the signed offset, so an offset within it of 0 may be none).")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.4))
    grouped_bars(ax1, labels, [(n, [fig_of(s, "straightness_mm", nan3)[k] * 1000 for s in subs])
                               for k, n in enumerate("xyz")], "um")
    ax1.set_title("straightness, worst pass (peak-to-valley)", fontsize=10)
    grouped_bars(ax2, labels, [(n, [fig_of(s, key, float("nan")) * 1000 for s in subs])
                               for n, key in (("C", "c_circle_rms_mm"), ("A", "a_circle_rms_mm"))], "um")
    ax2.set_title("circle residuals (RMS)", fontsize=10)
    report.figure(fig, "Each sub-machine's linear axes (twice the largest distance of a pass from its fitted line, "
                       "worst pass) and its C and A circles (RMS 3-D distance of the points from the fitted circle).")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.2))
    names = ["bed", "gantry"]
    grouped_bars(ax1, names, [("peak-to-valley", [glob["bed_flatness_mm"] * 1000,
                                                   glob["gantry_straightness_mm"] * 1000]),
                              ("noise floor", [known(glob.get("bed_flatness_noise_floor_mm")) * 1000,
                                               known(glob.get("gantry_straightness_noise_floor_mm")) * 1000])], "um")
    ax1.set_title("flatness, straightness (peak-to-valley)", fontsize=10)
    grouped_bars(ax2, names, [("form error", [known(glob.get("bed_form_error_mm")) * 1000,
                                              known(glob.get("gantry_form_error_mm")) * 1000])], "um",
                 [[glob.get("bed_form_error_sigma_mm"), glob.get("gantry_form_error_sigma_mm")]], 1000.0)
    ax2.set_title("noise-corrected form error (RMS, +-1 sigma)", fontsize=10)
    report.figure(fig, "The machine's own figures: bed flatness (the spread of the pads' distances from their fitted "
                       "plane) and gantry straightness (twice the largest distance of a gantry pass from its fitted "
                       "line, worst pass) beside the peak-to-valley the tracker's stated noise alone would give at "
                       "those point counts (the noise floor: a figure near it is noise, not geometry); right, the "
                       "form error with the noise taken out (RMS) and its 1 sigma: 0 within 3 sigma is a flat bed, "
                       "a straight gantry.")

    def vec(v, digits):
        return ", ".join(fmt(x, digits) for x in v)

    g_sigma = data.get("global_angle_sigma_arcsec", [NAN] * 3)
    table = [["global (tracker frame)", vec(glob["origin_mm"], 4),
              fmt(data.get("global_origin_sigma_mm", NAN) * 1000, 1), "", vec(glob["x"], 8), vec(glob["y"], 8),
              vec(glob["z"], 8), vec(g_sigma, 2)]]
    for s in subs:
        a_sigma = s.get("angle_sigma_arcsec", fig_of(s, "angle_sigma_arcsec", nan3))
        table.append([f"sp{s['id']} (global frame)", vec(s["origin_mm"], 4), fmt(s["origin_sigma_mm"] * 1000, 1),
                      s["master_axis"], vec(s["x"], 8), vec(s["y"], 8), vec(s["z"], 8),
                      ", ".join("n/a" if math.isnan(known(v)) else fmt(v, 2) for v in a_sigma)])
    report.table("Frames", ["frame", "origin (mm)", "origin 1-sigma, radial (um)", "master",
                            "x axis (unit vector)", "y axis (unit vector)", "z axis (unit vector)",
                            "axes' 1-sigma about x, y, z (arcsec)"], table)
    figures = []
    for s in subs:
        sq, sq_sigma = s["squareness_arcsec"], s.get("squareness_sigma_arcsec", {})
        figures.append([f"sp{s['id']}"] + [pm(sq[p], sq_sigma.get(p), 1, 1) for p in ("xy", "yz", "zx")]
                       + [pm(s["a_c_offset_mm"], s.get("a_c_offset_sigma_mm"), 1000, 1),
                          pm(s["a_c_angle_deg"], s.get("a_c_angle_sigma_deg"), 1, 5)])
    report.table("Sub-machine figures (value +- 1 sigma)",
                 ["sub-machine", "squareness xy (arcsec)", "squareness yz (arcsec)", "squareness zx (arcsec)",
                  "A-to-C offset (um)", "A-to-C angle (deg)"], figures)
    report.table("Flatness and straightness (um; noise floor: the peak-to-valley of the tracker's noise alone)",
                 ["figure", "peak-to-valley (um)", "noise floor (um)", "form error, noise-corrected RMS (um, +- 1 sigma)"],
                 [["bed flatness", fmt(glob["bed_flatness_mm"] * 1000, 1),
                   one(glob.get("bed_flatness_noise_floor_mm"), 1000, 1),
                   pm(known(glob.get("bed_form_error_mm")), glob.get("bed_form_error_sigma_mm"), 1000, 1)],
                  ["gantry straightness", fmt(glob["gantry_straightness_mm"] * 1000, 1),
                   one(glob.get("gantry_straightness_noise_floor_mm"), 1000, 1),
                   pm(known(glob.get("gantry_form_error_mm")), glob.get("gantry_form_error_sigma_mm"), 1000, 1)]])
    rows = []
    for s in subs:
        t = s["global_T_sub"]
        rows.append([f"sp{s['id']}"] + [" ".join(fmt(v, 9 if c < 3 else 4) for c, v in enumerate(t[4 * r:4 * r + 4]))
                                        for r in range(3)])
    report.table("global_T_sub (sub-machine coordinates into the global frame; rows 1-3, the last is 0 0 0 1; "
                 "their 1-sigma: the Frames table)",
                 ["sub-machine", "row 1 (R unitless, t mm)", "row 2 (R unitless, t mm)", "row 3 (R unitless, t mm)"],
                 rows)
