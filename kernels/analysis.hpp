#pragma once
// Micromechanical descriptors, SPEC §7, computed on the device over the touching contacts.
// Reductions use the fixed-chunk DeterministicSum (a Kokkos parallel_for over fixed chunks, then one
// ordered pass): the same cost as atomics, but the results, and so every series.csv, are bitwise the
// same on any thread count and after a resume. None of this feeds back into the dynamics.
//
// The contact source is a template parameter: `Src::operator()(p, Contact&)` fills one contact and
// returns false for a pair that is not touching. The engine's source reads positions, pair forces
// and flags; tests feed synthetic contact sets through the same kernel.
#include "dem.hpp"

namespace grainlab {

struct Contact {
  Vec3 n;     // unit normal, i -> j
  Real l;     // branch length |x_j - x_i|
  Vec3 f;     // force on j
  std::uint8_t flags;
};

// A symmetric 3x3 tensor as (xx, yy, zz, xy, yz, zx).
struct Sym {
  Real v[6] = {};
  Real operator()(int i, int j) const;
  Real trace() const { return v[0] + v[1] + v[2]; }
  Sym deviator() const;
  Real ddot(const Sym& o) const;  // a:b
  Sym scaled(Real s) const;
  static Sym symmetric_part(const Real (&m)[3][3]);
};

// p = tr/3 and q = sqrt(3/2 s:s) of a stress tensor (compression positive).
void stress_invariants(const Sym& sigma, Real& p, Real& q);

struct Network {
  int nc = 0;
  Sym ac, ad, an, at;           // anisotropy tensors (deviatoric)
  Real a_c = 0, a_d = 0, a_n = 0, a_t = 0;  // signed invariants (SPEC §7)
  Real d0 = 0, f0 = 0;          // mean weighted branch length and normal force
};

struct Descriptors {
  Real sigma[3][3] = {};        // Christoffersen stress over sphere-sphere contacts (SPEC §7),
                                // compression positive                                      [Pa]
  Real p = 0, q = 0;            // from sigma: p = tr/3, q = sqrt(3/2 s:s)                    [Pa]
  // sigma plus the sphere-wall contacts' terms F_w (x) a n_w (lever a = r - delta/2). By the Love-Weber
  // identity (each particle's moment sum, internal contacts cancelling) this equals the wall stress in
  // static equilibrium; SPEC's sum misses the boundary layer, ~ 2 r / L of the stress.
  Real sigma_walls[3][3] = {};
  Real p_walls = 0, q_walls = 0;
  Network all, strong, weak;
  Real sff = 0;                 // 2/5 (a_c + a_d + a_n + 3/2 a_t) (total network)
  Real share[4] = {};           // each term's share of that sum (c, d, n, t)
  int nc = 0, np = 0, sliding = 0, rolling_sliding = 0, weak_count = 0, sliding_weak = 0;
  int rattlers0 = 0, rattlers1 = 0;  // particles with 0 and 1 contacts
  Real z = 0, z_mech = 0, f_mean = 0;
  Real weak_frac = 0, sliding_frac = 0, sliding_weak_frac = 0, rolling_sliding_frac = 0;
};

// Signed scalar of an anisotropy tensor: sign(a:s) sqrt(3/2 a:a) (SPEC §7).
Real signed_invariant(const Sym& a, const Sym& s_dev);

// Finishes network tensors from the raw sums (shared by the kernel path and the host reference).
// fabric: sum n n; wd, wn, wt: weighted sums of |d| n n, f_n n n, sym(f_t n).
void finish_network(Network& net, const Sym& fabric_sum, const Sym& wd, const Sym& wn, const Sym& wt, const Sym& s_dev);

// Contacts are visited row by row: row r holds the contacts [offsets(r), offsets(r+1)) (the engine's
// rows are its particles' half-list rows). Sums are taken per row in row order, then over fixed chunks of
// rows, so they depend only on the set of touching pairs, not on which non-touching pairs a neighbour
// list happens to hold: the same bits after a restart or a different rebuild schedule.
template <class Src>
Descriptors compute_descriptors(const Src& src, const IntView& offsets, int nrows, int nparticles, Real volume,
                                DeterministicSum& red);

// The engine's contacts at the current evaluation (positions, pair forces, flags of the same step).
struct EngineContacts {
  VecView x;
  PairVecView f;
  IntView pi, pj;
  FlagView flags;
  KOKKOS_INLINE_FUNCTION bool operator()(int p, Contact& c) const {
    c.flags = flags(p);
    if (!(c.flags & kTouching)) return false;
    const int i = pi(p), j = pj(p);
    const Vec3 d = load(x, j) - load(x, i);
    c.l = norm(d);
    c.n = (Real(1) / c.l) * d;
    c.f = load(f, p);
    return true;
  }
};

// The volume of a sphere of radius r on the lower side of the plane at signed distance t from its centre along one
// axis (t clipped to [-r, r]): the spherical cap pi h^2 (3 r - h) / 3 with h = r + t.
KOKKOS_INLINE_FUNCTION Real sphere_volume_below(Real t, Real r) {
  t = t < -r ? -r : (t > r ? r : t);
  return Real(M_PI / 3) * (r + t) * (r + t) * (2 * r - t);
}

// The volume of the ball of radius r about the origin in the octant {x > a, y > b, z > c}, for a, b, c >= 0.
// Sliced across x, the slice at x is the disk of radius rho = sqrt(r^2 - x^2) in the quadrant {y > b, z > c}, of area
//   Q = 1/2 [rho^2 (pi/2 - asin(b/rho) - asin(c/rho)) - b sqrt(rho^2 - b^2) - c sqrt(rho^2 - c^2) + 2 b c]
// (Green's theorem round its boundary: the two segments from the corner (b, c) to the circle and the arc between)
// while the corner is inside the disk, x < x_m = sqrt(r^2 - b^2 - c^2), and 0 beyond. The volume is the integral of Q
// from a to x_m, in closed form F(x_m) - F(a) with
//   F = pi/4 (r^2 x - x^3/3) - G_b - G_c + b c x, and for s = b, c (q = sqrt(r^2 - x^2 - s^2), G_0 = 0):
//   G_s = 1/2 [(r^2 x - x^3/3) asin(s/rho) + s (3 r^2 - s^2)/3 asin(x/k) + 2/3 s x q - 2/3 r^3 atan2(x s, r q)],
// k^2 = r^2 - s^2: the asin(s/rho) term integrated by parts (its derivative s x / (rho^2 sqrt(rho^2 - s^2))), the rest
// standard integrals of x^2 / sqrt(k^2 - x^2) and 1 / ((r^2 - x^2) sqrt(k^2 - x^2)). The arcsines are taken as
// atan2(s, q) and atan2(x, q): their arguments near 1 (at x_m where the other corner coordinate is small) lost half the
// digits (a box's two halves summed over a packing differed by 1e-9 of it), and at x_m q is exactly the other
// coordinate (q_b = c, q_c = b). Computed in double whatever Real is: the box's inclusion-exclusion below subtracts
// terms of the sphere's volume.
KOKKOS_INLINE_FUNCTION double ball_octant_volume(double a, double b, double c, double r) {
  const double xm2 = r * r - b * b - c * c;
  if (!(xm2 > 0) || a * a >= xm2) return 0;  // the corner (a, b, c) outside the ball: nothing in the octant
  const double xm = math::sqrt(xm2);
  auto G = [r](double x, double s, double q) {
    if (!(s > 0)) return 0.0;
    return 0.5 * ((r * r * x - x * x * x / 3) * math::atan2(s, q) + s * (3 * r * r - s * s) / 3 * math::atan2(x, q) +
                  2.0 / 3.0 * s * x * q - 2.0 / 3.0 * r * r * r * math::atan2(x * s, r * q));
  };
  auto F = [&](double x, double qb, double qc) {
    return 0.25 * M_PI * (r * r * x - x * x * x / 3) - G(x, b, qb) - G(x, c, qc) + b * c * x;
  };
  const double qb = r * r - a * a - b * b, qc = r * r - a * a - c * c;
  return F(xm, c, b) - F(a, math::sqrt(qb > 0 ? qb : 0.0), math::sqrt(qc > 0 ? qc : 0.0));
}

// The same for an octant of any corner: a negative coordinate t by the ball's symmetry in that axis (the part beyond
// t < 0 is the whole slab's two halves less the part beyond -t), so a sum of at most 8 octants with a, b, c >= 0.
KOKKOS_INLINE_FUNCTION double ball_octant_volume_signed(double a, double b, double c, double r) {
  const double t[3] = {a < -r ? -r : a, b < -r ? -r : b, c < -r ? -r : c};
  double sum = 0;
  for (int m = 0; m < 8; ++m) {  // bit k of m: for a negative t[k], its -t[k] term (else its 0 term)
    double at[3], w = 1;
    bool used = true;
    for (int k = 0; k < 3; ++k) {
      const bool alt = (m >> k) & 1;
      if (t[k] >= 0) {
        used = used && !alt;
        at[k] = t[k];
      } else {
        at[k] = alt ? -t[k] : 0.0;
        w *= alt ? -1.0 : 2.0;
      }
    }
    if (used) sum += w * ball_octant_volume(at[0], at[1], at[2], r);
  }
  return sum;
}

// The volume of a sphere (centre c, radius r) inside the box [lo, hi], exact. A sphere that faces of one axis at most
// cut (one whole inside, or the common case in a box of many spheres): the sphere's volume times its share between
// that axis's faces, the difference of two caps. One that faces of two or three axes cut (straddling an edge or a
// corner): the inclusion-exclusion of the eight octants at the box's corners (ball_octant_volume_signed). (The
// product of the three shares it replaced was off by up to 2.3e-2 of a sphere on the random boxes of test
// Analysis.SphereVolumeInABoxExactAtEdgesAndCorners, and gave a small box about the sphere's centre 27 pi / 48 = 1.77
// times its volume, each share being 3 w / (4 r) there; both printed by the test.) Shares over adjacent boxes add up
// to the sphere, so the volumes of a box's parts sum to the box's.
KOKKOS_INLINE_FUNCTION Real sphere_volume_in_box(const Vec3& c, Real r, const Vec3& lo, const Vec3& hi) {
  const Real v = Real(4 * M_PI / 3) * r * r * r;
  Real in = v;
  int cut_axes = 0;
  for (int a = 0; a < 3; ++a) {
    const Real l = lo[a] - c[a], h = hi[a] - c[a];
    if (!(h > -r && l < r && h > l)) return 0;  // apart along this axis, or an empty box
    cut_axes += l > -r || h < r;
    const Real s = sphere_volume_below(h, r) - sphere_volume_below(l, r);
    in *= (s > 0 ? s : Real(0)) / v;
  }
  if (cut_axes <= 1) return in;
  double sum = 0;
  for (int m = 0; m < 8; ++m) {
    const int i = m & 1, j = (m >> 1) & 1, k = (m >> 2) & 1;
    const double o = ball_octant_volume_signed(double((i ? hi[0] : lo[0]) - c[0]), double((j ? hi[1] : lo[1]) - c[1]),
                                               double((k ? hi[2] : lo[2]) - c[2]), double(r));
    sum += ((i + j + k) & 1) ? -o : o;
  }
  return Real(sum > 0 ? sum : 0.0);
}

// Particles with 0 and 1 touching contacts (rattlers for the mechanical coordination number).
void count_rattlers(const Particles& P, const PairList& L, const PairHistory& H, DeterministicSum& red, int& n0, int& n1);

}  // namespace grainlab

#include "analysis_impl.hpp"
