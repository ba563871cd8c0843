"""Stress and dilatancy of a drained triaxial compression test, from its series (compression positive strains).

  - the dilatancy rate d = d eps_v / d eps_a: the slope of a least-squares line through the rows within WINDOW/2 of
    axial strain either side (at least MIN_ROWS rows), with its standard error; < 0 while the sample dilates;
  - the dilation angle of triaxial strain, sin psi = -d / (2 - d) (principal increments d eps_1 and d eps_3 =
    (d eps_v - d eps_1) / 2: sin psi = -(d eps_1 + 2 d eps_3) / (d eps_1 - 2 d eps_3); 0 at constant volume; Schanz &
    Vermeer 1996, Geotechnique 46, eq. 3);
  - Rowe's stress-dilatancy (1962, Proc. R. Soc. A 269; triaxial compression): sigma_1/sigma_3 = K (1 - d), K =
    tan^2(45 + phi_f/2), fitted through the origin over the rows from the sample's largest contraction (d = 0, where it
    turns to dilate) to the end; at critical state (d = 0) it gives sigma_1/sigma_3 = K: phi_f is the critical-state
    angle where Rowe holds, and lies between the grains' friction angle and it in Rowe's own reading. The principal
    stress ratio is that of the contact stress ratio eta = q/p' the report's peaks use: (3 + 2 eta) / (3 - eta);
  - Bolton's (1986, Geotechnique 36, eqs. 12-14) relations for triaxial strain: phi'_max - phi'_cs = 3 I_R degrees
    and (-d)_max = 0.3 I_R, so phi'_max - phi'_cs = 10 (-d)_max degrees: the report gives the measured ratio beside
    that 10 (plane strain's 0.8 psi_max reads 5 I_R against psi_max).
"""
import math

import numpy as np

# The slope's window of axial strain, widened to hold MIN_ROWS rows where the rows are sparser: over 2 % the row-to-row
# scatter of eps_v of a 5 000-sphere sample averages out (its largest rate changes by 7-14 % between 2 % and 4 %
# windows on the quick study's tests at mu_r 0.3; at mu_r 0 the rows are sparse enough that both widen alike), while the dense 10 000-sphere sample's largest rate, reached at 3 %, is 0.546
# over 2 % and 0.531 over 4 %: not flattened.
WINDOW = 0.02
MIN_ROWS = 5
# (-d)_max counts where it exceeds this many standard errors of its slope: a loose sample's dilatancy is within its
# noise, and the largest of many noisy slopes is no peak.
SIGNIFICANT = 3.0


def rate(eps_a, eps_v, window=WINDOW):
    """d eps_v / d eps_a at every row and its standard error: NaN where the window (widened to MIN_ROWS median row
    spacings) is not whole, at the series' ends, or holds fewer than MIN_ROWS rows."""
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


def dilation_angle(d):
    """psi [deg] of triaxial strain from d = d eps_v / d eps_a (module docstring)."""
    return np.degrees(np.arcsin(np.clip(-d / (2 - d), -1, 1)))


def principal_ratio(eta):
    """sigma_1 / sigma_3 in triaxial compression from eta = q / p'."""
    return (3 + 2 * eta) / (3 - eta)


def rowe_fit(ratio, d, start):
    """K of sigma_1/sigma_3 = K (1 - d) through the origin over rows start.. (least squares), phi_f [deg], and the
    rms of the relative residuals; NaNs where fewer than MIN_ROWS rows have a d."""
    D = 1 - d[start:]
    R = ratio[start:]
    ok = np.isfinite(D) & np.isfinite(R)
    if ok.sum() < MIN_ROWS:
        return float("nan"), float("nan"), float("nan")
    D, R = D[ok], R[ok]
    K = float((R * D).sum() / (D * D).sum())
    return K, math.degrees(math.asin((K - 1) / (K + 1))), float(np.sqrt(np.mean(((R - K * D) / R) ** 2)))


def analyse(eps_a, eps_v, eta, window=WINDOW):
    """One test's dilatancy: the largest dilation rate (-d)_max, its standard error, strain and angle psi_max (NaN
    where it is not SIGNIFICANT standard errors above 0), the row and strain of the largest contraction (turn,
    eps_turn), Rowe's K, phi_f and rms over the rows from it; and the per-row d (for figures)."""
    d, se = rate(eps_a, eps_v, window)
    out = dict(d=d, neg_d_max=float("nan"), se=float("nan"), eps_max=float("nan"), psi_max=float("nan"))
    if np.isfinite(d).any():
        k = int(np.nanargmin(d))
        out.update(neg_d_max=float(-d[k]), se=float(se[k]), eps_max=float(eps_a[k]))
        if -d[k] > SIGNIFICANT * se[k]:
            out["psi_max"] = float(dilation_angle(d[k]))
    k0 = int(np.argmax(eps_v))  # the largest contraction: where the sample turns to dilate
    out["turn"], out["eps_turn"] = k0, float(eps_a[k0])
    out["K"], out["phi_f"], out["rms"] = rowe_fit(principal_ratio(eta), d, k0)
    return out
