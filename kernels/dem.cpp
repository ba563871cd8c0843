#include "dem.hpp"

#include <algorithm>
#include <string>

namespace grainlab {
namespace {

template <class V>
void grow(V& v, const char* label, int n) {
  if (int(v.extent(0)) < n) {
    const int cap = std::max(n, int(1.25 * double(n)) + 16);
    V nv(Kokkos::view_alloc(std::string(label), Kokkos::WithoutInitializing), cap);
    v = nv;
  }
}

template <bool Rolling, bool Viscous>
void pair_forces_impl(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                      const ContactParams& cp) {
  using Law = LinearRollingContact<Rolling, Viscous>;
  auto x = P.x;
  auto v = P.v;
  auto w = P.w;
  auto r = P.r;
  auto m = P.m;
  auto off = L.offsets;
  auto pj = L.pair_j;
  auto ft = H.ft;
  auto mr = H.mr;
  auto flags = H.flags;
  auto fo = F.f;
  auto tjo = F.tj;
  auto rowf = F.row_f;
  auto rowt = F.row_t;
  const char* label = Rolling ? "grainlab::contact::rolling" : "grainlab::contact::sliding";
  // One work item per row i (a few pairs each): i's state is loaded once and its share summed in
  // registers, in row order, so the result does not depend on the thread count (no atomics).
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, P.n), KOKKOS_LAMBDA(int i) {
        const Vec3 xi = load(x, i), vi = load(v, i), wi = load(w, i);
        const Real ri = r(i), mi = m(i);
        Vec3 fi, ti;
        for (int p = off(i); p < off(i + 1); ++p) {
          const int j = pj(p);
          const Vec3 d = load(x, j) - xi;
          const Real rj = r(j);
          const Real dist2 = norm2(d);
          const Real sum = ri + rj;
          if (dist2 >= sum * sum) {  // separated: the pair loses its history (SPEC §2)
            if (flags(p)) {  // history is non-zero only on pairs flagged touching (capture/restore too)
              store(ft, p, Vec3());
              store(mr, p, Vec3());
              flags(p) = 0;
            }
            continue;
          }
          ContactHistory h;
          h.ft = load(ft, p);
          if (Rolling) h.mr = load(mr, p);
          const ContactResult c =
              Law::evaluate(cp, ri, rj, mi, m(j), d, math::sqrt(dist2), vi, load(v, j), wi, load(w, j), h);
          store(ft, p, h.ft);
          if (Rolling) store(mr, p, h.mr);
          flags(p) = c.flags;
          store(fo, p, c.f);
          store(tjo, p, c.tj);
          fi -= c.f;
          ti += c.ti;
        }
        store(rowf, i, fi);
        store(rowt, i, ti);
      });
}

template <bool Damped>
Real integrate_impl(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                    const WallSet& walls, Real E_wall,
                    Real alpha, Real dt) {
  auto x = P.x;
  auto v = P.v;
  auto w = P.w;
  auto fp = P.f;
  auto tp = P.t;
  auto xr = P.x_ref;
  auto r = P.r;
  auto m = P.m;
  auto I = P.inertia;
  auto toff = L.t_offsets;
  auto tpairs = L.t_pairs;
  auto fc = F.f;
  auto tcj = F.tj;
  auto rowf = F.row_f;
  auto rowt = F.row_t;
  const WallSet ws = walls;
  Real maxd2 = 0;
  Kokkos::parallel_reduce(
      Damped ? "grainlab::integrate::damped" : "grainlab::integrate::free", Kokkos::RangePolicy<ExecSpace>(0, P.n),
      KOKKOS_LAMBDA(int i, Real& mx) {
        // Row share (i first: -F, summed by the contact kernel), then the transposed pairs in ascending
        // pair order (i second: +F): a fixed order, so bitwise the same on any thread count.
        Vec3 f = load(rowf, i), t = load(rowt, i);
        for (int k = toff(i); k < toff(i + 1); ++k) {
          const int p = tpairs(k);
          if (!(flags(p) & kTouching)) continue;
          f += load(fc, p);
          t += load(tcj, p);
        }
        const Vec3 xi = load(x, i);
        const Real ri = r(i);
        for (int k = 0; k < ws.count; ++k) {
          const Real dw = WallLaw::overlap(ws.w[k], xi, ri);
          if (dw > 0) f += (WallLaw::stiffness(E_wall, ri) * dw) * ws.w[k].n;
        }
        store(fp, i, f);
        store(tp, i, t);
        Vec3 vi = load(v, i), wi = load(w, i);
        if (Damped) {
          // Cundall local non-viscous damping per component, against the current (half-step) velocity.
          f = Vec3(f.x - alpha * math::fabs(f.x) * sign0(vi.x), f.y - alpha * math::fabs(f.y) * sign0(vi.y),
                   f.z - alpha * math::fabs(f.z) * sign0(vi.z));
          t = Vec3(t.x - alpha * math::fabs(t.x) * sign0(wi.x), t.y - alpha * math::fabs(t.y) * sign0(wi.y),
                   t.z - alpha * math::fabs(t.z) * sign0(wi.z));
        }
        vi += (dt / m(i)) * f;
        wi += (dt / I(i)) * t;
        const Vec3 xn = xi + dt * vi;
        store(v, i, vi);
        store(w, i, wi);
        store(x, i, xn);
        const Real d2 = norm2(xn - load(xr, i));
        mx = d2 > mx ? d2 : mx;
      },
      Kokkos::Max<Real>(maxd2));
  return P.n > 0 ? maxd2 : Real(0);
}

}  // namespace

void compute_pair_forces(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                         const ContactParams& cp, ContactFeatures feat) {
  // Four instantiations chosen once per step on the host: the hot loop carries no feature branches.
  if (feat.rolling) {
    if (feat.viscous) pair_forces_impl<true, true>(P, L, H, F, cp);
    else pair_forces_impl<true, false>(P, L, H, F, cp);
  } else {
    if (feat.viscous) pair_forces_impl<false, true>(P, L, H, F, cp);
    else pair_forces_impl<false, false>(P, L, H, F, cp);
  }
}

Real gather_and_integrate(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                          const WallSet& walls,
                          Real E_wall, Real alpha, Real dt) {
  return alpha > 0 ? integrate_impl<true>(P, L, flags, F, walls, E_wall, alpha, dt)
                   : integrate_impl<false>(P, L, flags, F, walls, E_wall, alpha, dt);
}

WallLoads reduce_wall_loads(const Particles& P, const WallSet& walls, Real E_wall, DeterministicSum& red, bool team) {
  auto x = P.x;
  auto r = P.r;
  const WallSet ws = walls;
  const int nw = ws.count;
  Real out[DeterministicSum::kMaxValues] = {};
  // One term per value per particle (a particle touches wall k once): run_one_term's condition.
  auto loads = KOKKOS_LAMBDA(int i, Real* acc) {
    const Vec3 xi = load(x, i);
    const Real ri = r(i);
    for (int k = 0; k < nw; ++k) {
      const Real dw = WallLaw::overlap(ws.w[k], xi, ri);
      if (dw > 0) {
        const Real kw = WallLaw::stiffness(E_wall, ri);
        acc[3 * k] += kw * dw;
        acc[3 * k + 1] += kw;
        acc[3 * k + 2] += 1;
      }
    }
  };
  if (team)
    red.run_one_term<true>("grainlab::walls::loads", P.n, 3 * nw, loads, out);
  else
    red.run_one_term<false>("grainlab::walls::loads", P.n, 3 * nw, loads, out);
  WallLoads wl;
  for (int k = 0; k < nw; ++k) {
    wl.force[k] = out[3 * k];
    wl.stiffness[k] = out[3 * k + 1];
    wl.touching[k] = int(out[3 * k + 2]);
  }
  return wl;
}

void transfer_history(const PairList& old_list, const PairHistory& old_h, const PairList& new_list,
                      const PairHistory& new_h) {
  auto ooff = old_list.offsets;
  auto oj = old_list.pair_j;
  auto oft = old_h.ft;
  auto omr = old_h.mr;
  auto ofl = old_h.flags;
  auto ni = new_list.pair_i;
  auto nj = new_list.pair_j;
  auto nft = new_h.ft;
  auto nmr = new_h.mr;
  auto nfl = new_h.flags;
  const bool had_old = old_list.offsets.extent(0) > 0 && old_list.npairs > 0;
  Kokkos::parallel_for(
      "grainlab::contact::transfer_history", Kokkos::RangePolicy<ExecSpace>(0, new_list.npairs),
      KOKKOS_LAMBDA(int p) {
        const int i = ni(p), j = nj(p);
        int found = -1;
        if (had_old) {  // binary search of j in the old row of i (rows are sorted by j)
          int lo = ooff(i), hi = ooff(i + 1) - 1;
          while (lo <= hi) {
            const int mid = (lo + hi) / 2;
            const int v = oj(mid);
            if (v == j) {
              found = mid;
              break;
            }
            if (v < j) lo = mid + 1;
            else hi = mid - 1;
          }
        }
        if (found >= 0) {
          store(nft, p, load(oft, found));
          store(nmr, p, load(omr, found));
          nfl(p) = ofl(found);
        } else {
          store(nft, p, Vec3());
          store(nmr, p, Vec3());
          nfl(p) = 0;
        }
      });
}

void ensure_pair_arrays(PairHistory& h, int n) {
  grow(h.ft, "grainlab::history::ft", n);
  grow(h.mr, "grainlab::history::mr", n);
  grow(h.flags, "grainlab::history::flags", n);
}
void ensure_pair_arrays(PairForces& f, int n, int nparticles) {
  grow(f.f, "grainlab::pair::f", n);
  grow(f.tj, "grainlab::pair::tj", n);
  grow(f.row_f, "grainlab::pair::row_f", nparticles);
  grow(f.row_t, "grainlab::pair::row_t", nparticles);
}

}  // namespace grainlab
