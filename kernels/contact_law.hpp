#pragma once
// Sphere-sphere contact law, SPEC §2: linear normal spring, incremental tangential spring with
// Coulomb cap, and the rolling-resistance moment spring with its cap. Pure physics on one pair,
// callable on host and device, so the analytic tests exercise exactly the code the kernels run.
// Optional physics are template flags: with Rolling = false no rolling code is compiled in.
#include "types.hpp"

namespace grainlab {

enum ContactFlag : std::uint8_t {
  kTouching = 1u << 0,        // overlap > 0 this step
  kSliding = 1u << 1,         // Coulomb cap active (|F_t| reached mu |F_n|)
  kRollingSliding = 1u << 2,  // rolling cap active (|M_r| reached mu_r |F_n| l)
};

struct ContactParams {
  Real E = 100e6;             // k_n = E * rbar                                    [Pa]
  Real kappa = 1.0;           // k_t = kappa * k_n                                 [-]
  Real mu = 0.5;              // Coulomb friction coefficient                     [-]
  Real mu_r = 0.0;            // rolling friction coefficient                     [-]
  Real roll_arm = 0.05;       // l = roll_arm * rbar (SPEC §2)                    [-]
  Real normal_damping = 0.0;  // viscous normal damping ratio beta (choice: off)  [-]
  Real dt = 0.0;              // time step                                         [s]
};

// What a pair carries from step to step (SPEC §2: history belongs to the pair).
struct ContactHistory {
  Vec3 ft;  // tangential force on j   [N]
  Vec3 mr;  // rolling moment on i     [N m]
};

struct ContactResult {
  Vec3 f;         // total force on j (force on i is -f)          [N]
  Vec3 ti, tj;    // torques on i and on j, rolling moment included [N m]
  int flags = 0;  // ContactFlag bits (int, not uint8: a byte type in the vector loop would set GCC's vectorization factor to 64)
};

// Rotate a history vector into the plane normal to n, keeping its length (SPEC §2). Projection plus
// rescaling makes the stored force follow a rigidly rotating contact instead of staying frozen in the
// global frame (test: objectivity).
//
// The length ratio is sqrt(1 + t) with t = (h.n)^2 / |p|^2. Within one step the normal turns by
// ~|v_rel| dt / r (1e-6 rad in a quasi-static test), so t ~ 1e-12: then 1 + t/2 equals sqrt(1 + t) to
// within t^2/8 < 1.3e-17, below double rounding, and saves a sqrt per history vector (perf/NOTES.md,
// attempt 4). Faster rotations (t > 1e-8) take the exact square root.
KOKKOS_FORCEINLINE_FUNCTION Vec3 to_tangent_plane(const Vec3& h, const Vec3& n) {
  const Real hn = dot(h, n);
  const Vec3 p = h - hn * n;
  const Real plen2 = norm2(p);
  // Selects, not branches: the CPU kernel runs this law on 8 pairs side by side in vector registers,
  // which needs a loop body without control flow. plen2 = 0 (also h = 0) gives exactly 0 as before.
  const bool zero = plen2 == Real(0);
  const Real t = hn * hn / (zero ? Real(1) : plen2);
  const Real s = t <= Real(1e-8) ? Real(1) + Real(0.5) * t : math::sqrt(Real(1) + t);
  return Vec3(zero ? Real(0) : s * p.x, zero ? Real(0) : s * p.y, zero ? Real(0) : s * p.z);
}

// v scaled to length cap when |v|^2 = len2 exceeds cap^2 (the Coulomb and rolling caps), else v.
KOKKOS_FORCEINLINE_FUNCTION Vec3 cap_length(const Vec3& v, Real len2, Real cap, bool& capped) {
  capped = len2 > cap * cap;
  const Real s = cap / math::sqrt(capped ? len2 : Real(1));
  return Vec3(capped ? s * v.x : v.x, capped ? s * v.y : v.y, capped ? s * v.z : v.z);
}

template <bool Rolling, bool Viscous>
struct LinearRollingContact {
  // d = x_j - x_i; contact iff the caller found |d| < r_i + r_j. Velocities are the half-step ones
  // (leapfrog), so v*dt is exactly the displacement since the last force evaluation.
  KOKKOS_FORCEINLINE_FUNCTION static ContactResult evaluate(const ContactParams& P, Real ri, Real rj, Real mi,
                                                       Real mj, const Vec3& d, Real dist, const Vec3& vi,
                                                       const Vec3& vj, const Vec3& wi, const Vec3& wj,
                                                       ContactHistory& h) {
    ContactResult out;
    const Vec3 n = (Real(1) / dist) * d;
    const Real delta = ri + rj - dist;
    const Real rbar = Real(0.5) * (ri + rj);
    const Real kn = P.E * rbar;
    const Real kt = P.kappa * kn;

    // (choice) The contact point is the middle of the overlap, lever arms a = r - delta/2. With the
    // same point for i and j a rigid spin of the pair gives zero relative velocity there, so rotation
    // alone never loads the tangential spring (SPEC's r n differs by delta/2, < 1 % of r).
    const Real ai = ri - Real(0.5) * delta;
    const Real aj = rj - Real(0.5) * delta;

    Real fn = kn * delta;
    const Vec3 vrel = (vj + cross(wj, -aj * n)) - (vi + cross(wi, ai * n));
    const Real vn = dot(vrel, n);
    if (Viscous) {
      // Dashpot c = 2 beta sqrt(m* k_n): restitution exp(-pi beta / sqrt(1 - beta^2)) for one contact.
      const Real meff = mi * mj / (mi + mj);
      fn -= Real(2) * P.normal_damping * math::sqrt(meff * kn) * vn;
      fn = fn < Real(0) ? Real(0) : fn;  // (choice) no cohesion from the dashpot
    }
    out.flags = kTouching;

    // Tangential spring: rotate the history, add the increment, cap at mu |F_n|.
    const Vec3 vt = vrel - vn * n;
    Vec3 ft = to_tangent_plane(h.ft, n) - (kt * P.dt) * vt;
    const Real fmax = P.mu * fn;
    bool sliding;
    ft = cap_length(ft, norm2(ft), fmax, sliding);
    out.flags |= sliding ? kSliding : 0;
    h.ft = ft;

    out.f = fn * n + ft;
    const Vec3 nxf = cross(n, out.f);
    out.ti = -ai * nxf;  // (a_i n) x (-F)
    out.tj = -aj * nxf;  // (-a_j n) x F

    if (Rolling) {
      // Iwashita-Oda relative rotation, twisting removed (SPEC §2 choice); k_r = k_t rbar^2.
      const Vec3 dw = wi - wj;
      const Vec3 dtheta = (dw - dot(dw, n) * n) * P.dt;
      Vec3 mr = to_tangent_plane(h.mr, n) - (kt * rbar * rbar) * dtheta;
      const Real mmax = P.mu_r * fn * P.roll_arm * rbar;
      bool rolling_sliding;
      mr = cap_length(mr, norm2(mr), mmax, rolling_sliding);
      out.flags |= rolling_sliding ? kRollingSliding : 0;
      h.mr = mr;
      out.ti += mr;
      out.tj -= mr;
    }
    return out;
  }
};

// Sphere-wall contact, SPEC §3: frictionless, k_w = E_w r (choice), force along the inward normal.
struct Wall {
  Vec3 n;           // inward unit normal
  Real offset = 0;  // plane: n.x = offset; signed distance of a centre = n.x - offset
};

struct WallLaw {
  KOKKOS_INLINE_FUNCTION static Real overlap(const Wall& w, const Vec3& x, Real r) { return r - (dot(w.n, x) - w.offset); }
  KOKKOS_INLINE_FUNCTION static Real stiffness(Real E_wall, Real r) { return E_wall * r; }
};

// SPEC §4 local non-viscous (Cundall) damping: each component of a force (torque) loses alpha of its magnitude
// against the current velocity (angular velocity) component. The integration damps with it, and
// Engine::damping_moment measures the drag it applies (damped(f, v, alpha) - f) with the same expression.
struct CundallDamping {
  KOKKOS_INLINE_FUNCTION static Vec3 damped(const Vec3& f, const Vec3& v, Real alpha) {
    return Vec3(f.x - alpha * math::fabs(f.x) * sign0(v.x), f.y - alpha * math::fabs(f.y) * sign0(v.y),
                f.z - alpha * math::fabs(f.z) * sign0(v.z));
  }
};

}  // namespace grainlab
