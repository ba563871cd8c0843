// Conservation laws through the full engine. Issue 2 item 6.
#include <gtest/gtest.h>

#include <random>

#include "helpers.hpp"

using namespace grainlab;

// A free cluster with friction and rolling: pair forces are equal and opposite and every pair's
// torques balance the moment of its forces (shared contact point), so total linear and angular
// momentum are conserved by leapfrog to round-off (L at half steps: sum x_{n+1} x m v_{n+1/2} + I w).
TEST(Conservation, FreeClusterMomentumToRoundoff) {
  std::mt19937_64 g(11);
  std::uniform_real_distribution<Real> U(-1, 1);
  ParticleSetup s;
  const int n = 60;
  for (int i = 0; i < n; ++i) {
    s.x.push_back({1e-3 * U(g), 1e-3 * U(g), 1e-3 * U(g)});
    s.v.push_back({0.05 * U(g), 0.05 * U(g), 0.05 * U(g)});
    s.w.push_back({50 * U(g), 50 * U(g), 50 * U(g)});
    s.r.push_back(0.3e-3 + 0.2e-3 * std::abs(U(g)));
  }
  EngineParams p;
  p.contact = test::reference_contact();
  p.contact.mu_r = 0.3;
  p.damping = 0;  // Cundall damping is an external force: off
  p.skin = 0.05e-3;
  Engine eng(s, p, WallSet{}, false);
  auto totals = [&](Vec3& P, Vec3& L, Real& scaleP, Real& scaleL) {
    const auto x = eng.positions(), v = eng.velocities(), w = eng.angular_velocities();
    auto m = Kokkos::create_mirror_view_and_copy(HostSpace(), eng.particles().m);
    auto I = Kokkos::create_mirror_view_and_copy(HostSpace(), eng.particles().inertia);
    P = Vec3();
    L = Vec3();
    scaleP = scaleL = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 xi(x[i][0], x[i][1], x[i][2]), vi(v[i][0], v[i][1], v[i][2]), wi(w[i][0], w[i][1], w[i][2]);
      P += m(i) * vi;
      L += m(i) * cross(xi, vi) + I(i) * wi;
      scaleP += m(i) * norm(vi);
      scaleL += m(i) * norm(xi) * norm(vi) + I(i) * norm(wi);
    }
  };
  eng.step();  // L is defined from the first half-step on
  Vec3 P0, L0;
  Real sP, sL;
  totals(P0, L0, sP, sL);
  int max_contacts = 0;
  for (int k = 0; k < 4000; ++k) {
    eng.step();
    if (k % 200 == 0) max_contacts = std::max(max_contacts, eng.diagnostics().contacts);
  }
  Vec3 P1, L1;
  Real sP1, sL1;
  totals(P1, L1, sP1, sL1);
  ASSERT_GT(max_contacts, 20) << "the cluster must actually interact";
  // 4000 steps x ~10 contacts per particle of rounding at 1e-16: 1e-11 of the momentum scale.
  EXPECT_LT(norm(P1 - P0), 1e-11 * sP);
  EXPECT_LT(norm(L1 - L0), 1e-11 * sL);
}

// A dense frictionless packing without damping between fixed walls: leapfrog conserves a shadow
// energy, so E = PE(x_n) + (KE_{n-1/2} + KE_{n+1/2}) / 2 fluctuates by O((omega dt)^2) without drift.
TEST(Conservation, FrictionlessDensePackingEnergy) {
  test::DenseScene sc = test::consolidated_scene(500, 3, 5, 0.0, 0.0, 12000);
  std::mt19937_64 g(5);
  std::uniform_real_distribution<Real> U(-1, 1);
  sc.setup.v.clear();
  for (size_t i = 0; i < sc.setup.r.size(); ++i) sc.setup.v.push_back({0.01 * U(g), 0.01 * U(g), 0.01 * U(g)});
  sc.params.contact.mu = 0;
  sc.params.damping = 0;
  sc.params.dt_factor = 0.1;
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  const int c0 = eng.diagnostics().contacts;
  std::printf("  packing: %d contacts for 500 particles\n", c0);
  ASSERT_GT(c0, 2 * 500) << "the packing must be dense (coordination > 4)";
  Real ke_prev = eng.diagnostics().kinetic;
  Real e0 = 0, emax = -1e300, emin = 1e300, first = 0, last = 0;
  const int nsteps = 10000, window = 1000;
  for (int k = 0; k < nsteps; ++k) {
    const Real pe = eng.diagnostics().potential;
    eng.step();
    const Real ke = eng.diagnostics().kinetic;
    const Real e = pe + 0.5 * (ke_prev + ke);
    ke_prev = ke;
    if (k == 0) e0 = e;
    emax = std::max(emax, e);
    emin = std::min(emin, e);
    if (k < window) first += e / window;
    if (k >= nsteps - window) last += e / window;
  }
  const Diagnostics d = eng.diagnostics();
  std::printf("  E0 = %.6e J, band [%.3e, %.3e] relative, drift of window means %.3e, contacts %d, rebuilds %d\n",
              e0, (emin - e0) / e0, (emax - e0) / e0, (last - first) / e0, d.contacts, eng.rebuild_count());
  ASSERT_GT(eng.rebuild_count(), 1);
  // Bound: (omega dt)^2 with omega dt <= 2 f sqrt(2) ~ 0.28 at f = 0.1 gives 8e-2 for the worst single
  // spring; the system-wide fluctuation is far smaller. 1e-3 band, 1e-4 drift.
  EXPECT_LT((emax - emin) / e0, 1e-3);
  EXPECT_LT(std::abs(last - first) / e0, 1e-4);
}
