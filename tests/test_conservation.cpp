// Conservation laws through the full engine. Issue 2 item 6.
#include <gtest/gtest.h>

#include <random>

#include "helpers.hpp"
#include "src/energy_tally.hpp"

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

// A dense frictionless packing without damping between fixed walls. Leapfrog conserves a shadow energy
// for smooth forces, so E = PE(x_n) + (KE_{n-1/2} + KE_{n+1/2}) / 2 only fluctuates; the linear spring's
// kink at delta = 0 (a contact switching on between two samples) costs O((omega dt)^2) of the contact's
// energy per event. So over the same physical time the drift must shrink when dt is halved (expected
// 4x, required > 2x), and at f = 0.1 (omega dt ~ 0.14 per spring) stay below 1e-3 of E, as must the
// fluctuation band.
namespace {
struct EnergyRun {
  Real band = 0, drift = 0;
  int contacts0 = 0, rebuilds = 0;
};
EnergyRun energy_run(const test::DenseScene& base, Real f, int nsteps) {
  test::DenseScene sc = base;
  std::mt19937_64 g(5);
  std::uniform_real_distribution<Real> U(-1, 1);
  sc.setup.v.clear();
  for (size_t i = 0; i < sc.setup.r.size(); ++i) sc.setup.v.push_back({0.01 * U(g), 0.01 * U(g), 0.01 * U(g)});
  sc.params.contact.mu = 0;
  sc.params.damping = 0;
  sc.params.dt_factor = f;
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  EnergyRun out;
  out.contacts0 = eng.diagnostics().contacts;
  EnergyTally tally(nsteps, eng.diagnostics().kinetic);
  for (int k = 0; k < nsteps; ++k) {
    const Real pe = eng.diagnostics().potential;
    eng.step();
    tally.add(pe, eng.diagnostics().kinetic);
  }
  const Real e0 = tally.e0();
  out.band = tally.band();
  out.drift = tally.drift();
  out.rebuilds = eng.rebuild_count();
  std::printf("  f = %g, %d steps: E0 = %.4e J, band %.3e, drift %.3e, contacts %d -> %d, rebuilds %d\n", f, nsteps, e0,
              out.band, out.drift, out.contacts0, eng.diagnostics().contacts, out.rebuilds);
  return out;
}
}  // namespace

TEST(Conservation, FrictionlessDensePackingEnergy) {
  const test::DenseScene sc = test::consolidated_scene(500, 3, 5, 0.0, 0.0, 12000);
  const EnergyRun a = energy_run(sc, 0.1, 10000);
  const EnergyRun b = energy_run(sc, 0.05, 20000);
  ASSERT_GT(a.contacts0, 2 * 500) << "the packing must be dense (coordination > 4)";
  ASSERT_GT(a.rebuilds, 1);
  EXPECT_LT(a.band, 1e-3);
  EXPECT_LT(a.drift, 1e-3);
  EXPECT_LT(b.drift, a.drift / 2) << "energy drift does not converge with dt";
}
