#!/usr/bin/python3
"""M4 identifiability study (issue 7): which parameters of the seed's screw model of
the tool axis (docs/METHODS.md M4, seed 002) can a spindle error analyser separate, with
balls at one and at two heights, and the identifiable parameterisation the firmware
fits. Deterministic; prints every number docs/M4_IDENTIFIABILITY.md quotes.

    /usr/bin/python3 tools/m4_identifiability.py

Conventions (docs/INTERFACE.md "M4 spindle"):
  * CS1: origin O1 (upper bearing seat centre), axes parallel to the machine's.
  * The analyser frame CSM is CS1 translated: p_M = p_1 + o,  o = O1 written in CSM.
  * The seed's nominal spindle direction u = (cos alpha, cos beta, cos gamma) points from
    the lower bearing to the upper one (A2 = ... - h u), i.e. away from the tool.
    a = -u is the spindle axis pointing towards the tool.
  * phi grows in the M03 sense: right-handed about a (the seed's A1(phi) turns
    right-handed about u; the two differ by the sign of phi only).
  * Everything is computed in long double (80-bit) so that central differences
    resolve sensitivities down to ~1e-12 of the largest one.
"""
import numpy as np

F = np.longdouble
ARCSEC = F(np.pi) / F(180 * 3600)
UM = F("1e-3")  # mm

# ---------------------------------------------------------------- nominal machine
H_NOM = F(300)          # bearing_spacing_mm
L2_NOM = F(20)          # lower bearing to holder top (mm)
L3_NOM = F(30)          # holder length (mm); G = h + l2 + l3 = 350
G_NOM = H_NOM + L2_NOM + L3_NOM   # gauge_from_upper_bearing_mm
H1_NOM = F(5)           # collet lower face below the holder face (mm)
LCH_NOM = F(40)         # collet length (mm)
BALLS = (F(50), F(150))  # ball_1_mm, ball_2_mm (from the gauge line)
TOOL_LENGTHS = (F(100), F(250))  # tool lengths NOT used in the fit (interp., extrap.)

# ------------------------------------------------------------- seed parameters
SEED_NAMES = ["r1", "theta1", "r2", "theta2", "alpha", "beta", "h", "l2", "l3",
              "Delta3", "rho1", "psi1", "rho2", "psi2", "h1", "l_chuck",
              "o_x", "o_y", "o_z"]
SEED_UNITS = ["mm", "rad", "mm", "rad", "rad", "rad", "mm", "mm", "mm",
              "mm", "mm", "rad", "mm", "rad", "mm", "mm", "mm", "mm", "mm"]
# prior range of each parameter (what is plausible before measuring); used to scale
# the Fisher information so that an eigenvalue lambda means: along that direction the
# data shrink the prior range to 1/sqrt(lambda) of itself.
PRIOR = np.array([5 * UM, np.pi, 5 * UM, np.pi, 50 * ARCSEC, 50 * ARCSEC,
                  10 * UM, 10 * UM, 10 * UM, 10 * UM, 5 * UM, np.pi, 5 * UM, np.pi,
                  10 * UM, 10 * UM, F(1), F(1), F(1)], dtype=F)


def deg(x):
    return F(x) * F(np.pi) / F(180)


# realistic true values: run-outs of a few um, tilt of tens of arcsec
TRUE = np.array([
    2.0 * UM, deg(40),               # r1, theta1
    4.0 * UM, deg(160),              # r2, theta2
    deg(90) - 20 * ARCSEC,           # alpha: cos(alpha) = +20" (u tilts to +x)
    deg(90) + 35 * ARCSEC,           # beta:  cos(beta)  = -35"
    H_NOM + 3 * UM, L2_NOM - 2 * UM, L3_NOM + 1 * UM,
    3.0 * UM,                        # Delta3
    3.0 * UM, deg(100),              # rho1, psi1 (collet lower end)
    2.0 * UM, deg(250),              # rho2, psi2 (collet upper end)
    H1_NOM + 2 * UM, LCH_NOM - 4 * UM,
    F("0.0123"), F("-0.0087"), F("400.0051"),  # O1 in the analyser frame
], dtype=F)


def cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]], dtype=F)


def norm(v):
    return np.sqrt(np.sum(v * v))


def rot(axis, phi):
    """R = I + sin(phi)[s]x + (1 - cos(phi))[s]x^2 (the seed's formula), |s| = 1."""
    s = axis
    K = np.array([[0, -s[2], s[1]], [s[2], 0, -s[0]], [-s[1], s[0], 0]], dtype=F)
    return np.eye(3, dtype=F) + np.sin(phi) * K + (1 - np.cos(phi)) * (K @ K)


# ------------------------------------------------------------------ seed model
def seed_body(p, depths):
    """The seed's geometry at phi = 0 in CS1: returns (u, points at the given depths
    below the gauge line along the tool, O4*, O4)."""
    (r1, t1, r2, t2, al, be, h, l2, l3, d3, rho1, psi1, rho2, psi2, h1, lch,
     ox, oy, oz) = p
    ca, cb = np.cos(al), np.cos(be)
    sg = np.sqrt(ca * ca + cb * cb)             # sin(gamma): 0/0 at u = Z exactly
    cg = np.sqrt(1 - sg * sg)
    u = np.array([ca, cb, cg], dtype=F)
    e1 = np.array([cb, -ca, F(0)], dtype=F) / sg
    e2 = np.array([ca * cg, cb * cg, -sg * sg], dtype=F) / sg   # = u x e1
    A1 = r1 * (np.cos(t1) * e1 + np.sin(t1) * e2)
    A2 = r2 * (np.cos(t2) * e1 + np.sin(t2) * e2) - h * u
    v = A2 - A1
    n = v / norm(v)                             # down the shaft
    Z3 = -n
    nP = cross(A1, v)                           # O1A1 x A1A2
    X3 = cross(-v, nP)
    X3 = X3 / norm(X3)
    Y3 = cross(Z3, X3)
    O3 = A1 + (h + l2 + l3 + d3) * n
    O4 = O3 + rho1 * np.cos(psi1) * X3 + rho1 * np.sin(psi1) * Y3 - h1 * Z3
    O4s = O3 + rho2 * np.cos(psi2) * X3 + rho2 * np.sin(psi2) * Y3 + (lch - h1) * Z3
    pts = []
    for b in depths:
        lcut = b - H1_NOM                       # ball / tip as built below the collet
        pts.append(O4s + (lch + lcut) / lch * (O4 - O4s))
    return u, pts, O4s, O4


def seed_samples(p, phis, balls=BALLS):
    u, pts, _, _ = seed_body(p, balls)
    a = -u
    o = p[16:19]
    out = np.empty((len(phis), len(balls), 3), dtype=F)
    for i, ph in enumerate(phis):
        R = rot(a, ph)
        for k, P in enumerate(pts):
            out[i, k] = o + R @ P
    return out.reshape(-1)


def seed_outputs(p, phis, L):
    """theta_e, d_e and the tool-tip error at tool length L, from the seed model."""
    u, (tip,), O4s, O4 = seed_body(p, [L])
    a = -u
    d0 = (O4 - O4s) / norm(O4 - O4s)
    res = []
    for ph in phis:
        R = rot(a, ph)
        res.append(screw_and_tip(R @ O4s, R @ d0, R @ tip, L))
    return np.array(res, dtype=F).reshape(-1)


def screw_and_tip(point, d, tip, L):
    """Ideal axis: through O1 (origin of CS1) along -Z. Both lines are in CS1; the
    analyser offset o translates both and cancels."""
    zi = np.array([0, 0, -1], dtype=F)
    c = cross(zi, d)
    sn = norm(c)
    theta = np.arctan2(sn, np.dot(zi, d))
    de = abs(np.dot(point, c)) / sn
    ideal_tip = (G_NOM + L) * zi
    return [theta, de, *(tip - ideal_tip)]


# ------------------------------------------------------------- identifiable model
ID_NAMES = ["o_x", "o_y", "o_z", "a_x", "a_y", "e_x", "e_y", "w_x", "w_y"]
ID_UNITS = ["mm", "mm", "mm", "rad", "rad", "mm", "mm", "rad", "rad"]


def id_vectors(q):
    ox, oy, oz, ax, ay, ex, ey, wx, wy = q
    a = np.array([ax, ay, -np.sqrt(1 - ax * ax - ay * ay)], dtype=F)
    e = np.array([ex, ey, -(ax * ex + ay * ey) / a[2]], dtype=F)   # e . a = 0
    w = np.array([wx, wy, -(ax * wx + ay * wy) / a[2]], dtype=F)   # w . a = 0
    return np.array([ox, oy, oz], dtype=F), a, e, w


def id_samples(q, phis, balls=BALLS, G=G_NOM):
    """M_k(phi) = o + R_a(phi) (G a + e + b_k (a + w))."""
    o, a, e, w = id_vectors(q)
    out = np.empty((len(phis), len(balls), 3), dtype=F)
    for i, ph in enumerate(phis):
        R = rot(a, ph)
        for k, b in enumerate(balls):
            out[i, k] = o + R @ (G * a + e + b * (a + w))
    return out.reshape(-1)


def id_outputs(q, phis, L, G=G_NOM):
    o, a, e, w = id_vectors(q)
    d0 = (a + w) / norm(a + w)
    res = []
    for ph in phis:
        R = rot(a, ph)
        res.append(screw_and_tip(R @ (G * a + e), R @ d0,
                                 R @ (G * a + e + L * (a + w)), L))
    return np.array(res, dtype=F).reshape(-1)


def seed_to_id(p):
    """The identifiable combination of the seed parameters: exact map, by geometry."""
    u, (B1, B2), _, _ = seed_body(p, BALLS)
    a = -u
    d = B2 - B1
    w = d / np.dot(d, a) - a                  # tool direction a + w, w . a = 0
    # the gauge plane as the data define it: b1 above ball 1 along a (the nominal
    # plane G is off by the unseen axial error delta; the tool line is taken there)
    e = (B1 - BALLS[0] * (a + w))
    e = e - np.dot(e, a) * a
    # axial: ball 1 sits at depth G + b1 + delta below O1; the data see only
    # o + (G + b1 + delta) a, so o absorbs delta a (all axial length errors)
    delta = np.dot(B1, a) - G_NOM - BALLS[0]
    oz = p[18] + delta * a[2]
    ox = p[16] + delta * a[0]
    oy = p[17] + delta * a[1]
    return np.array([ox, oy, oz, a[0], a[1], e[0], e[1], w[0], w[1]], dtype=F)


# ----------------------------------------------------------------------- tools
def jac(f, x, steps):
    cols = []
    for j in range(len(x)):
        xp, xm = x.copy(), x.copy()
        xp[j] += steps[j]
        xm[j] -= steps[j]
        cols.append((f(xp) - f(xm)) / (2 * steps[j]))
    return np.array(cols, dtype=F).T


def seed_steps():
    return np.array([F("1e-6") if u == "mm" else F("1e-6") for u in SEED_UNITS], dtype=F)


def id_steps():
    return np.array([F("1e-6")] * 9, dtype=F)


def phis_deg(step_deg, revs=1):
    n = int(round(360 * revs / step_deg))
    return [deg(step_deg * i) for i in range(n)]


def svd64(M):
    return np.linalg.svd(np.array(M, dtype=np.float64), compute_uv=True)


def fmt(x, n=3):
    return f"{float(x):.{n}e}"


def crb(J, sigma):
    Fi = (J.T @ J) / sigma ** 2
    C = np.linalg.inv(np.array(Fi, dtype=np.float64))
    return Fi, C


SIG_PROBE = 15e-6   # mm, 1 sigma per axis
SIG_FORM = 50e-6    # mm, RMS of the ball form error seen in the centre (harmonics >= 2)


def main():
    np.set_printoptions(linewidth=140)
    phis = phis_deg(5)
    N = len(phis)
    print("M4 identifiability study (tools/m4_identifiability.py)")
    print(f"samples: phi every 5 deg over one revolution, N = {N} angles; balls at "
          f"{float(BALLS[0]):g} and {float(BALLS[1]):g} mm below the gauge line, "
          f"gauge line {float(G_NOM):g} mm below O1, h = {float(H_NOM):g} mm")
    print(f"noise: probe {SIG_PROBE*1e6:g} nm per axis, ball form error {SIG_FORM*1e6:g} nm RMS")

    # ------------------------------------------------------------- 1. seed model
    print("\n[1] seed model at the true values (phi = 0)")
    u, (B1, B2), O4s, O4 = seed_body(TRUE, BALLS)
    print("  u =", [fmt(x, 6) for x in u])
    q_true = seed_to_id(TRUE)
    for nme, un, v in zip(ID_NAMES, ID_UNITS, q_true):
        extra = f" = {float(v / ARCSEC):.3f} arcsec" if un == "rad" else f" = {float(v*1000):.4f} um"
        print(f"  {nme:4s} = {float(v): .9e} {un}{extra}")

    # ------------------------------------------- 2. Fisher information of the seed
    print("\n[2] seed parameters: Jacobian by central differences, Fisher information")
    Js = {}
    for label, balls in (("two heights", BALLS), ("one height (ball 1)", BALLS[:1]),
                         ("one height (ball 2)", BALLS[1:])):
        J = jac(lambda p: seed_samples(p, phis, balls), TRUE.copy(), seed_steps())
        Js[label] = J
        # prior-scaled Fisher information: eigenvalue = (prior range / CRB sigma)^2
        JD = J * PRIOR[None, :]
        s = np.linalg.svd(np.array(JD, dtype=np.float64), compute_uv=False)
        lam = s ** 2 / SIG_PROBE ** 2
        Jn = J / np.sqrt(np.sum(J * J, axis=0))[None, :]
        sn = np.linalg.svd(np.array(Jn, dtype=np.float64), compute_uv=False)
        print(f"  {label}: {J.shape[0]} observations x {J.shape[1]} parameters")
        print("    singular values of J with unit-norm columns (relative):")
        print("     ", " ".join(f"{x/sn[0]:.1e}" for x in sn))
        print("    eigenvalues of the prior-scaled Fisher information (prior range / sigma)^2:")
        print("     ", " ".join(f"{x:.1e}" for x in lam))
        r_num = int(np.sum(sn / sn[0] > 1e-9))
        r_id = int(np.sum(lam > 100.0))
        print(f"    numerical rank (relative tol 1e-9 on unit-norm J) = {r_num}; "
              f"identified (sigma < prior/10) = {r_id} of {J.shape[1]}")
        kept = sn[:r_num]
        print(f"    condition number of J (unit-norm columns) over its numerical rank: "
              f"{kept[0]/kept[-1]:.2e}; of the Fisher information: {(kept[0]/kept[-1])**2:.2e}")
        print(f"    over the {r_id} identified directions: cond(J, unit-norm columns) = {sn[0]/sn[r_id-1]:.1f}, "
              f"cond(Fisher) = {(sn[0]/sn[r_id-1])**2:.0f}; gap to the next: {sn[r_id-1]/sn[r_id]:.1e} in J, "
              f"{lam[r_id-1]/lam[r_id]:.1e} in the prior-scaled Fisher information")
        if label == "two heights":
            _, _, Vt = np.linalg.svd(np.array(JD, dtype=np.float64))
            for k in (9, 10):
                v = Vt[k] / np.max(np.abs(Vt[k]))
                print(f"    direction {k+1} (eigenvalue {lam[k]:.1e}, prior-scaled, largest = 1): "
                      + " ".join(f"{n}:{x:+.2f}" for n, x in zip(SEED_NAMES, v) if abs(x) > 0.05))
    # the seed's own 13 (our reading: r1 r2 theta1 theta2 alpha beta [gamma dependent]
    # rho1 rho2 h1 Delta3 + the analyser offset; collet phases fixed, lengths nominal)
    sub = [SEED_NAMES.index(n) for n in ["r1", "theta1", "r2", "theta2", "alpha", "beta",
                                         "rho1", "rho2", "h1", "Delta3", "o_x", "o_y", "o_z"]]
    JD = np.array(Js["two heights"][:, sub] * PRIOR[sub][None, :], dtype=np.float64)
    lam = np.linalg.svd(JD, compute_uv=False) ** 2 / SIG_PROBE ** 2
    print("  the seed's 13 parameters (r1 theta1 r2 theta2 alpha beta rho1 rho2 h1 Delta3 o_x o_y o_z),"
          " two heights: prior-scaled eigenvalues")
    print("     ", " ".join(f"{x:.1e}" for x in lam), f"-> identified {int(np.sum(lam > 100))} of 13")
    # the seed's frames are singular at the nominal geometry
    pp, pm = TRUE.copy(), TRUE.copy()
    pp[4] = pm[4] = deg(90)
    pp[5], pm[5] = deg(90) - F("1e-12"), deg(90) + F("1e-12")
    jump = seed_body(pp, BALLS)[1][0] - seed_body(pm, BALLS)[1][0]
    with np.errstate(all="ignore"):
        p1 = TRUE.copy()
        p1[0] = F(0)
        u1 = seed_body(p1, BALLS)[1][0]
    print(f"  seed frames: u tilted by +1e-12 rad and -1e-12 rad about X from Z (the nominal): ball 1 moves"
          f" by {float(norm(jump))*1e3:.3f} um (e1 = (cos beta, -cos alpha, 0)/sin gamma flips; 0/0 at u = Z);")
    print(f"  at r1 = 0 ball 1 = {[float(x) for x in u1]} (X3 from O1A1 x A1A2 = 0)")
    print(f"  d(e_x)/d(alpha) = {float(jac(seed_to_id, TRUE.copy(), seed_steps())[5, 4]):.2f} mm/rad: the run-out"
          " phases are counted from e1, which turns with the azimuth of the tilt (1/sin gamma)")

    # the data depend on the seed parameters only through seed_to_id: J_seed = J_id M
    print("\n[3] the seed Jacobian factors through the 9 identifiable combinations")
    M = jac(seed_to_id, TRUE.copy(), seed_steps())     # 9 x 19
    for label, balls in (("two heights", BALLS), ("one height (ball 1)", BALLS[:1])):
        Jid = jac(lambda q: id_samples(q, phis, balls), q_true.copy(), id_steps())
        Jfac = Jid @ M
        J = Js[label]
        rel = np.max(np.abs(J - Jfac), axis=0) / np.max(np.abs(J), axis=0)
        print(f"  {label}: max |J_seed - J_id M| per column / max |J_seed| column:")
        print("    " + "  ".join(f"{n}:{float(x):.0e}" for n, x in zip(SEED_NAMES, rel)))
    # model residual: seed data against the identifiable model at seed_to_id
    r = seed_samples(TRUE, phis) - id_samples(q_true, phis)
    print(f"  seed samples minus identifiable-model samples at the mapped values: "
          f"max |r| = {float(np.max(np.abs(r)))*1e6:.3f} nm (noise {SIG_PROBE*1e6:g} nm)")
    # first-order closed form of the merge (complex numbers in the seed's e1, e2 plane)
    (r1, t1, r2, t2, al, be, h, l2, l3, d3, rho1, psi1, rho2, psi2, h1, lch) = [complex(float(x)) for x in TRUE[:16]]
    a1, a2 = r1 * np.exp(1j * t1.real), r2 * np.exp(1j * t2.real)
    c1 = rho1 * np.exp(1j * (t1.real + np.pi + psi1.real))
    c2 = rho2 * np.exp(1j * (t1.real + np.pi + psi2.real))
    Gn = float(G_NOM)
    e_c = a1 + (a2 - a1) * Gn / h + c1 + (c2 - c1) * h1 / lch
    w_c = (a2 - a1) / h + (c1 - c2) / lch
    ca, cb = np.cos(float(TRUE[4])), np.cos(float(TRUE[5]))
    sg = np.hypot(ca, cb)
    cg = np.sqrt(1 - sg * sg)
    E1 = np.array([cb, -ca, 0]) / sg
    E2 = np.array([ca * cg, cb * cg, -sg * sg]) / sg
    e_v = e_c.real * E1 + e_c.imag * E2
    w_v = w_c.real * E1 + w_c.imag * E2
    qq = np.array(q_true, dtype=np.float64)
    print(f"  first-order merge e = a1 + (a2 - a1) G/h + c1 + (c2 - c1) h1/l_chuck: ({e_v[0]*1e3:.4f}, {e_v[1]*1e3:.4f}) um"
          f" vs exact ({qq[5]*1e3:.4f}, {qq[6]*1e3:.4f}) um")
    print(f"  first-order merge w = (a2 - a1)/h + (c1 - c2)/l_chuck: ({w_v[0]/float(ARCSEC):.4f}, {w_v[1]/float(ARCSEC):.4f}) arcsec"
          f" vs exact ({qq[7]/float(ARCSEC):.4f}, {qq[8]/float(ARCSEC):.4f}) arcsec")
    # null space of M = what the data cannot see; show the merges column by column
    print("  d(identifiable)/d(seed) (M, rows = identifiable, units mm or rad per seed unit;"
          " |entry| < 1e-9 shown as .):")
    print("    " + " ".join(f"{n:>8s}" for n in SEED_NAMES))
    for i, nme in enumerate(ID_NAMES):
        row = []
        for j in range(len(SEED_NAMES)):
            x = float(M[i, j])
            row.append(f"{x:8.1e}" if abs(x) > 1e-9 else f"{'.':>8s}")
        print(f"  {nme:4s}" + " ".join(row))
    print(f"  rank of M = {np.linalg.matrix_rank(np.array(M*PRIOR[None,:], dtype=np.float64), tol=1e-12)}"
          f" -> null space of dimension {len(SEED_NAMES) - 9} (the combinations no analyser "
          f"data can see)")

    # --------------------------------------------------- 4. identifiable model
    print("\n[4] identifiable model (9 parameters): rank, condition, Cramer-Rao bounds")
    scale = np.array([1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-3, 1e-3, 1e-6, 1e-6])  # um, urad
    results = {}
    for label, balls in (("two heights", BALLS), ("one height (ball 1)", BALLS[:1])):
        Jid = np.array(jac(lambda q: id_samples(q, phis, balls), q_true.copy(), id_steps()),
                       dtype=np.float64)
        results[label] = Jid
        Js_ = Jid * scale[None, :]
        s = np.linalg.svd(Js_, compute_uv=False)
        sv = np.linalg.svd(Js_ / np.sqrt(np.sum(Js_ ** 2, axis=0))[None, :], compute_uv=False)
        ev = sv[::-1] ** 2
        print(f"  {label}: singular values of J (columns in um and urad):")
        print("    " + " ".join(f"{x:.3e}" for x in s))
        print(f"    rank (relative tol 1e-9) = {int(np.sum(s/s[0] > 1e-9))} of 9; cond(J) = "
              f"{s[0]/s[-1]:.3e}; cond(Fisher) = {(s[0]/s[-1])**2:.3e} (um, urad); "
              f"cond(Fisher, unit diagonal) = {ev[-1]/ev[0]:.3e}")
    Jid = results["two heights"]
    print("  Cramer-Rao 1-sigma, two heights, N = 72 angles:")
    print(f"    {'param':6s} {'true':>14s} {'sigma (15 nm)':>16s} {'sigma (52 nm)':>16s}")
    sig_white = np.hypot(SIG_PROBE, SIG_FORM)
    _, C15 = crb(Jid, SIG_PROBE)
    _, C52 = crb(Jid, sig_white)
    for i, (nme, un) in enumerate(zip(ID_NAMES, ID_UNITS)):
        f = 1 / float(ARCSEC) if un == "rad" else 1e6
        unit = "arcsec" if un == "rad" else "nm"
        tv = float(q_true[i]) * (1 / float(ARCSEC) if un == "rad" else 1e3)
        tu = "arcsec" if un == "rad" else "um"
        print(f"    {nme:6s} {tv:10.4f} {tu:6s} {np.sqrt(C15[i,i])*f:10.4f} {unit:6s}"
              f" {np.sqrt(C52[i,i])*f:10.4f} {unit}")
    d = np.sqrt(np.diag(C15))
    R = C15 / np.outer(d, d)
    print("  correlation of the estimates (two heights):")
    print("    " + " ".join(f"{n:>6s}" for n in ID_NAMES))
    for i, nme in enumerate(ID_NAMES):
        print(f"  {nme:4s}" + " ".join(f"{R[i,j]:6.2f}" for j in range(9)))

    print("  scaling: sigma of a_x (arcsec) and e_x (nm) vs sampling and noise (two heights):")
    for step, revs, sg in ((10, 1, SIG_PROBE), (5, 1, SIG_PROBE), (1, 1, SIG_PROBE),
                           (5, 4, SIG_PROBE), (5, 1, 2 * SIG_PROBE)):
        ph = phis_deg(step, revs)
        J = np.array(jac(lambda q: id_samples(q, ph), q_true.copy(), id_steps()), dtype=np.float64)
        _, C = crb(J, sg)
        print(f"    step {step:2d} deg, {revs} rev, N = {len(ph):4d}, noise {sg*1e6:4.0f} nm: "
              f"a_x {np.sqrt(C[3,3])/float(ARCSEC):.5f} arcsec, o_x {np.sqrt(C[0,0])*1e6:.3f} nm, "
              f"e_x {np.sqrt(C[5,5])*1e6:.3f} nm, w_x {np.sqrt(C[7,7])/float(ARCSEC):.5f} arcsec, "
              f"sqrt(N)*sigma(e_x)/noise = {np.sqrt(len(ph))*np.sqrt(C[5,5])/sg:.3f}")
    for b1, b2 in ((F(50), F(100)), (F(50), F(150)), (F(50), F(250))):
        J = np.array(jac(lambda q: id_samples(q, phis, (b1, b2)), q_true.copy(), id_steps()),
                     dtype=np.float64)
        _, C = crb(J, SIG_PROBE)
        print(f"    balls at {float(b1):g}/{float(b2):g} mm: a_x {np.sqrt(C[3,3])/float(ARCSEC):.5f} "
              f"arcsec, w_x {np.sqrt(C[7,7])/float(ARCSEC):.5f} arcsec, o_x {np.sqrt(C[0,0])*1e6:.3f} nm, "
              f"e_x {np.sqrt(C[5,5])*1e6:.3f} nm")
    # one height: what the weak directions cost
    J1 = results["one height (ball 1)"]
    s1 = np.linalg.svd(J1 * scale[None, :], compute_uv=True)
    print("  one height: null directions of J (unit vectors in um/urad coordinates, "
          "smallest singular values):")
    for k in (8, 7, 6, 5):
        v = s1[2][k]
        print(f"    s = {s1[1][k]:.2e}: " + " ".join(f"{n}:{x:+.3f}" for n, x in zip(ID_NAMES, v)
                                                 if abs(x) > 0.01))

    # closed-form start (harmonics 0 and 1) and Gauss-Newton on noise-free seed data
    y = np.array(seed_samples(TRUE, phis), dtype=np.float64).reshape(N, 2, 3)
    ph64 = np.array([float(x) for x in phis])
    m1, m2 = y[:, 0].mean(axis=0), y[:, 1].mean(axis=0)
    b1, b2 = float(BALLS[0]), float(BALLS[1])
    a0 = (m2 - m1) / (b2 - b1)
    a0 = a0 / np.linalg.norm(a0)
    o0 = m1 - (float(G_NOM) + b1) * a0
    ex1 = np.array([1.0, 0, 0]) - a0[0] * a0
    ex1 /= np.linalg.norm(ex1)
    ex2 = np.cross(a0, ex1)
    cks = []
    for k in range(2):
        c = (y[:, k] @ ex1) + 1j * (y[:, k] @ ex2)
        ck = np.mean(c * np.exp(-1j * ph64))
        cks.append(ck.real * ex1 + ck.imag * ex2)
    w0 = (cks[1] - cks[0]) / (b2 - b1)
    e0 = cks[0] - b1 * w0
    q0 = np.array([o0[0], o0[1], o0[2], a0[0], a0[1], e0[0], e0[1], w0[0], w0[1]])
    qv = np.array(q0, dtype=F)
    print("  closed-form start from the harmonics, then Gauss-Newton (noise-free seed data):")
    for it in range(4):
        dqv = qv - q_true
        print(f"    iteration {it}: |dq| o {float(np.max(np.abs(dqv[:3])))*1e6:.3e} nm, a {float(np.max(np.abs(dqv[3:5])))/float(ARCSEC):.3e} arcsec, "
              f"e {float(np.max(np.abs(dqv[5:7])))*1e6:.3e} nm, w {float(np.max(np.abs(dqv[7:9])))/float(ARCSEC):.3e} arcsec")
        Jg = np.array(jac(lambda q: id_samples(q, phis), qv.copy(), id_steps()), dtype=np.float64)
        rr = np.array(seed_samples(TRUE, phis) - id_samples(qv, phis), dtype=np.float64)
        qv = qv + np.array(np.linalg.lstsq(Jg, rr, rcond=None)[0], dtype=F)

    # ------------------------------------------------------ Monte Carlo check
    print("\n[5] Monte Carlo (2,000 runs): probe noise 15 nm + ball form error 50 nm RMS "
          "(random harmonics 2..15 per ball and axis), linearised least squares")
    rng = np.random.default_rng(7)
    phis64 = np.array([float(x) for x in phis])
    y0 = np.array(id_samples(q_true, phis), dtype=np.float64)
    A = Jid
    P = np.linalg.solve(A.T @ A, A.T)
    est = []
    for _ in range(2000):
        form = np.zeros((N, 2, 3))
        for k in range(2):
            for ax in range(3):
                amp = rng.normal(size=(14, 2))
                h = np.arange(2, 16)
                f = (amp[:, :1] * np.cos(np.outer(h, phis64)) + amp[:, 1:] *
                     np.sin(np.outer(h, phis64))).sum(axis=0)
                form[:, k, ax] = f / np.sqrt(np.mean(f ** 2)) * SIG_FORM
        noise = rng.normal(scale=SIG_PROBE, size=y0.shape) + form.reshape(-1)
        est.append(P @ noise)
    est = np.array(est)
    ratio = est.std(axis=0) / np.sqrt(np.diag(C15))
    bias = np.abs(est.mean(axis=0)) / np.sqrt(np.diag(C15))
    print("  RMS / CRB(15 nm):  " + " ".join(f"{n}:{x:.3f}" for n, x in zip(ID_NAMES, ratio)))
    print("  |mean| / CRB(15 nm): max " + f"{bias.max():.3f}")
    # a first-harmonic error at one ball (ball eccentricity on its stem) is absorbed
    ecc = np.zeros((N, 2, 3))
    a_true = id_vectors(q_true)[1]
    for i, ph in enumerate(phis):
        ecc[i, 1] = np.array(rot(a_true, ph) @ np.array([F("0.5e-3"), 0, 0], dtype=F), dtype=np.float64)
    dq = P @ ecc.reshape(-1)
    res = ecc.reshape(-1) - A @ dq
    print(f"  0.5 um eccentricity of ball 2 on its stem (turns with the spindle): residual "
          f"max {np.max(np.abs(res))*1e6:.3f} nm; absorbed as de_x {dq[5]*1e6:+.1f} nm, "
          f"dw_x {dq[7]/float(ARCSEC):+.3f} arcsec")

    # --------------------------------------------------- 6. outputs are identifiable
    print("\n[6] screw error and tool-tip error depend on the identifiable parameters only")
    ph_out = phis_deg(10)
    for L in TOOL_LENGTHS:
        g_seed = jac(lambda p: seed_outputs(p, ph_out, L), TRUE.copy(), seed_steps())
        g_id = jac(lambda q: id_outputs(q, ph_out, L), q_true.copy(), id_steps())
        fac = g_id @ M
        names = ["theta_e", "d_e", "tip_x", "tip_y", "tip_z"]
        nout = len(names)
        gs = np.array(g_seed, dtype=np.float64).reshape(len(ph_out), nout, -1)
        gf = np.array(fac, dtype=np.float64).reshape(len(ph_out), nout, -1)
        # null space of the two-height seed Jacobian (prior-scaled)
        JD = np.array(Js["two heights"] * PRIOR[None, :], dtype=np.float64)
        U, s, Vt = np.linalg.svd(JD)
        rk = int(np.sum(s ** 2 / SIG_PROBE ** 2 > 100))
        Nul = Vt[rk:].T
        J1D = np.array(Js["one height (ball 1)"] * PRIOR[None, :], dtype=np.float64)
        U1, s1_, Vt1 = np.linalg.svd(J1D)
        rk1 = int(np.sum(s1_ ** 2 / SIG_PROBE ** 2 > 100))
        Nul1 = Vt1[rk1:].T
        print(f"  tool length {float(L):g} mm (balls at 50/150; rank two heights {rk}, one height {rk1}):")
        for j, nme in enumerate(names):
            g = gs[:, j, :] * np.array(PRIOR, dtype=np.float64)[None, :]
            gn = np.linalg.norm(g, axis=1) + 1e-300
            in_null2 = np.max(np.linalg.norm(g @ Nul, axis=1) / gn)
            in_null1 = np.max(np.linalg.norm(g @ Nul1, axis=1) / gn)
            facerr = np.max(np.abs(gs[:, j, :] - gf[:, j, :])) / (np.max(np.abs(gs[:, j, :])) + 1e-300)
            print(f"    {nme:8s}: gradient part in the data's null space: two heights "
                  f"{in_null2:.1e}, one height {in_null1:.1e}; |g_seed - g_id M|/|g| {facerr:.1e}")
    # values and their uncertainty over a revolution
    print("  values over one revolution (10 deg steps) and CRB 1-sigma (15 nm, two heights):")
    ph_out = phis_deg(10)
    for L in TOOL_LENGTHS:
        out = np.array(id_outputs(q_true, ph_out, L), dtype=np.float64).reshape(len(ph_out), 5)
        G = np.array(jac(lambda q: id_outputs(q, ph_out, L), q_true.copy(), id_steps()),
                     dtype=np.float64)
        cov = G @ C15 @ G.T
        sd = np.sqrt(np.diag(cov)).reshape(len(ph_out), 5)
        tip = np.linalg.norm(out[:, 2:4], axis=1)
        print(f"    L = {float(L):g} mm: theta_e {out[:,0].min()/float(ARCSEC):.3f}..{out[:,0].max()/float(ARCSEC):.3f} arcsec "
              f"(sigma <= {sd[:,0].max()/float(ARCSEC):.4f}), d_e {out[:,1].min()*1e3:.3f}..{out[:,1].max()*1e3:.3f} um "
              f"(sigma <= {sd[:,1].max()*1e6:.2f} nm), |tip_xy| {tip.min()*1e3:.3f}..{tip.max()*1e3:.3f} um "
              f"(sigma <= {max(sd[:,2].max(), sd[:,3].max())*1e6:.2f} nm), tip_z {out[:,4].min()*1e6:.2f}..{out[:,4].max()*1e6:.2f} nm")
    # seed-model outputs vs identifiable-model outputs at the mapped values
    for L in TOOL_LENGTHS:
        a_ = np.array(seed_outputs(TRUE, ph_out, L), dtype=np.float64).reshape(-1, 5)
        b_ = np.array(id_outputs(q_true, ph_out, L), dtype=np.float64).reshape(-1, 5)
        print(f"    L = {float(L):g} mm seed vs identifiable model: theta_e {np.abs(a_[:,0]-b_[:,0]).max()/float(ARCSEC):.1e} arcsec, "
              f"d_e {np.abs(a_[:,1]-b_[:,1]).max()*1e6:.1e} nm, tip xy {np.abs(a_[:,2:4]-b_[:,2:4]).max()*1e6:.1e} nm, "
              f"tip z {np.abs(a_[:,4]-b_[:,4]).max()*1e6:.1e} nm")
    # ------------------------------------------- 7. errors of the nominal lengths
    print("\n[7] bias from wrong nominal lengths (data made with the true length, fitted with the nominal)")
    ph_out = phis_deg(10)
    for what, dG, db1, db2 in (("gauge_from_upper_bearing +0.1 mm", F("0.1"), F(0), F(0)),
                               ("ball_1, ball_2 and tool +0.1 mm", F(0), F("0.1"), F("0.1")),
                               ("ball_2 - ball_1 +0.01 mm (spacing)", F(0), F(0), F("0.01"))):
        Gt = G_NOM + dG
        bt = (BALLS[0] + db1, BALLS[1] + db2)
        y = id_samples(q_true, phis, bt, Gt)
        qv = q_true.copy()
        for _ in range(3):
            Jg = jac(lambda q: id_samples(q, phis), qv.copy(), id_steps())
            qv = qv + np.array(np.linalg.lstsq(np.array(Jg, dtype=np.float64),
                                               np.array(y - id_samples(qv, phis), dtype=np.float64),
                                               rcond=None)[0], dtype=F)
        worst = []
        for L in TOOL_LENGTHS:
            t = np.array(id_outputs(q_true, ph_out, L + db1, Gt), dtype=np.float64).reshape(-1, 5)
            t[:, 4] += float(dG + db1)   # the true tip's ideal reference is the true gauge line
            f = np.array(id_outputs(qv, ph_out, L), dtype=np.float64).reshape(-1, 5)
            worst.append((np.abs(t[:, 0] - f[:, 0]).max() / float(ARCSEC), np.abs(t[:, 1] - f[:, 1]).max() * 1e6,
                          np.abs(t[:, 2:4] - f[:, 2:4]).max() * 1e6))
        print(f"  {what:40s}: " + "; ".join(f"L = {float(L):g}: theta_e {w_[0]:.4f} arcsec, d_e {w_[1]:.1f} nm, tip_xy {w_[2]:.1f} nm"
                                          for L, w_ in zip(TOOL_LENGTHS, worst)))

    print(f"  tip_z against Delta3 (seed): d tip_z / d Delta3 = "
          f"{float(jac(lambda p: seed_outputs(p, [F(0)], TOOL_LENGTHS[0]), TRUE.copy(), seed_steps())[4, 9]):+.6f}"
          " (mm/mm): the axial length error moves the tip but is in the data's null space")


if __name__ == "__main__":
    main()
