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

// The volume of a sphere (centre c, radius r) inside the box [lo, hi]: the sphere's volume times the share of it
// between each pair of faces (the difference of two caps along that axis). Exact for a sphere that at most one face
// cuts, for one whole inside, and for faces through the centre (a corner at the centre: 1/8); for a sphere that two
// faces cut off-centre (straddling an edge) the product of the shares errs by at most ~1 % of that sphere (two faces
// at r/2: 0.702 of it inside against the product's 0.712). Shares over adjacent boxes add up to the sphere, so the
// volumes of a box's parts sum to the box's.
KOKKOS_INLINE_FUNCTION Real sphere_volume_in_box(const Vec3& c, Real r, const Vec3& lo, const Vec3& hi) {
  const Real v = Real(4 * M_PI / 3) * r * r * r;
  Real in = v;
  for (int a = 0; a < 3; ++a) {
    const Real s = sphere_volume_below(hi[a] - c[a], r) - sphere_volume_below(lo[a] - c[a], r);
    in *= (s > 0 ? s : Real(0)) / v;
  }
  return in;
}

// Particles with 0 and 1 touching contacts (rattlers for the mechanical coordination number).
void count_rattlers(const Particles& P, const PairList& L, const PairHistory& H, DeterministicSum& red, int& n0, int& n1);

}  // namespace grainlab

#include "analysis_impl.hpp"
