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


def rowe_fit(ratio, d, start, extension=False):
    """K of sigma_1/sigma_3 = K D (rowe_dilatancy) through the origin over rows start.. (least squares), phi_f [deg],
    and the rms of the relative residuals; NaNs where fewer than MIN_ROWS rows have a d."""
    D = rowe_dilatancy(d[start:], extension)
    R = ratio[start:]
    ok = np.isfinite(D) & np.isfinite(R)
    if ok.sum() < MIN_ROWS:
        return float("nan"), float("nan"), float("nan")
    D, R = D[ok], R[ok]
    K = float((R * D).sum() / (D * D).sum())
    return K, math.degrees(math.asin((K - 1) / (K + 1))), float(np.sqrt(np.mean(((R - K * D) / R) ** 2)))


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
