// Attempt 17's prototype (perf/NOTES.md, Session 6): the SELL contact kernel alone against the row kernel,
// one call each from the same state (bitwise comparison), then interleaved timing rounds. It needs the
// select-based law of 17-sell-lanes.patch (apply it first), then, in perf/CMakeLists.txt:
//   add_executable(sell_proto attempts/17-sell-proto.cpp)
//   target_link_libraries(sell_proto PRIVATE grainlab_core)
//   target_compile_options(sell_proto PRIVATE -fno-math-errno -fno-trapping-math
//                          -mtune-ctrl=use_gather_2parts,use_gather_4parts,use_gather)
// and run: OMP_NUM_THREADS=1 build/perf/sell_proto --scene S/scene_32k.txt --box S/scene_32k_box.txt --sigma 1024
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "../scene.hpp"

using namespace grainlab;

namespace {

constexpr int C = 8;

struct Sell {
  int nchunks = 0, nslots = 0;
  IntView cbase;  // nchunks + 1
  Kokkos::View<long*, MemSpace> sj;     // slot -> j (padding: the lane's own i)
  IntView srow;   // chunk lane -> row i (rows sorted by length within windows of sigma rows)
  IntView slot_of_p;
  Kokkos::View<double* [3], Kokkos::LayoutLeft, MemSpace> ft, mr, f, tj;
  Kokkos::View<long*, MemSpace> flags;
};

int g_sigma = 1;
Sell build_sell(const PairList& L, const PairHistory& H, int n) {
  Sell S;
  S.nchunks = (n + C - 1) / C;
  auto off = Kokkos::create_mirror_view_and_copy(HostSpace(), L.offsets);
  auto pj = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_j);
  auto hft = Kokkos::create_mirror_view_and_copy(HostSpace(), H.ft);
  auto hmr = Kokkos::create_mirror_view_and_copy(HostSpace(), H.mr);
  auto hfl = Kokkos::create_mirror_view_and_copy(HostSpace(), H.flags);
  std::vector<int> rowof(S.nchunks * C);
  for (int q = 0; q < S.nchunks * C; ++q) rowof[q] = std::min(q, n - 1);
  for (int w0 = 0; w0 < n; w0 += g_sigma) {
    const int w1 = std::min(n, w0 + g_sigma);
    std::stable_sort(rowof.begin() + w0, rowof.begin() + w1,
                     [&](int a, int b) { return off(a + 1) - off(a) > off(b + 1) - off(b); });
  }
  std::vector<int> cb(S.nchunks + 1, 0);
  for (int c = 0; c < S.nchunks; ++c) {
    int K = 0;
    for (int l = 0; l < C; ++l) {
      const int i = rowof[c * C + l];
      if (c * C + l < n) K = std::max(K, off(i + 1) - off(i));
    }
    cb[c + 1] = cb[c] + K * C;
  }
  S.nslots = cb[S.nchunks];
  S.cbase = IntView("cbase", S.nchunks + 1);
  S.sj = Kokkos::View<long*, MemSpace>("sj", S.nslots);
  S.srow = IntView("srow", S.nchunks * C);
  {
    auto h = Kokkos::create_mirror_view(S.srow);
    for (int q = 0; q < S.nchunks * C; ++q) h(q) = rowof[q];
    Kokkos::deep_copy(S.srow, h);
  }
  S.slot_of_p = IntView("slot_of_p", L.npairs);
  S.ft = decltype(S.ft)("sft", S.nslots);
  S.mr = decltype(S.mr)("smr", S.nslots);
  S.f = decltype(S.f)("sf", S.nslots);
  S.tj = decltype(S.tj)("stj", S.nslots);
  S.flags = Kokkos::View<long*, MemSpace>("sfl", S.nslots);
  auto hcb = Kokkos::create_mirror_view(S.cbase);
  auto hsj = Kokkos::create_mirror_view(S.sj);
  auto hsp = Kokkos::create_mirror_view(S.slot_of_p);
  auto sft = Kokkos::create_mirror_view(S.ft);
  auto smr = Kokkos::create_mirror_view(S.mr);
  auto sfl = Kokkos::create_mirror_view(S.flags);
  for (int c = 0; c <= S.nchunks; ++c) hcb(c) = cb[c];
  for (int c = 0; c < S.nchunks; ++c) {
    const int K = (cb[c + 1] - cb[c]) / C;
    for (int l = 0; l < C; ++l) {
      const int i = rowof[c * C + l];
      for (int k = 0; k < K; ++k) {
        const int s = cb[c] + k * C + l;
        const bool real = c * C + l < n && k < off(i + 1) - off(i);
        if (!real) {
          hsj(s) = i;
          sfl(s) = 0;
          for (int q = 0; q < 3; ++q) sft(s, q) = smr(s, q) = 0;
          continue;
        }
        const int p = off(i) + k;
        hsj(s) = pj(p);
        hsp(p) = s;
        sfl(s) = hfl(p);
        for (int q = 0; q < 3; ++q) sft(s, q) = hft(p, q), smr(s, q) = hmr(p, q);
      }
    }
  }
  Kokkos::deep_copy(S.cbase, hcb);
  Kokkos::deep_copy(S.sj, hsj);
  Kokkos::deep_copy(S.slot_of_p, hsp);
  Kokkos::deep_copy(S.ft, sft);
  Kokkos::deep_copy(S.mr, smr);
  Kokkos::deep_copy(S.flags, sfl);
  return S;
}

template <bool Rolling, bool Viscous>
void sell_forces(const Particles& P, const Sell& S, const PairForces& F, const ContactParams& cp_) {
  using Law = LinearRollingContact<Rolling, Viscous>;
  const double* X_ = P.x.data();
  const double* V_ = P.v.data();
  const double* W_ = P.w.data();
  const double* R_ = P.r.data();
  const double* M_ = P.m.data();
  const int* cbase = S.cbase.data();
  const long* sj_ = S.sj.data();
  const int* srow_ = S.srow.data();
  double* hft_ = S.ft.data();
  double* hmr_ = S.mr.data();
  double* fo_ = S.f.data();
  double* tjo_ = S.tj.data();
  long* fl_ = S.flags.data();
  const long cap_ = S.ft.extent(0);
  auto rowf = F.row_f;
  auto rowt = F.row_t;
  const int n = P.n;
  Kokkos::parallel_for(
      "grainlab::contact::sell", Kokkos::RangePolicy<ExecSpace>(0, S.nchunks), KOKKOS_LAMBDA(int c) {
        const double* __restrict X = X_;
        const double* __restrict V = V_;
        const double* __restrict W = W_;
        const double* __restrict R = R_;
        const double* __restrict M = M_;
        const long* __restrict sj = sj_;
        const int* __restrict srow = srow_;
        double* __restrict hft = hft_;
        double* __restrict hmr = hmr_;
        double* __restrict fo = fo_;
        double* __restrict tjo = tjo_;
        long* __restrict fl = fl_;
        const long cap = cap_;
        const ContactParams cp = cp_;
        double xi[3][C], vi[3][C], wi[3][C], ri[C], mi[C], fi[3][C], ti[3][C];
        long il[C];
        for (int l = 0; l < C; ++l) {
          const int i = srow[c * C + l];
          il[l] = i;
          for (int q = 0; q < 3; ++q) {
            xi[q][l] = X[3 * i + q];
            vi[q][l] = V[3 * i + q];
            wi[q][l] = W[3 * i + q];
            fi[q][l] = 0;
            ti[q][l] = 0;
          }
          ri[l] = R[i];
          mi[l] = M[i];
        }
        const int K = (cbase[c + 1] - cbase[c]) / C;
        for (int k = 0; k < K; ++k) {
          const int s0 = cbase[c] + k * C;
#pragma GCC ivdep
          for (int l = 0; l < C; ++l) {
            const int s = s0 + l;
            const long j = sj[s];
            const Vec3 d(X[3 * j] - xi[0][l], X[3 * j + 1] - xi[1][l], X[3 * j + 2] - xi[2][l]);
            const double rj = R[j];
            const double dist2 = norm2(d);
            const double sum = ri[l] + rj;
            const bool touching = (j != il[l]) & (dist2 < sum * sum);
            const double dist = touching ? math::sqrt(dist2) : sum;
            ContactHistory h;
            h.ft = Vec3(hft[s], hft[s + cap], hft[s + 2 * cap]);
            if (Rolling) h.mr = Vec3(hmr[s], hmr[s + cap], hmr[s + 2 * cap]);
            const ContactResult cr = Law::evaluate(
                cp, ri[l], rj, mi[l], M[j], d, dist, Vec3(vi[0][l], vi[1][l], vi[2][l]),
                Vec3(V[3 * j], V[3 * j + 1], V[3 * j + 2]), Vec3(wi[0][l], wi[1][l], wi[2][l]),
                Vec3(W[3 * j], W[3 * j + 1], W[3 * j + 2]), h);
            hft[s] = touching ? h.ft.x : 0.0;
            hft[s + cap] = touching ? h.ft.y : 0.0;
            hft[s + 2 * cap] = touching ? h.ft.z : 0.0;
            if (Rolling) {
              hmr[s] = touching ? h.mr.x : 0.0;
              hmr[s + cap] = touching ? h.mr.y : 0.0;
              hmr[s + 2 * cap] = touching ? h.mr.z : 0.0;
            }
            const double fx = touching ? cr.f.x : 0.0, fy = touching ? cr.f.y : 0.0, fz = touching ? cr.f.z : 0.0;
            fo[s] = fx;
            fo[s + cap] = fy;
            fo[s + 2 * cap] = fz;
            tjo[s] = touching ? cr.tj.x : 0.0;
            tjo[s + cap] = touching ? cr.tj.y : 0.0;
            tjo[s + 2 * cap] = touching ? cr.tj.z : 0.0;
            fl[s] = touching ? cr.flags : 0;
            fi[0][l] -= fx;
            fi[1][l] -= fy;
            fi[2][l] -= fz;
            ti[0][l] += touching ? cr.ti.x : 0.0;
            ti[1][l] += touching ? cr.ti.y : 0.0;
            ti[2][l] += touching ? cr.ti.z : 0.0;
          }
        }
        for (int l = 0; l < C; ++l) {
          if (c * C + l >= n) break;
          const int i = srow[c * C + l];
          rowf(i, 0) = fi[0][l], rowf(i, 1) = fi[1][l], rowf(i, 2) = fi[2][l];
          rowt(i, 0) = ti[0][l], rowt(i, 1) = ti[1][l], rowt(i, 2) = ti[2][l];
        }
      });
}

}  // namespace

int main(int argc, char** argv) {
  perf::SceneArgs sa;
  int reps = 50, rounds = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (sa.parse(k, v)) continue;
    if (k == "--reps") reps = std::stoi(v);
    else if (k == "--rounds") rounds = std::stoi(v);
    else if (k == "--sigma") g_sigma = std::stoi(v);
  }
  compat::initialize(0);
  {
    perf::Scene sc = perf::load_scene(sa);
    const int n = int(sc.s.r.size());
    Real r_mean = 0;
    for (Real r : sc.s.r) r_mean += r / n;
    EngineParams p;
    p.contact.E = 2e4 / (1.1 * r_mean);
    p.contact.kappa = 1;
    p.contact.mu = 0.5;
    p.contact.mu_r = 0.1;
    p.contact.roll_arm = 0.5;
    p.contact.normal_damping = 0.06;
    p.contact.dt = 1e-7;
    p.E_wall = 2e4 / r_mean;
    p.damping = 0;
    p.skin = 1e-4;
    Engine eng(sc.s, p, make_box_walls(sc.lo, sc.hi), true);
    eng.wall_control(4) = WallControl{WallMode::Velocity, 0.01};
    eng.wall_control(5) = WallControl{WallMode::Velocity, 0.01};
    eng.run(200);
    const Particles P = eng.particles();
    const PairList& L = eng.pairs();
    const PairHistory& H0 = eng.history();
    // Private CSR copies (the engine's are left alone).
    PairHistory H;
    H.ft = PairVecView("ft", L.npairs);
    H.mr = PairVecView("mr", L.npairs);
    H.flags = FlagView("fl", L.npairs);
    Kokkos::deep_copy(H.ft, Kokkos::subview(H0.ft, std::make_pair(0, L.npairs), Kokkos::ALL));
    Kokkos::deep_copy(H.mr, Kokkos::subview(H0.mr, std::make_pair(0, L.npairs), Kokkos::ALL));
    Kokkos::deep_copy(H.flags, Kokkos::subview(H0.flags, std::make_pair(0, L.npairs)));
    PairForces F1, F2;
    ensure_pair_arrays(F1, L.npairs, n);
    ensure_pair_arrays(F2, L.npairs, n);
    Sell S = build_sell(L, H, n);
    std::printf("n=%d pairs=%d slots=%d (padding %.1f %%)\n", n, L.npairs, S.nslots,
                100.0 * (S.nslots - L.npairs) / S.nslots);
    const ContactParams cp = eng.params().contact;
    const ContactFeatures feat{true, true};
    // One call each from the same state: bitwise comparison.
    compute_pair_forces(P, L, H, F1, cp, feat);
    sell_forces<true, true>(P, S, F2, cp);
    Kokkos::fence();
    {
      auto a = Kokkos::create_mirror_view_and_copy(HostSpace(), H.ft);
      auto b = Kokkos::create_mirror_view_and_copy(HostSpace(), S.ft);
      auto am = Kokkos::create_mirror_view_and_copy(HostSpace(), H.mr);
      auto bm = Kokkos::create_mirror_view_and_copy(HostSpace(), S.mr);
      auto af = Kokkos::create_mirror_view_and_copy(HostSpace(), F1.f);
      auto bf = Kokkos::create_mirror_view_and_copy(HostSpace(), S.f);
      auto afl = Kokkos::create_mirror_view_and_copy(HostSpace(), H.flags);
      auto bfl = Kokkos::create_mirror_view_and_copy(HostSpace(), S.flags);
      auto sp = Kokkos::create_mirror_view_and_copy(HostSpace(), S.slot_of_p);
      auto r1 = Kokkos::create_mirror_view_and_copy(HostSpace(), F1.row_f);
      auto r2 = Kokkos::create_mirror_view_and_copy(HostSpace(), F2.row_f);
      auto t1 = Kokkos::create_mirror_view_and_copy(HostSpace(), F1.row_t);
      auto t2 = Kokkos::create_mirror_view_and_copy(HostSpace(), F2.row_t);
      long bad = 0, touching = 0;
      for (int q = 0; q < L.npairs; ++q) {
        const int s = sp(q);
        if (afl(q) != bfl(s)) ++bad;
        if (afl(q) & kTouching) ++touching;
        for (int k = 0; k < 3; ++k) {
          if (a(q, k) != b(s, k) || am(q, k) != bm(s, k)) ++bad;
          if ((afl(q) & kTouching) && af(q, k) != bf(s, k)) ++bad;
        }
      }
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
          if (r1(i, k) != r2(i, k) || t1(i, k) != t2(i, k)) ++bad;
      std::printf("touching=%ld mismatches=%ld\n", touching, bad);
    }
    std::vector<double> ta, tb;
    for (int round = 0; round < rounds; ++round) {
      Kokkos::fence();
      auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < reps; ++k) compute_pair_forces(P, L, H, F1, cp, feat);
      Kokkos::fence();
      auto t1 = std::chrono::steady_clock::now();
      for (int k = 0; k < reps; ++k) sell_forces<true, true>(P, S, F2, cp);
      Kokkos::fence();
      auto t2 = std::chrono::steady_clock::now();
      ta.push_back(std::chrono::duration<double>(t1 - t0).count() / reps);
      tb.push_back(std::chrono::duration<double>(t2 - t1).count() / reps);
      std::printf("round %d: row %.3f ms  sell %.3f ms  ratio %.3f\n", round, 1e3 * ta.back(), 1e3 * tb.back(),
                  ta.back() / tb.back());
    }
    std::sort(ta.begin(), ta.end());
    std::sort(tb.begin(), tb.end());
    std::printf("median row %.3f ms sell %.3f ms speedup %.3f\n", 1e3 * ta[rounds / 2], 1e3 * tb[rounds / 2],
                ta[rounds / 2] / tb[rounds / 2]);
  }
  Kokkos::finalize();
  return 0;
}
