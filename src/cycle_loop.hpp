#pragma once
// One load cycle of a cyclic stage, accumulated step by step: the extremes of q and eps_a, the loop's area
// (the work per volume dissipated in the cycle) and the largest excess pore pressure. At the cycle's end it gives
// the two numbers a cyclic triaxial test reports per cycle (ASTM D3999: modulus and damping):
//  - the equivalent (secant) Young's modulus E_eq = (q_max - q_min) / (eps_max - eps_min);
//  - the damping ratio D = W_loop / (4 pi W_e), W_loop the loop's area (the closed integral of q d eps_a, taken about
//    the stage's q_0: q_ref below),
//    W_e = q_a eps_a / 2 the elastic energy of the secant at the single amplitudes q_a = (q_max - q_min)/2 and
//    eps_a = (eps_max - eps_min)/2: D = W_loop / (2 pi q_a eps_a). D is 0 for an elastic loop and 2/pi for a
//    rigid-plastic one (the rectangle 2 q_a x 2 eps_a);
//  - the equivalent shear modulus G_eq = (tau_max - tau_min) / (gamma_max - gamma_min) on the plane of largest shear,
//    tau = q/2 and gamma = eps_a - eps_r (the engineering shear strain there; 1.5 eps_q): the modulus resonant-column
//    and simple-shear tests report and the G/G_max curves of site response (Darendeli 2001) use. Undrained (eps_v = 0)
//    gamma = 1.5 eps_a to first order and G_eq = E_eq/3; drained the sample's lateral strain sets it, and
//    E_eq/G_eq = 2 (1 + nu_eq);
//  - E_eq and D of the walls' q less the local damping's drag q_drag (series q_drag, fed each step with q): the walls'
//    q carries the drag (SPEC section 4's damping acts on every sphere against its velocity, so on a cycle it opposes
//    the straining both ways and adds area to the loop). Less the drag, the loop is the material's as the boundary
//    measures it: on configs/modulus_damping.yaml the drag is 30-60 % of D at eps_a = 1e-5 and 2-6 % from 1e-4 on;
//  - of the walls' vertical stress sigma_v (sigma_z), the loop a cyclic oedometer reports: the equivalent constrained
//    modulus M_eq = (sigma_v,max - sigma_v,min) / (eps_max - eps_min) and the damping ratio D_v of the sigma_v - eps_a
//    loop, as D's of q's. With the lateral walls held the loop's area is the whole work per volume the walls do in the
//    cycle (the lateral ones do none); of a triaxial cycle under a constant sigma_3 it is q's loop again. The area is
//    taken about the cycle's first sigma_v, the integral of (sigma_v - sigma_v,start) d eps_a: the same for a closed
//    loop, and an open one (the strain the cycle leaves) does not count the mean stress's work on that strain as
//    hysteresis: cycled about 200 kPa by +-10 kPa, the first cycle's 0.047 % of permanent strain is 94 J/m^3 of it,
//    where the loop encloses ~2.5 (configs/cyclic-oedometer-study.yaml: D_v 3.6 of the plain integral, past the 2/pi
//    of any closed loop, against 0.094 about the cycle's start; q's is taken about the stage's q_0, where a stress
//    reversal's cycles also start, within a step's change). Less the drag too (svd: the drag's share of sigma_v, fed
//    with it), as q's.
// Host code, no Kokkos: Laboratory feeds it the measure it turns on, once a step (test_cycle_loop checks it on
// analytic loops).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace grainlab {

struct CycleLoop {
  double q_max = 0, q_min = 0, e_max = 0, e_min = 0;
  double work = 0;         // integral of (q - q_ref) d eps_a so far (trapezoids between the steps' measures) [Pa]
  // The q the loop's area is taken about: the stage's q_0, the centre its stress reversal cycles about (set before
  // start). The same area for a closed loop; of an open one, the work of q_0 on the strain the cycle leaves is not
  // hysteresis (q_0 = 64 kPa on a cycle of +-30 kPa and +-0.18 % that leaves 0.1 % of strain: 64 J/m^3 against a loop
  // of 2 pi 30e3 x 1.8e-3 = 340, D 0.19 too high; test CycleLoop.QLoopIsTakenAboutTheStagesQ0). 0 after an isotropic
  // stage (SPEC §6.3's q_0): exactly the integral of q d eps_a there.
  double q_ref = 0;
  double q_prev = 0, e_prev = 0;
  double g_max = 0, g_min = 0;  // extremes of the shear strain gamma = eps_a - eps_r (NaN: not known, see set_state)
  double u_max = 0;        // the largest excess pore pressure u seen in the cycle [Pa]
  double work_drag = 0;    // integral of q_drag d eps_a so far [Pa]
  double qd_prev = 0;
  double qn_max = 0, qn_min = 0;  // extremes of q - q_drag (NaN: not known, see set_state)
  double sv_max = 0, sv_min = 0;  // extremes of sigma_v (NaN: not known, see set_state) [Pa]
  double work_v = 0, sv_prev = 0;  // integral of (sigma_v - sv_start) d eps_a so far [Pa]
  double sv_start = 0;             // sigma_v at the cycle's start [Pa]
  double work_v_drag = 0, svd_prev = 0;  // integral of (svd - svd_start) d eps_a so far, svd the drag's share [Pa]
  double svd_start = 0;
  double svn_max = 0, svn_min = 0;       // extremes of sigma_v less the drag [Pa]
  bool open = false;
  double n = 0;            // the stage's cycle number N at the last step fed (it never decreases)

  // The cycle starts at this measure (qd: the drag's share of q, 0 without damping; sv: sigma_v, 0 where not given;
  // svd: the drag's share of sigma_v).
  void start(double q, double e, double g, double u, double qd = 0, double sv = 0, double svd = 0) {
    q_max = q_min = q_prev = q;
    e_max = e_min = e_prev = e;
    g_max = g_min = g;
    work = 0;
    u_max = u;
    work_drag = 0;
    qd_prev = qd;
    qn_max = qn_min = q - qd;
    sv_max = sv_min = sv_prev = sv_start = sv;
    work_v = 0;
    work_v_drag = 0;
    svd_prev = svd_start = svd;
    svn_max = svn_min = sv - svd;
    open = true;
  }
  void add(double q, double e, double g, double u, double qd = 0, double sv = 0, double svd = 0) {
    work += (0.5 * (q + q_prev) - q_ref) * (e - e_prev);  // q_ref 0: 0.5 (q + q_prev) to the bit
    work_v += (0.5 * (sv + sv_prev) - sv_start) * (e - e_prev);  // before e_prev moves on
    // (sv - svd)'s area about its own start is work_v less this
    work_v_drag += (0.5 * (svd + svd_prev) - svd_start) * (e - e_prev);
    sv_prev = sv;
    svd_prev = svd;
    svn_max = std::max(svn_max, sv - svd);
    svn_min = std::min(svn_min, sv - svd);
    sv_max = std::max(sv_max, sv);  // NaN stays NaN (std::max's first argument where the comparison fails)
    sv_min = std::min(sv_min, sv);
    work_drag += 0.5 * (qd + qd_prev) * (e - e_prev);  // the same trapezoids: q's less q_drag's is (q - q_drag)'s
    q_prev = q;
    qd_prev = qd;
    qn_max = std::max(qn_max, q - qd);  // NaN stays NaN, as g's below
    qn_min = std::min(qn_min, q - qd);
    e_prev = e;
    q_max = std::max(q_max, q);
    q_min = std::min(q_min, q);
    e_max = std::max(e_max, e);
    e_min = std::min(e_min, e);
    // std::max(NaN, g) is NaN (its first argument when the comparison fails): an unknown extreme stays unknown
    g_max = std::max(g_max, g);
    g_min = std::min(g_min, g);
    u_max = std::max(u_max, u);
  }
  double modulus() const { return e_max > e_min ? (q_max - q_min) / (e_max - e_min) : 0; }
  double shear_modulus() const {
    if (std::isnan(g_max - g_min)) return std::nan("");
    return g_max > g_min ? 0.5 * (q_max - q_min) / (g_max - g_min) : 0;
  }
  double damping() const { return damping_of(work, q_max, q_min); }
  // Of q - q_drag: its own extremes and loop area (NaN where a checkpoint from before the drag left them unknown).
  double modulus_less_drag() const {
    if (std::isnan(qn_max - qn_min)) return std::nan("");
    return e_max > e_min ? (qn_max - qn_min) / (e_max - e_min) : 0;
  }
  double damping_less_drag() const {
    if (std::isnan(qn_max - qn_min + work_drag)) return std::nan("");
    return damping_of(work - work_drag, qn_max, qn_min);
  }
  // Of sigma_v: the constrained modulus and damping ratio of the cyclic oedometer (NaN where sigma_v is not known).
  double constrained_modulus() const {
    if (std::isnan(sv_max - sv_min)) return std::nan("");
    return e_max > e_min ? (sv_max - sv_min) / (e_max - e_min) : 0;
  }
  double damping_v() const {
    if (std::isnan(sv_max - sv_min + work_v)) return std::nan("");
    return damping_of(work_v, sv_max, sv_min);
  }
  // Of sigma_v less its drag: its own extremes, and its area about its own start (work_v less the drag's)
  double constrained_modulus_less_drag() const {
    if (std::isnan(svn_max - svn_min)) return std::nan("");
    return e_max > e_min ? (svn_max - svn_min) / (e_max - e_min) : 0;
  }
  double damping_v_less_drag() const {
    if (std::isnan(svn_max - svn_min + work_v - work_v_drag)) return std::nan("");
    return damping_of(work_v - work_v_drag, svn_max, svn_min);
  }
  double damping_of(double w, double qmax, double qmin) const {
    const double qa = 0.5 * (qmax - qmin), ea = 0.5 * (e_max - e_min);
    return qa > 0 && ea > 0 ? w / (2 * M_PI * qa * ea) : 0;
  }

  // For checkpoints: the state as numbers, and back. A checkpoint written before gamma was tracked holds the first
  // kStateSizeNoShear numbers: the open cycle's gamma extremes are then unknown (NaN), and so is its G_eq, rather than
  // a modulus over the part of the cycle after the restart; the cycles after it are whole again. One written before
  // the drag holds kStateSizeNoDrag: the open cycle's values less the drag are unknown alike; one before sigma_v's
  // loop, kStateSizeNoSigmaV: the open cycle's M_eq and D_v unknown.
  static constexpr size_t kStateSize = 27, kStateSizeNoSigmaV = 16, kStateSizeNoDrag = 12, kStateSizeNoShear = 10;
  std::vector<double> state() const {
    return {q_max, q_min, e_max, e_min, work, q_prev, e_prev, u_max, double(open), n, g_max, g_min,
            work_drag, qd_prev, qn_max, qn_min, sv_max, sv_min, work_v, sv_prev, sv_start,
            work_v_drag, svd_prev, svn_max, svn_min, svd_start, q_ref};
  }
  void set_state(const std::vector<double>& s) {
    if (s.size() != kStateSize && s.size() != kStateSizeNoSigmaV && s.size() != kStateSizeNoDrag &&
        s.size() != kStateSizeNoShear)
      throw std::runtime_error("cycle loop state has the wrong length (corrupt?)");
    q_max = s[0];
    q_min = s[1];
    e_max = s[2];
    e_min = s[3];
    work = s[4];
    q_prev = s[5];
    e_prev = s[6];
    u_max = s[7];
    open = s[8] != 0;
    n = s[9];
    const bool shear = s.size() >= kStateSizeNoDrag, drag = s.size() >= kStateSizeNoSigmaV, sv = s.size() == kStateSize;
    g_max = shear ? s[10] : std::nan("");
    g_min = shear ? s[11] : std::nan("");
    work_drag = drag ? s[12] : std::nan("");
    qd_prev = drag ? s[13] : std::nan("");
    qn_max = drag ? s[14] : std::nan("");
    qn_min = drag ? s[15] : std::nan("");
    sv_max = sv ? s[16] : std::nan("");
    sv_min = sv ? s[17] : std::nan("");
    work_v = sv ? s[18] : std::nan("");
    sv_prev = sv ? s[19] : std::nan("");
    sv_start = sv ? s[20] : std::nan("");
    work_v_drag = sv ? s[21] : std::nan("");
    svd_prev = sv ? s[22] : std::nan("");
    svn_max = sv ? s[23] : std::nan("");
    svn_min = sv ? s[24] : std::nan("");
    svd_start = sv ? s[25] : std::nan("");
    q_ref = sv ? s[26] : 0;  // an older build's loop: about q = 0, as its part before the restart
  }
};

}  // namespace grainlab
