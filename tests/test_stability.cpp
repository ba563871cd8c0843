// Hard cases stay stable. Issue 2 item 10.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace grainlab;

namespace {
bool all_finite(const std::vector<Vec3d>& a) {
  for (auto& v : a)
    for (Real c : v)
      if (!std::isfinite(c)) return false;
  return true;
}
}  // namespace

// Size ratio 10, every contact of a consolidated sample pushed 5 % of r_min deeper (radii inflated by
// 2.5 % of r_min), mu_r = 0.5 with k_r = k_t rbar^2, no damping, fixed walls, 1e5 steps at the default
// f = 0.2. Nothing injects energy, so total energy may only fall (friction and rolling dissipate) up to
// leapfrog's O((omega dt)^2) fluctuation; 2 % is generous for that and far below any instability,
// which grows exponentially.
TEST(Stability, SizeRatio10OverlapsRollingResistance) {
  test::DenseScene sc = test::consolidated_scene(300, 10, 31, 0.3, 0.0, 30000, 190e3, 2e-2);
  Real rmin = 1e9;
  for (Real r : sc.setup.r) rmin = std::min(rmin, r);
  for (Real& r : sc.setup.r) r += 0.025 * rmin;
  sc.params.contact.mu = 0.5;
  sc.params.contact.mu_r = 0.5;
  sc.params.damping = 0;
  sc.params.dt_factor = 0.2;
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  const Diagnostics d0 = eng.diagnostics();
  const Real e0 = d0.kinetic + d0.potential;
  // Ratio-10 packings have many rattlers (small spheres in the voids), so Z ~ 1.7 here; the hard part is
  // the small-on-big contacts, where the rolling spring is stiffest: require plenty of them.
  ASSERT_GT(d0.contacts, 200);
  {
    auto pi = Kokkos::create_mirror_view_and_copy(HostSpace(), eng.pairs().pair_i);
    auto pj = Kokkos::create_mirror_view_and_copy(HostSpace(), eng.pairs().pair_j);
    auto fl = Kokkos::create_mirror_view_and_copy(HostSpace(), eng.history().flags);
    int small_big = 0;
    for (int p = 0; p < eng.pairs().npairs; ++p) {
      const Real a = sc.setup.r[pi(p)], b = sc.setup.r[pj(p)];
      if ((fl(p) & kTouching) && std::min(a, b) < 2.5 * rmin && std::max(a, b) > 5 * rmin) ++small_big;
    }
    std::printf("  %d contacts, %d between spheres < 2.5 r_min and > 5 r_min\n", d0.contacts, small_big);
    ASSERT_GT(small_big, 20);
  }
  Real emax = e0;
  for (int k = 0; k < 100000; ++k) {
    eng.step();
    if (k % 1000 == 999) {
      const Diagnostics d = eng.diagnostics();
      const Real e = d.kinetic + d.potential;
      ASSERT_TRUE(std::isfinite(e)) << "step " << k;
      emax = std::max(emax, e);
    }
  }
  const Diagnostics d1 = eng.diagnostics();
  std::printf("  E0 = %.4e J, max E = %.4e J (%+.3e), final %.4e J, contacts %d -> %d, rolling-sliding %d\n", e0,
              emax, (emax - e0) / e0, d1.kinetic + d1.potential, d0.contacts, d1.contacts, d1.rolling_sliding);
  EXPECT_TRUE(all_finite(eng.positions()));
  EXPECT_TRUE(all_finite(eng.angular_velocities()));
  EXPECT_LT(emax, 1.02 * e0);
}

// The rolling spring is the stiffest one for small spheres next to big ones: at ratio 10 the stable
// limit must come from it, and the engine's default dt must respect it.
TEST(Stability, RollingStiffnessSetsTheLimitAtRatio10) {
  ParticleSetup s;
  s.x = {{0, 0, 0}, {1e-2, 0, 0}};
  s.r = {0.6e-3, 0.06e-3};
  EngineParams p;
  p.contact = test::reference_contact();
  p.contact.mu_r = 0.5;
  Engine eng(s, p, WallSet{}, false);
  EXPECT_LT(eng.stable_dt(true), eng.stable_dt(false) / 5);
  EXPECT_LE(eng.dt(), 0.2 * eng.stable_dt(true) * (1 + 1e-12));
}

// A requested dt above the stable limit is an error with a message that says what and how to fix it.
TEST(Stability, TooLargeDtIsRefused) {
  ParticleSetup s;
  s.x = {{0, 0, 0}, {1e-3, 0, 0}};
  s.r = {0.3e-3, 0.3e-3};
  EngineParams p;
  p.contact = test::reference_contact();
  p.contact.dt = 1e-3;
  try {
    Engine eng(s, p, WallSet{}, false);
    FAIL() << "dt = 1e-3 s was accepted";
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("above the stable limit"), std::string::npos) << msg;
    EXPECT_NE(msg.find("use dt <="), std::string::npos) << msg;
  }
  // Just below the limit is accepted; switching rolling on later re-checks it.
  Engine probe(s, p = [&] { EngineParams q = p; q.contact.dt = 0; return q; }(), WallSet{}, false);
  p.contact.dt = 0.99 * probe.stable_dt(false);
  Engine ok(s, p, WallSet{}, false);
  EXPECT_THROW(ok.set_friction(0.5, 0.5), ParameterError);
}
