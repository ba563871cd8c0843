#include "dem.hpp"
#include "huge_pages.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <string>

#if GRAINLAB_PAIR_LANES && defined(__AVX__)
#include <immintrin.h>
#endif

namespace grainlab {
namespace {

// SPEC §2 on listed pair p of particle i, with i's position and radius given: the views it reads and writes,
// shared by the row kernel and the one-pair-per-thread kernel, so that both run the same code (and bits).
struct ListedPair {
  VecView x, v, w;
  RealView r, m;
  IntView pj;
  PairVecView ft, mr;
  FlagView flags;
  PairVecView fo, tjo;
  ListedPair(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F)
      : x(P.x), v(P.v), w(P.w), r(P.r), m(P.m), pj(L.pair_j), ft(H.ft), mr(H.mr), flags(H.flags), fo(F.f), tjo(F.tj) {}
  // false: separated, and the pair loses its history (SPEC §2); nothing else is written. true: c holds the
  // law's result; the history, flags, force on j and torque on j are stored.
  template <bool Rolling, bool Viscous>
  KOKKOS_INLINE_FUNCTION bool evaluate(const ContactParams& cp, int p, int i, const Vec3& xi, Real ri,
                                       ContactResult& c) const {
    const int j = pj(p);
    const Vec3 d = load(x, j) - xi;
    const Real rj = r(j);
    const Real dist2 = norm2(d);
    const Real sum = ri + rj;
    if (dist2 >= sum * sum) {
      if (flags(p)) {  // history is non-zero only on pairs flagged touching (capture/restore too)
        store(ft, p, Vec3());
        store(mr, p, Vec3());
        flags(p) = 0;
      }
      return false;
    }
    ContactHistory h;
    h.ft = load(ft, p);
    if (Rolling) h.mr = load(mr, p);
    c = LinearRollingContact<Rolling, Viscous>::evaluate(cp, ri, rj, m(i), m(j), d, math::sqrt(dist2), load(v, i),
                                                         load(v, j), load(w, i), load(w, j), h);
    store(ft, p, h.ft);
    if (Rolling) store(mr, p, h.mr);
    flags(p) = c.flags;
    store(fo, p, c.f);
    store(tjo, p, c.tj);
    return true;
  }
};

template <bool Rolling, bool Viscous>
void pair_forces_impl(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                      const ContactParams& cp) {
  const ListedPair lp(P, L, H, F);
  auto off = L.offsets;
  auto rowf = F.row_f;
  auto rowt = F.row_t;
  const char* label = Rolling ? "grainlab::contact::rolling" : "grainlab::contact::sliding";
  // One work item per row i (a few pairs each): i's share summed in registers, in row order, so the result
  // does not depend on the thread count (no atomics).
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, P.n), KOKKOS_LAMBDA(int i) {
        const Vec3 xi = load(lp.x, i);
        const Real ri = lp.r(i);
        Vec3 fi, ti;
        for (int p = off(i); p < off(i + 1); ++p) {
          ContactResult c;
          if (!lp.template evaluate<Rolling, Viscous>(cp, p, i, xi, ri, c)) continue;
          fi -= c.f;
          ti += c.ti;
        }
        store(rowf, i, fi);
        store(rowt, i, ti);
      });
}

// SPEC §2 with one work item per pair of the list and the pair-lane kernel's outputs (f, tj and ti at the
// pair's index, +0 for a separated pair), which the integration sums in the row kernel's order: the same bits
// as both (perf/NOTES.md attempt 30). For GPUs: the row kernel runs a row's ~3 pairs as one dependent chain
// per thread (37 us for 32k particles on an H100, one thread per particle; 14 us here).
template <bool Rolling, bool Viscous>
void pair_forces_pairs_impl(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                            const ContactParams& cp) {
  const ListedPair lp(P, L, H, F);
  auto pi = L.pair_i;
  auto tio = F.ti;
  const char* label = Rolling ? "grainlab::contact::rolling_pairs" : "grainlab::contact::sliding_pairs";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, L.npairs), KOKKOS_LAMBDA(int p) {
        const int i = pi(p);
        ContactResult c;
        if (lp.template evaluate<Rolling, Viscous>(cp, p, i, load(lp.x, i), lp.r(i), c)) {
          store(tio, p, c.ti);
        } else {  // separated: its shares read +0
          store(lp.fo, p, Vec3());
          store(lp.tjo, p, Vec3());
          store(tio, p, Vec3());
        }
      });
}

#if GRAINLAB_PAIR_LANES
// SPEC §2 on C consecutive pairs of the CSR list at once, as one vector loop (perf/NOTES.md attempt 20).
// The row kernel above runs the law's ~300 dependent instructions one pair at a time; here lane l of a
// vector register holds pair p0 + l, whatever row it belongs to, so the law runs on C pairs side by side.
// Every lane is computed, and selects zero the outputs and the history of separated pairs (branches would
// break the vector loop). The outputs stay in CSR order at their pair's index, so the transposed gather
// keeps the locality the row kernel gives it (attempt 17 lost its kernel gain there: slot order). i's share
// cannot be summed in registers across lanes of different rows, so the torque on i is stored per pair (ti)
// and the integration sums row i's pairs, in row order, from +0: the row kernel's additions, so the same
// bits (a +0 written for a separated pair adds nothing to a sum that starts at +0, which is never -0).
// a[3 p + q] = component q of v where `on`, else +0 (a select, not a branch: the loop stays one vector loop).
KOKKOS_FORCEINLINE_FUNCTION void store_lane(PairReal* __restrict a, int p, bool on, const Vec3& v) {
  const Real z = 0;
  a[3 * p] = PairReal(on ? v.x : z);
  a[3 * p + 1] = PairReal(on ? v.y : z);
  a[3 * p + 2] = PairReal(on ? v.z : z);
}

// The state of both particles of one lane, as the law reads it.
struct LaneState {
  Vec3 xi, xj, vi, vj, wi, wj;
  Real ri, rj, mi, mj;
};

template <bool Rolling, bool Viscous>
KOKKOS_FORCEINLINE_FUNCTION void lane_pair(int p, const ContactParams& cp, const LaneState& s,
                                           PairReal* __restrict FT, PairReal* __restrict MR,
                                           PairReal* __restrict FO, PairReal* __restrict TJ,
                                           PairReal* __restrict TI, int& flag) {
  using Law = LinearRollingContact<Rolling, Viscous>;
  const Vec3 d = s.xj - s.xi;
  const Real dist2 = norm2(d);
  const Real sum = s.ri + s.rj;
  const bool touching = !(dist2 >= sum * sum);  // the row kernel's test
  ContactHistory h;
  h.ft = Vec3(FT[3 * p], FT[3 * p + 1], FT[3 * p + 2]);
  if (Rolling) h.mr = Vec3(MR[3 * p], MR[3 * p + 1], MR[3 * p + 2]);
  // A separated lane evaluates at dist = r_i + r_j (zero overlap, finite values); its results are dropped.
  const ContactResult c = Law::evaluate(cp, s.ri, s.rj, s.mi, s.mj, d, touching ? math::sqrt(dist2) : sum, s.vi,
                                        s.vj, s.wi, s.wj, h);
  // A separated pair loses its history (SPEC §2), and its outputs read as +0.
  store_lane(FT, p, touching, h.ft);
  if (Rolling) store_lane(MR, p, touching, h.mr);
  store_lane(FO, p, touching, c.f);
  store_lane(TJ, p, touching, c.tj);
  store_lane(TI, p, touching, c.ti);
  flag = touching ? c.flags : 0;
}

// Lane-major staging of a 3-vector field for 4 lanes: out[q * C + k] = A[3 idx[k] + q] (LayoutRight records of
// 3 doubles), for k = 0..3 and q = 0..2. The vector loop then reads the lanes' x, v, w with contiguous loads.
// Until attempt 33 GCC gathered them in the loop: 36 vgatherdpd per 8-lane block for x, v, w of i and j, whose
// stalls (seen on the kmovb after each gather) held ~25 % of the kernel's samples. Here each record is one
// masked 256-bit load (the masked-off fourth double is not read, so the last particle is safe) and the 4 x 4
// transpose is 7 shuffles. Only data moves: the law sees the same values, so the same bits.
template <int C>
KOKKOS_FORCEINLINE_FUNCTION void stage4(const Real* __restrict A, const int* __restrict idx, Real* __restrict out) {
#if defined(__AVX__)
  static_assert(std::is_same_v<Real, double>, "stage4 transposes doubles");
  const __m256i m = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d a = _mm256_maskload_pd(A + 3 * idx[0], m);  // ax ay az -
  const __m256d b = _mm256_maskload_pd(A + 3 * idx[1], m);
  const __m256d c = _mm256_maskload_pd(A + 3 * idx[2], m);
  const __m256d d = _mm256_maskload_pd(A + 3 * idx[3], m);
  const __m256d ab_lo = _mm256_unpacklo_pd(a, b);  // ax bx az bz
  const __m256d ab_hi = _mm256_unpackhi_pd(a, b);  // ay by -  -
  const __m256d cd_lo = _mm256_unpacklo_pd(c, d);  // cx dx cz dz
  const __m256d cd_hi = _mm256_unpackhi_pd(c, d);  // cy dy -  -
  _mm256_storeu_pd(out, _mm256_permute2f128_pd(ab_lo, cd_lo, 0x20));          // ax bx cx dx
  _mm256_storeu_pd(out + C, _mm256_permute2f128_pd(ab_hi, cd_hi, 0x20));      // ay by cy dy
  _mm256_storeu_pd(out + 2 * C, _mm256_permute2f128_pd(ab_lo, cd_lo, 0x31));  // az bz cz dz
#else
  for (int k = 0; k < 4; ++k)
    for (int q = 0; q < 3; ++q) out[q * C + k] = A[3 * idx[k] + q];
#endif
}

// The same for a scalar field: out[k] = A[idx[k]], k = 0..3, by scalar loads instead of a gather (r and m:
// 1.03x on the step against gathering them in the loop, perf/NOTES.md attempt 33b).
KOKKOS_FORCEINLINE_FUNCTION void stage4_scalar(const Real* __restrict A, const int* __restrict idx, Real* __restrict out) {
#if defined(__AVX__)
  _mm256_storeu_pd(out, _mm256_setr_pd(A[idx[0]], A[idx[1]], A[idx[2]], A[idx[3]]));
#else
  for (int k = 0; k < 4; ++k) out[k] = A[idx[k]];
#endif
}

template <bool Rolling, bool Viscous>
void pair_forces_lanes_impl(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                            const ContactParams& cp_in) {
  constexpr int C = kPairLanesWidth;
  static_assert(C % 4 == 0, "stage4 fills the lanes four at a time");
  // 64 pairs ahead. 32 measured the same with the gathers (attempt 23). Since the staging, farther is faster at 1
  // thread (128/64 1.022x, 256/128 1.086x) but 256/64 is 0.975x at 2 threads, the headline (perf/NOTES.md attempt 40).
  constexpr int kPrefetchBlocks = 64 / C;
  static_assert(std::is_same_v<VecLayout, Kokkos::LayoutRight>, "the pair-lane kernel indexes x(i, q) as 3 i + q");
  if (L.npairs == 0) return;
  // Raw pointers: the staging (stage4) and the vector loop index the arrays by plain pointer arithmetic, which
  // GCC vectorizes (through a View's operator() it did not).
  const int* PI_ = L.pair_i.data();
  const int* PJ_ = L.pair_j.data();
  const Real* X_ = P.x.data();
  const Real* V_ = P.v.data();
  const Real* W_ = P.w.data();
  const Real* R_ = P.r.data();
  const Real* M_ = P.m.data();
  PairReal* FT_ = H.ft.data();
  PairReal* MR_ = H.mr.data();
  PairReal* FO_ = F.f.data();
  PairReal* TJ_ = F.tj.data();
  PairReal* TI_ = F.ti.data();
  std::uint8_t* FL_ = H.flags.data();
  const int npairs = L.npairs;
  const int nblocks = (npairs + C - 1) / C;
  const char* label = Rolling ? "grainlab::contact::rolling_lanes" : "grainlab::contact::sliding_lanes";
  // Dynamic schedule: each block writes only its own pairs, so which thread takes it changes no bit, and the
  // threads finish together even when the cores run at different speeds (this VM's two do: 2 threads,
  // 1.09x median of 12 alternating runs against the static schedule, perf/NOTES.md attempt 20).
  Kokkos::parallel_for(
      label, dynamic_range(nblocks), KOKKOS_LAMBDA(int b) {
        // Local restrict copies: through the closure every store could alias the captured pointers, and
        // GCC would then neither hoist the loads nor if-convert the loop.
        const int* __restrict PI = PI_;
        const int* __restrict PJ = PJ_;
        const Real* __restrict X = X_;
        const Real* __restrict V = V_;
        const Real* __restrict W = W_;
        const Real* __restrict R = R_;
        const Real* __restrict M = M_;
        PairReal* __restrict FT = FT_;
        PairReal* __restrict MR = MR_;
        PairReal* __restrict FO = FO_;
        PairReal* __restrict TJ = TJ_;
        PairReal* __restrict TI = TI_;
        const ContactParams cp = cp_in;
        const int p0 = b * C;
        int fl[C];
        {
          // j's state for the block kPrefetchBlocks ahead: the loads below stalled on it (perf at 256k put ~40 % of
          // the kernel's samples right after the gathers that preceded attempt 33's staging). The lanes' j are
          // near-random within the neighbourhood, which the hardware prefetcher cannot follow; i's rows are
          // sequential, which it can.
          // Measured (perf/NOTES.md attempt 23), 64 pairs ahead: 1.23x on the step at 32k, 1.35x at 256k.
          const int q0 = p0 + kPrefetchBlocks * C;
          const int q1 = q0 + C < npairs ? q0 + C : npairs;
          for (int q = q0; q < q1; ++q) {
            const int j = PJ[q];
            __builtin_prefetch(X + 3 * j);
            __builtin_prefetch(V + 3 * j);
            __builtin_prefetch(W + 3 * j);
            __builtin_prefetch(R + j);
            __builtin_prefetch(M + j);
          }
        }
        if (p0 + C <= npairs) {
          // x, v, w of i and j for the C lanes, lane-major: S[field][component][lane] (stage4).
          alignas(64) Real S[6][3][C];
          alignas(64) Real Q[4][C];  // r_i, r_j, m_i, m_j
          for (int g = 0; g < C; g += 4) {
            stage4<C>(X, PI + p0 + g, &S[0][0][g]);
            stage4<C>(X, PJ + p0 + g, &S[1][0][g]);
            stage4<C>(V, PI + p0 + g, &S[2][0][g]);
            stage4<C>(V, PJ + p0 + g, &S[3][0][g]);
            stage4<C>(W, PI + p0 + g, &S[4][0][g]);
            stage4<C>(W, PJ + p0 + g, &S[5][0][g]);
            stage4_scalar(R, PI + p0 + g, &Q[0][g]);
            stage4_scalar(R, PJ + p0 + g, &Q[1][g]);
            stage4_scalar(M, PI + p0 + g, &Q[2][g]);
            stage4_scalar(M, PJ + p0 + g, &Q[3][g]);
          }
#pragma GCC ivdep
          for (int l = 0; l < C; ++l) {
            const LaneState s{Vec3(S[0][0][l], S[0][1][l], S[0][2][l]), Vec3(S[1][0][l], S[1][1][l], S[1][2][l]),
                              Vec3(S[2][0][l], S[2][1][l], S[2][2][l]), Vec3(S[3][0][l], S[3][1][l], S[3][2][l]),
                              Vec3(S[4][0][l], S[4][1][l], S[4][2][l]), Vec3(S[5][0][l], S[5][1][l], S[5][2][l]),
                              Q[0][l], Q[1][l], Q[2][l], Q[3][l]};
            lane_pair<Rolling, Viscous>(p0 + l, cp, s, FT, MR, FO, TJ, TI, fl[l]);
          }
          for (int l = 0; l < C; ++l) FL_[p0 + l] = std::uint8_t(fl[l]);
        } else {  // the last, partial block, straight from the particle arrays
          for (int p = p0; p < npairs; ++p) {
            const int i = PI[p], j = PJ[p];
            const LaneState s{Vec3(X[3 * i], X[3 * i + 1], X[3 * i + 2]), Vec3(X[3 * j], X[3 * j + 1], X[3 * j + 2]),
                              Vec3(V[3 * i], V[3 * i + 1], V[3 * i + 2]), Vec3(V[3 * j], V[3 * j + 1], V[3 * j + 2]),
                              Vec3(W[3 * i], W[3 * i + 1], W[3 * i + 2]), Vec3(W[3 * j], W[3 * j + 1], W[3 * j + 2]),
                              R[i], R[j], M[i], M[j]};
            lane_pair<Rolling, Viscous>(p, cp, s, FT, MR, FO, TJ, TI, fl[0]);
            FL_[p] = std::uint8_t(fl[0]);
          }
        }
      });
}
#endif

// The per-wall sums as DeterministicSum leaves them: wall k's k_w delta, k_w and count at 3 k, 3 k + 1, 3 k + 2.
WallLoads unpack_wall_loads(const Real* out, int nw) {
  WallLoads wl;
  for (int k = 0; k < nw; ++k) {
    wl.force[k] = out[3 * k];
    wl.stiffness[k] = out[3 * k + 1];
    wl.touching[k] = int(out[3 * k + 2]);
  }
  return wl;
}

// Particle i's terms of the wall loads (wall k: k_w delta, k_w, 1 at 3 k, 3 k + 1, 3 k + 2), one term per value
// per particle (a particle touches wall k once): DeterministicSum::run_one_term's condition. A named functor:
// reduce_wall_loads and the GPU's fused step share it.
struct WallLoadTerms {
  VecView x;
  RealView r;
  WallSet ws;
  Real E_wall;
  KOKKOS_INLINE_FUNCTION void operator()(int i, Real* acc) const {
    const Vec3 xi = load(x, i);
    const Real ri = r(i);
    for (int k = 0; k < ws.count; ++k) {
      const Real dw = WallLaw::overlap(ws.w[k], xi, ri);
      if (dw > 0) {
        const Real kw = WallLaw::stiffness(E_wall, ri);
        acc[3 * k] += kw * dw;
        acc[3 * k + 1] += kw;
        acc[3 * k + 2] += 1;
      }
    }
  }
};

// Move = false: the gather alone (total force and torque at the evaluated instant into P.f, P.t), for
// measurements between evaluate() and advance(); the same code, so the same bits as the integration's.
// Store = false: P.f and P.t are left alone. Nothing in the dynamics reads them, and on the fused step that
// measures nothing the two stores cost 1.05-1.08x of the step (perf/NOTES.md attempt 27).
// device_max (with Loads = false): the max goes to that device address instead of the host (attempt 32); NaN
// is returned.
// Drag (with Loads): acc also sums the damping's drag moment about drag_c after the wall terms, into *drag_moment
// (gather_integrate_and_load_walls with a DragMeasure).
template <bool Damped, bool RowPairs, bool Loads, bool Store, bool Move, bool Drag = false>
Real integrate_impl(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                    const WallSet& walls, Real E_wall, Real alpha, Real dt, DeterministicSum* red, WallLoads* loads,
                    Real* device_max = nullptr, const Vec3& drag_c = Vec3(), Vec3* drag_moment = nullptr) {
  static_assert(!Drag || (Loads && Move), "the drag moment rides on the loads' sums, in a kick");
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
  auto off = L.offsets;
  auto tci = F.ti;
  const WallSet ws = walls;
  // One particle: gather, walls, damping, kick, drift. With Loads it also adds its wall terms to acc in
  // reduce_wall_loads' order (wall k: k_w delta, k_w, 1), from the same overlaps at the same x(t).
  auto particle = KOKKOS_LAMBDA(int i, Real* acc, Real& mx) {
    // drag_c named outside the if constexpr below: nvcc's extended lambdas may not first-capture inside one
    const Vec3 c = drag_c;
    // Row share (i first: -F, summed by the contact kernel), then the transposed pairs in ascending
    // pair order (i second: +F): a fixed order, so bitwise the same on any thread count.
    Vec3 f, t;
    if (RowPairs) {  // the per-pair shares of i (Lanes, Pairs), summed as the row kernel sums them
      for (int p = off(i); p < off(i + 1); ++p) {
        f -= load(fc, p);
        t += load(tci, p);
      }
    } else {
      f = load(rowf, i);
      t = load(rowt, i);
    }
    for (int k = toff(i); k < toff(i + 1); ++k) {
      const int p = tpairs(k);
      // The pair-lane kernel writes +0 for separated pairs, which adds nothing (see above): no flag load.
      if (!RowPairs && !(flags(p) & kTouching)) continue;
      f += load(fc, p);
      t += load(tcj, p);
    }
    const Vec3 xi = load(x, i);
    const Real ri = r(i);
    for (int k = 0; k < ws.count; ++k) {
      const Real dw = WallLaw::overlap(ws.w[k], xi, ri);
      if (dw > 0) {
        const Real kw = WallLaw::stiffness(E_wall, ri);
        f += (kw * dw) * ws.w[k].n;
        if (Loads) {
          acc[3 * k] += kw * dw;
          acc[3 * k + 1] += kw;
          acc[3 * k + 2] += 1;
        }
      }
    }
    if (Store) {
      store(fp, i, f);
      store(tp, i, t);
    }
    if (!Move) return;
    Vec3 vi = load(v, i), wi = load(w, i);
    if (Damped) {
      // Cundall local non-viscous damping per component, against the current (half-step) velocity.
      const Vec3 fd = CundallDamping::damped(f, vi, alpha);
      if constexpr (Drag) {  // Engine::damping_moment's terms, in its order
        const Vec3 drag = fd - f;
        const Vec3 d = xi - c;
        acc[3 * ws.count] += d.x * drag.x;
        acc[3 * ws.count + 1] += d.y * drag.y;
        acc[3 * ws.count + 2] += d.z * drag.z;
      }
      f = fd;
      t = CundallDamping::damped(t, wi, alpha);
    }
    vi += (dt / m(i)) * f;
    wi += (dt / I(i)) * t;
    const Vec3 xn = xi + dt * vi;
    store(v, i, vi);
    store(w, i, wi);
    store(x, i, xn);
    const Real d2 = norm2(xn - load(xr, i));
    mx = d2 > mx ? d2 : mx;
  };
  const char* label = !Move ? "grainlab::gather::forces" : Damped ? "grainlab::integrate::damped" : "grainlab::integrate::free";
  if constexpr (Loads) {
    Real out[DeterministicSum::kMaxValues] = {};
    const Real maxd2 = red->run_with_max(label, P.n, 3 * ws.count + (Drag ? 3 : 0), particle, out);
    *loads = unpack_wall_loads(out, ws.count);
    if constexpr (Drag) *drag_moment = Vec3(out[3 * ws.count], out[3 * ws.count + 1], out[3 * ws.count + 2]);
    return maxd2;
  } else {
    Real maxd2 = 0;
    // Dynamic schedule as in the pair-lane kernel: per-particle outputs and an exact max, so no bit depends on it.
    const DynamicRange policy = dynamic_range(P.n);
    auto body = KOKKOS_LAMBDA(int i, Real& mx) { particle(i, nullptr, mx); };
    if (device_max) {
      // Into device memory: the launch returns without waiting for the kernel (no copy to the host yet).
      using Max = Kokkos::Max<Real, MemSpace>;
      Kokkos::parallel_reduce(label, policy, body, Max(typename Max::result_view_type(device_max)));
      return std::numeric_limits<Real>::quiet_NaN();
    }
    Kokkos::parallel_reduce(label, policy, body, Kokkos::Max<Real>(maxd2));
    return P.n > 0 ? maxd2 : Real(0);
  }
}

}  // namespace

void compute_pair_forces(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                         const ContactParams& cp, ContactFeatures feat, PairKernel kernel) {
  if (kernel == PairKernel::Lanes && !kPairLanesBuilt)
    throw std::logic_error("compute_pair_forces: the pair-lane kernel is not built here (kPairLanesBuilt)");
  // Four instantiations per kernel chosen once per step on the host: the hot loop carries no feature branches.
  auto run = [&](auto rolling, auto viscous) {
    constexpr bool R = decltype(rolling)::value, V = decltype(viscous)::value;
    if (kernel == PairKernel::Pairs) {
      pair_forces_pairs_impl<R, V>(P, L, H, F, cp);
    } else if (kernel == PairKernel::Lanes) {
#if GRAINLAB_PAIR_LANES
      if constexpr (kPairLanesBuilt) pair_forces_lanes_impl<R, V>(P, L, H, F, cp);
#endif
    } else {
      pair_forces_impl<R, V>(P, L, H, F, cp);
    }
  };
  using Y = std::true_type;
  using N = std::false_type;
  if (feat.rolling) {
    if (feat.viscous) run(Y{}, Y{});
    else run(Y{}, N{});
  } else {
    if (feat.viscous) run(N{}, Y{});
    else run(N{}, N{});
  }
}

// The one dispatch of integrate_impl: where i's share is (kernel) and whether damping is on (alpha), at run
// time once per call; Loads, Store and Move are the caller's.
template <bool Loads, bool Store, bool Move, bool Drag = false>
Real integrate_dispatch(const char* who, const Particles& P, const PairList& L, const FlagView& flags,
                        const PairForces& F, const WallSet& walls, Real E_wall, Real alpha, Real dt, PairKernel kernel,
                        DeterministicSum* red, WallLoads* loads, Real* device_max = nullptr, const Vec3& drag_c = Vec3(),
                        Vec3* drag_moment = nullptr) {
  if (kernel == PairKernel::Lanes && !kPairLanesBuilt)
    throw std::logic_error(std::string(who) + ": the pair-lane kernel is not built here (kPairLanesBuilt)");
  if (!(alpha > 0)) {
    if constexpr (Drag) *drag_moment = Vec3();  // no damping, no drag (and no undamped instantiation with Drag)
    constexpr bool D = false;
    return per_pair_shares(kernel)
               ? integrate_impl<false, true, Loads, Store, Move, D>(P, L, flags, F, walls, E_wall, alpha, dt, red, loads, device_max)
               : integrate_impl<false, false, Loads, Store, Move, D>(P, L, flags, F, walls, E_wall, alpha, dt, red, loads, device_max);
  }
  return per_pair_shares(kernel)
             ? integrate_impl<true, true, Loads, Store, Move, Drag>(P, L, flags, F, walls, E_wall, alpha, dt, red, loads,
                                                                    device_max, drag_c, drag_moment)
             : integrate_impl<true, false, Loads, Store, Move, Drag>(P, L, flags, F, walls, E_wall, alpha, dt, red, loads,
                                                                     device_max, drag_c, drag_moment);
}

Real remap_affine(const Particles& P, const Vec3& lo0, const Vec3& scale, const Vec3& lo1) {
  auto x = P.x;
  auto xr = P.x_ref;
  const Real a0 = lo0.x, a1 = lo0.y, a2 = lo0.z, s0 = scale.x, s1 = scale.y, s2 = scale.z, b0 = lo1.x, b1 = lo1.y,
             b2 = lo1.z;
  Real maxd2 = 0;
  Kokkos::parallel_reduce(
      "grainlab::integrate::affine_remap", Kokkos::RangePolicy<ExecSpace>(0, P.n),
      KOKKOS_LAMBDA(int i, Real& mx) {
        x(i, 0) = b0 + (x(i, 0) - a0) * s0;
        x(i, 1) = b1 + (x(i, 1) - a1) * s1;
        x(i, 2) = b2 + (x(i, 2) - a2) * s2;
        const Real d0 = x(i, 0) - xr(i, 0), d1 = x(i, 1) - xr(i, 1), d2 = x(i, 2) - xr(i, 2);
        const Real d = d0 * d0 + d1 * d1 + d2 * d2;
        mx = d > mx ? d : mx;
      },
      Kokkos::Max<Real>(maxd2));
  return maxd2;
}

Real gather_and_integrate(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                          const WallSet& walls, Real E_wall, Real alpha, Real dt, PairKernel kernel, bool store_forces) {
  if (store_forces)
    return integrate_dispatch<false, true, true>("gather_and_integrate", P, L, flags, F, walls, E_wall, alpha, dt,
                                                 kernel, nullptr, nullptr);
  return integrate_dispatch<false, false, true>("gather_and_integrate", P, L, flags, F, walls, E_wall, alpha, dt,
                                                kernel, nullptr, nullptr);
}

void gather_forces(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                   const WallSet& walls, Real E_wall, PairKernel kernel) {
  // alpha = 0: damping acts on the kick, which the gather alone does not do.
  integrate_dispatch<false, true, false>("gather_forces", P, L, flags, F, walls, E_wall, 0, 0, kernel, nullptr, nullptr);
}

Real gather_integrate_and_load_walls(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                                     const WallSet& walls, Real E_wall, Real alpha, Real dt, PairKernel kernel,
                                     DeterministicSum& red, WallLoads& loads, DragMeasure* drag) {
  if constexpr (kHostBackend) {
    static_assert(3 * kMaxWalls + 3 <= DeterministicSum::kMaxValues, "the loads and the drag fit the sums");
    if (drag)
      return integrate_dispatch<true, false, true, true>("gather_integrate_and_load_walls", P, L, flags, F, walls, E_wall,
                                                         alpha, dt, kernel, &red, &loads, nullptr, drag->c, &drag->moment);
    return integrate_dispatch<true, false, true>("gather_integrate_and_load_walls", P, L, flags, F, walls, E_wall, alpha, dt,
                                                 kernel, &red, &loads);
  } else {
    if (drag) throw std::logic_error("gather_integrate_and_load_walls: the drag on host backends only (a GPU's "
                                     "Engine::step_measuring_drag takes damping_moment between the step's halves)");
    // The loads at x(t) into device slots 0 .. 3 nw, the max after the drift into slot 3 nw, then one copy.
    const int nv = 3 * walls.count;
    red.run_one_term_on_device("grainlab::walls::loads", P.n, nv, WallLoadTerms{P.x, P.r, walls, E_wall});
    integrate_dispatch<false, false, true>("gather_integrate_and_load_walls", P, L, flags, F, walls, E_wall, alpha, dt,
                                           kernel, nullptr, nullptr, red.device_slot(nv));
    Real out[DeterministicSum::kMaxValues];
    red.fetch(nv + 1, out);
    loads = unpack_wall_loads(out, walls.count);
    return P.n > 0 ? out[nv] : Real(0);
  }
}

WallLoads reduce_wall_loads(const Particles& P, const WallSet& walls, Real E_wall, DeterministicSum& red, bool team) {
  const int nw = walls.count;
  Real out[DeterministicSum::kMaxValues] = {};
  const WallLoadTerms loads{P.x, P.r, walls, E_wall};
  if (team)
    red.run_one_term<true>("grainlab::walls::loads", P.n, 3 * nw, loads, out);
  else
    red.run_one_term<false>("grainlab::walls::loads", P.n, 3 * nw, loads, out);
  return unpack_wall_loads(out, nw);
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
  grow_view(h.ft, "grainlab::history::ft", n);
  grow_view(h.mr, "grainlab::history::mr", n);
  grow_view(h.flags, "grainlab::history::flags", n);
}
void ensure_pair_arrays(PairForces& f, int n, int nparticles, PairKernel kernel) {
  grow_view(f.f, "grainlab::pair::f", n);
  grow_view(f.tj, "grainlab::pair::tj", n);
  if (per_pair_shares(kernel)) {
    grow_view(f.ti, "grainlab::pair::ti", n);
  } else {
    grow_view(f.row_f, "grainlab::pair::row_f", nparticles);
    grow_view(f.row_t, "grainlab::pair::row_t", nparticles);
  }
}

}  // namespace grainlab
