"""Stress and dilatancy of a drained triaxial compression or extension test, from its series (compression positive
strains).

  - the dilatancy rate d = d eps_v / d eps_l, eps_l the axial strain along the loading (eps_a in compression, -eps_a in
    extension, both rising): the slope of a least-squares line through the rows within WINDOW/2 of it either side (at
    least MIN_ROWS rows), with its standard error; < 0 while the sample dilates;
  - the dilation angle of triaxial strain, sin psi = -d / (2 - d) (principal increments d eps_1 and d eps_3 =
    (d eps_v - d eps_1) / 2: sin psi = -(d eps_1 + 2 d eps_3) / (d eps_1 - 2 d eps_3); 0 at constant volume; Schanz &
    Vermeer 1996, Geotechnique 46, eq. 3); in extension the two lateral increments are the major ones, d eps_1 =
    (d eps_v + d eps_l) / 2, and the axial the minor, d eps_3 = -d eps_l: sin psi = -(2 d eps_1 + d eps_3) /
    (2 d eps_1 - d eps_3) = -d / (2 + d), the same form with the lateral pair the major increments;
  - Rowe's stress-dilatancy (1962, Proc. R. Soc. A 269; triaxial compression): sigma_1/sigma_3 = K (1 - d), K =
    tan^2(45 + phi_f/2), fitted through the origin over the rows from the sample's largest contraction (d = 0, where it
    turns to dilate) to the end; at critical state (d = 0) it gives sigma_1/sigma_3 = K: phi_f is the critical-state
    angle where Rowe holds, and lies between the grains' friction angle and it in Rowe's own reading. The principal
    stress ratio is that of the contact stress ratio eta = q/p' the report's peaks use: (3 + 2 eta) / (3 - eta). In
    extension Rowe's energy ratio has the two major stresses doing the work, 2 sigma_1 d eps_1 / (-sigma_3 d eps_3) =
    K (Rowe, Barden & Lee 1964, Geotechnique 14, the extension cell test): sigma_1/sigma_3 = K (-d eps_3 / (2 d
    eps_1)) = K / (1 + d), with sigma_1/sigma_3 = (3 + eta) / (3 - 2 eta) for eta = |q|/p'; d = 0 still gives K;
  - Bolton's (1986, Geotechnique 36, eqs. 12-14) relations for triaxial strain: phi'_max - phi'_cs = 3 I_R degrees
    and (-d)_max = 0.3 I_R, so phi'_max - phi'_cs = 10 (-d)_max degrees: the report gives the measured ratio beside
    that 10 (plane strain's 0.8 psi_max reads 5 I_R against psi_max). Bolton gives no extension relation: the report
    gives the ratio there for comparison only.
"""
import math

import numpy as np

# The slope's window of axial strain, widened to hold MIN_ROWS rows where the rows are sparser: over 2 % the row-to-row
# scatter of eps_v of a 5 000-sphere sample averages out (its largest rate changes by 7-14 % between 2 % and 4 %
# windows on the quick study's tests at mu_r 0.3; at mu_r 0 the rows are sparse enough that both widen alike), while
# the dense 10 000-sphere sample's largest rate, reached at 3 %, is 0.546
# over 2 % and 0.531 over 4 %: not flattened.
WINDOW = 0.02
MIN_ROWS = 5
# (-d)_max counts where it exceeds this many standard errors of its slope: a loose sample's dilatancy is within its
# noise, and the largest of many noisy slopes is no peak.
SIGNIFICANT = 3.0


def rate(eps_a, eps_v, window=WINDOW):
    """d eps_v / d eps_a (eps_a rising: in extension pass -eps_a) at every row and its standard error: NaN where the
    window (widened to MIN_ROWS median row spacings) is not whole, at the series' ends, or holds fewer than MIN_ROWS
    rows."""
    n = len(eps_a)
    d, se = np.full(n, np.nan), np.full(n, np.nan)
    if n < MIN_ROWS:
        return d, se
    window = max(window, MIN_ROWS * float(np.median(np.diff(eps_a))))
    for k in range(n):
        if eps_a[k] - window / 2 < eps_a[0] or eps_a[k] + window / 2 > eps_a[-1]:
            continue
        m = np.abs(eps_a - eps_a[k]) <= window / 2
        if m.sum() < MIN_ROWS:
            continue
        x, y = eps_a[m] - eps_a[m].mean(), eps_v[m]
        sxx = float((x * x).sum())
        if sxx <= 0:
            continue
        b = float((x * (y - y.mean())).sum() / sxx)
        res = y - y.mean() - b * x
        d[k] = b
        se[k] = math.sqrt(float((res * res).sum()) / (m.sum() - 2) / sxx)
    return d, se


def dilation_angle(d, extension=False):
    """psi [deg] of triaxial strain from d = d eps_v / d eps_l (module docstring)."""
    return np.degrees(np.arcsin(np.clip(-d / ((2 + d) if extension else (2 - d)), -1, 1)))


def principal_ratio(eta, extension=False):
    """sigma_1 / sigma_3 in triaxial compression (extension) from eta = |q| / p'."""
    return (3 + eta) / (3 - 2 * eta) if extension else (3 + 2 * eta) / (3 - eta)


def rowe_dilatancy(d, extension=False):
    """Rowe's dilatancy factor D of sigma_1/sigma_3 = K D from d = d eps_v / d eps_l: 1 - d in compression (-2 d eps_3
    / d eps_1), 1 / (1 + d) in extension (-d eps_3 / (2 d eps_1); module docstring)."""
    return 1 / (1 + d) if extension else 1 - d


def through_origin(y, x):
    """K of y = K x through the origin (least squares over the rows where both are numbers), phi_f = asin((K - 1) / (K
    + 1)) [deg] and the rms of the relative residuals (y - K x) / y; NaNs where fewer than MIN_ROWS rows are."""
    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < MIN_ROWS:
        return float("nan"), float("nan"), float("nan")
    x, y = x[ok], y[ok]
    K = float((y * x).sum() / (x * x).sum())
    return K, math.degrees(math.asin((K - 1) / (K + 1))), float(np.sqrt(np.mean(((y - K * x) / y) ** 2)))


def rowe_fit(ratio, d, start, extension=False):
    """K of sigma_1/sigma_3 = K D (rowe_dilatancy) through the origin over rows start.. (least squares), phi_f [deg],
    and the rms of the relative residuals; NaNs where fewer than MIN_ROWS rows have a d."""
    return through_origin(ratio[start:], rowe_dilatancy(d[start:], extension))


def analyse(eps_a, eps_v, eta, window=WINDOW, extension=False):
    """One test's dilatancy: the largest dilation rate (-d)_max, its standard error, axial strain eps_a and angle
    psi_max (NaN where it is not SIGNIFICANT standard errors above 0), the row and axial strain of the largest
    contraction (turn, eps_turn), Rowe's K, phi_f and rms over the rows from it; and the per-row d (for figures). eta:
    |q|/p'; extension: the test unloads axially (eps_a falls; d is taken along -eps_a)."""
    d, se = rate(-eps_a if extension else eps_a, eps_v, window)
    out = dict(d=d, neg_d_max=float("nan"), se=float("nan"), eps_max=float("nan"), psi_max=float("nan"))
    if np.isfinite(d).any():
        k = int(np.nanargmin(d))
        out.update(neg_d_max=float(-d[k]), se=float(se[k]), eps_max=float(eps_a[k]))
        if -d[k] > SIGNIFICANT * se[k]:
            out["psi_max"] = float(dilation_angle(d[k], extension))
    k0 = int(np.argmax(eps_v))  # the largest contraction: where the sample turns to dilate
    out["turn"], out["eps_turn"] = k0, float(eps_a[k0])
    out["K"], out["phi_f"], out["rms"] = rowe_fit(principal_ratio(eta, extension), d, k0, extension)
    return out


# Any b (true triaxial): the flow direction in the deviatoric plane and Rowe's energy ratio, from each axis's strain
# (series eps_x, eps_y, eps_a) and the walls' principal stresses (sigma_x, sigma_y, sigma_z). The axisymmetric
# relations above hold at b = 0 and 1 only: with sigma_2 between the others the two lateral increments differ.
#   - Strain increments are natural, d lambda = -d L / L = d(-ln(1 - eps)) of each axis's engineering strain from the
#     stage's start: they add up over the axes to the volume's at any strain (1 - eps_v = (1 - eps_a)(1 - eps_x)(1 -
#     eps_y)), which the engineering ones do only to first order (the compression section's d eps_v / d eps_a is
#     engineering: 20 % axial strain makes the two differ by up to ~20 %). Each is the slope against the loading axis's
#     (rate(), WINDOW): per unit strain along the loading.
#   - b_eps = (d lambda_2 - d lambda_3) / (d lambda_1 - d lambda_3), the increments of the axes of sigma_1, sigma_2,
#     sigma_3 (the stress's b = (sigma_2 - sigma_3) / (sigma_1 - sigma_3)): the strain increment's Lode angle as b is
#     the stress's. A flow whose deviator is parallel to the stress deviator (a circular plastic potential in the
#     deviatoric plane, Drucker-Prager's) has b_eps = b; one normal to a failure surface there has the b of that
#     surface's gradient (normal_b). Total increments: their elastic part vanishes at critical state (stress steady)
#     and is small near the peak.
#   - Rowe's stress-dilatancy as an energy ratio (Rowe 1962), written here for three unequal principal stresses: the
#     work of the stresses whose axes shorten over the work done against those whose axes lengthen, E = sum(sigma_i d
#     lambda_i, d lambda_i > 0) / -sum(sigma_i d lambda_i, d lambda_i < 0) = K = tan^2(45 + phi_f / 2). In triaxial
#     compression (d lambda_2 = d lambda_3 < 0) it is Rowe's sigma_1 d lambda_1 / (-2 sigma_3 d lambda_3) = K, i.e.
#     sigma_1 / sigma_3 = K (1 - d); in extension (the lateral pair shortening) Rowe, Barden & Lee's 2 sigma_1 d
#     lambda_1 / (-sigma_3 d lambda_3) = K; in plane strain (d lambda_2 = 0) Rowe's sigma_1 d lambda_1 / (-sigma_3 d
#     lambda_3) = K: the relations above, with natural increments. K is fitted through the origin of W_in = K W_out,
#     both over sigma_3, from the largest contraction on, as rowe_fit. Rowe's K is the material's whatever the stress
#     path: one K (phi_f) across a b series is what his theory claims there, and what the report measures.


def natural(eps):
    """The natural strain -ln(1 - eps) of an engineering strain from the stage's start (compression positive)."""
    return -np.log1p(-np.asarray(eps, dtype=float))


def energy_ratio(sig, inc):
    """W_in / sigma_3 and W_out / sigma_3 of Rowe's energy ratio at every row: sig and inc (3, n) the principal
    stresses and their axes' strain increments (compression positive), ordered sigma_1, sigma_2, sigma_3. NaN where an
    increment is."""
    work = sig * inc
    bad = ~np.isfinite(inc).all(axis=0)
    w_in = np.where(inc > 0, work, 0.0).sum(axis=0) / sig[2]
    w_out = -np.where(inc < 0, work, 0.0).sum(axis=0) / sig[2]
    return np.where(bad, np.nan, w_in), np.where(bad, np.nan, w_out)


def b_of(v):
    """(v_2 - v_3) / (v_1 - v_3) of (3, n) components ordered 1, 2, 3 (b of stresses, b_eps of strain increments):
    NaN where v_1 = v_3 (an isotropic row: no Lode angle)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return (v[1] - v[2]) / (v[0] - v[2])


def normal_b(sig, criterion):
    """b_eps of a strain increment normal, in the deviatoric plane, to the surface of a failure criterion through the
    stresses sig (3, n; ordered 1, 2, 3): b of its gradient, which a hydrostatic part (a constant added to the three
    components) leaves alone. "MN", Matsuoka-Nakai, ln(I1 I2 / I3): 1/I1 + (I1 - sigma_i) / I2 - 1/sigma_i, i.e.
    -sigma_i / I2 - 1/sigma_i and a constant; "LD", Lade-Duncan, ln(I1^3 / I3): 3/I1 - 1/sigma_i. Both give 0 at b = 0
    and 1 at b = 1 (the gradient shares the stresses' symmetry there), as radial flow does."""
    if criterion == "MN":
        i2 = sig[0] * sig[1] + sig[1] * sig[2] + sig[2] * sig[0]
        return b_of(-sig / i2 - 1 / sig)
    if criterion == "LD":
        return b_of(-1 / sig)
    raise ValueError(criterion)


def plane_strain_dilation(d, inc_1, inc_3):
    """psi [deg] of plane strain (d lambda_2 = 0) from the volume's increment d and the major and minor ones: the
    Mohr circle of strain increments, sin psi = -(d lambda_1 + d lambda_3) / (d lambda_1 - d lambda_3) = -d / (d
    lambda_1 - d lambda_3), 0 at constant volume (Bolton 1986, Geotechnique 36: phi'_max - phi'_cs = 0.8
    psi_max in plane strain). Per unit strain of the loading axis (d lambda_1 = 1, d lambda_3 = d - 1) it is -d / (2 -
    d), dilation_angle's triaxial expression in d: the same function of d in both tests, from different increments."""
    return np.degrees(np.arcsin(np.clip(-d / (inc_1 - inc_3), -1, 1)))


def deviatoric_flow(sig_xyz, eps_xyz, eps_v, extension=False, window=WINDOW):
    """One drained shear at any b: sig_xyz, eps_xyz (3, n) the walls' stresses and engineering strains of the x, y, z
    axes (compression positive), eps_v the volume's; extension: the axial walls move apart (the loading along -z).
    Returns the axes' order (indices of sigma_1, sigma_2, sigma_3 by their mean over the rows: fixed over the shear,
    so that a b = 0 test's nearly equal lateral pair does not swap from row to row), per row the ordered stresses
    `sig` and natural increments `inc` per unit loading strain, b, b_eps, the Lode angles' normal-flow b_eps of
    Matsuoka-Nakai and Lade-Duncan (`b_mn`, `b_ld`), w_in and w_out; the dilatancy rate d = d lambda_v / d lambda_l
    (`d`) and its largest dilation (-d)_max with its standard error and axial strain; the turn (largest contraction)
    and Rowe's K, phi_f and rms over the rows from it (module notes above)."""
    lam = natural(eps_xyz)
    load = -lam[2] if extension else lam[2]
    inc = np.empty_like(lam)
    for a in range(2):
        inc[a] = rate(load, lam[a], window)[0]
    inc[2] = np.where(np.isfinite(inc[0]), -1.0 if extension else 1.0, np.nan)
    d, se = rate(load, natural(eps_v), window)
    order = np.argsort(-np.nanmean(sig_xyz, axis=1), kind="stable")
    sig, inc = sig_xyz[order], inc[order]
    out = dict(order=order, sig=sig, inc=inc, b=b_of(sig), b_eps=b_of(inc), b_mn=normal_b(sig, "MN"),
               b_ld=normal_b(sig, "LD"), d=d, neg_d_max=float("nan"), se=float("nan"), eps_max=float("nan"),
               psi_ps=float("nan"))
    out["w_in"], out["w_out"] = energy_ratio(sig, inc)
    if np.isfinite(d).any():
        k = int(np.nanargmin(d))
        out.update(neg_d_max=float(-d[k]), se=float(se[k]), eps_max=float(eps_xyz[2][k]),
                   psi_ps=float(plane_strain_dilation(d[k], inc[0][k], inc[2][k])) if -d[k] > SIGNIFICANT * se[k]
                   else float("nan"))
    k0 = int(np.argmax(eps_v))
    out["turn"] = k0
    out["K"], out["phi_f"], out["rms"] = through_origin(out["w_in"][k0:], out["w_out"][k0:])
    return out
