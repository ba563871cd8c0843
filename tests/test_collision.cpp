// Analytic binary collisions through the full engine (neighbour list, kernels, leapfrog).
// Issue 2 items 1 (head-on) and 2 (wall bounce), plus the optional viscous normal damping.
#include <gtest/gtest.h>

#include "helpers.hpp"

using namespace grainlab;

namespace {

struct Collision {
  Real duration = 0;  // from the interpolated gap zero crossings (exact for the discrete path: the
                      // motion between samples outside contact is a straight line)
  Real exit_speed = 0;
};

// Steps eng until the gap (gap(): > 0 apart) has closed and opened again; the contact's duration from the
// interpolated zero crossings, or -1 where it never separated (200 000 steps).
template <class Gap>
Real contact_duration(Engine& eng, Gap gap) {
  Real g_prev = gap(), t_in = -1, t_out = -1;
  for (int k = 0; k < 200000 && t_out < 0; ++k) {
    const Real t0 = eng.time();
    eng.step();
    const Real g = gap();
    if (t_in < 0 && g_prev > 0 && g <= 0) t_in = t0 + eng.dt() * g_prev / (g_prev - g);
    if (t_in >= 0 && g_prev <= 0 && g > 0) t_out = t0 + eng.dt() * (-g_prev) / (g - g_prev);
    g_prev = g;
  }
  return t_out < 0 ? -1 : t_out - t_in;
}

// Two spheres of radius r approach head-on at +-V (or one sphere hits a floor when wall = true).
Collision collide(Real f, bool wall, Real beta = 0) {
  const Real r = 0.3e-3, V = 0.05;
  ParticleSetup s;
  EngineParams p;
  p.contact = test::reference_contact();
  p.contact.normal_damping = beta;
  p.damping = 0;
  p.dt_factor = f;
  p.skin = 0.05e-3;
  WallSet walls;
  const Real gap0 = 20e-6;
  if (wall) {
    s.x = {{0, 0, r + gap0}};
    s.v = {{0, 0, -V}};
    s.r = {r};
    walls.count = 1;
    walls.w[0].n = Vec3(0, 0, 1);
    walls.w[0].offset = 0;
  } else {
    s.x = {{0, 0, 0}, {2 * r + gap0, 0, 0}};
    s.v = {{V, 0, 0}, {-V, 0, 0}};
    s.r = {r, r};
  }
  Engine eng(s, p, walls, false);
  Collision c;
  c.duration = contact_duration(eng, [&] {
    const auto x = eng.positions();
    return wall ? x[0][2] - r : (x[1][0] - x[0][0]) - 2 * r;
  });
  const auto v = eng.velocities();
  c.exit_speed = wall ? v[0][2] : 0.5 * (v[1][0] - v[0][0]);
  EXPECT_GT(c.duration, 0) << "no separation";
  return c;
}

// Leapfrog on a linear spring shifts the frequency by (omega dt)^2 / 24 (second order), so the contact
// duration error is bounded by that (25 % margin for higher orders). The contact switches on between two
// samples; the impulse missed or gained in that step is ~ k (V dt) dt, a relative exit-speed error of
// order (omega dt)^2 with a phase-dependent coefficient < 1/2. Both must hold at every f, and the
// exit-speed error must fall by > 10x from f = 0.2 to f = 0.025 (64x for a clean second-order method).
void check_convergence(bool wall, Real T_exact) {
  Real first_v = 0, last_v = 0;
  for (Real f : {0.2, 0.1, 0.05, 0.025}) {
    const Collision c = collide(f, wall);
    // dt = f sqrt(m / k); omega = sqrt(k / m*), m* = m/2 for two equal spheres, m for the wall.
    const Real wdt = f * (wall ? 1.0 : std::sqrt(2.0));
    const Real ed = std::abs(c.duration - T_exact) / T_exact;
    const Real ev = std::abs(c.exit_speed - 0.05) / 0.05;
    std::printf("  f = %-6g omega dt %.3f  duration error %.3e (bound %.3e)  exit-speed error %.3e (bound %.3e)\n", f,
                wdt, ed, 1.25 * wdt * wdt / 24, ev, 0.5 * wdt * wdt);
    EXPECT_LT(ed, 1.25 * wdt * wdt / 24);
    EXPECT_LT(ev, 0.5 * wdt * wdt);
    EXPECT_GT(c.exit_speed, 0) << "did not rebound";
    if (f == 0.2) first_v = ev;
    last_v = ev;
  }
  EXPECT_LT(last_v, first_v / 10);
}

}  // namespace

TEST(Collision, HeadOnDurationAndRestitution) {
  const Real r = 0.3e-3, m = test::sphere_mass(r), kn = 100e6 * r;
  check_convergence(false, M_PI * std::sqrt(0.5 * m / kn));  // m* = m/2
}

TEST(Collision, WallBounceDurationAndRestitution) {
  const Real r = 0.3e-3, m = test::sphere_mass(r), kw = 100e6 * r;
  check_convergence(true, M_PI * std::sqrt(m / kw));
}

// Linear dashpot with the no-cohesion clip: the contact ends when k delta + c v_n = 0 (delta > 0).
// Closed form: omega_d t* = pi - atan(2 z sqrt(1 - z^2) / (1 - 2 z^2)), e = e^{-z w t*} (cos - z w/w_d sin).
// The dashpot reads the half-step velocity, a first-order lag: error <= z omega dt at every f, and it
// must fall by > 5x over the 8x range of f.
TEST(Collision, ViscousRestitutionMatchesClosedForm) {
  const Real z = 0.2;
  const Real w = 1, wd = std::sqrt(1 - z * z);
  const Real ts = (M_PI - std::atan(2 * z * std::sqrt(1 - z * z) / (1 - 2 * z * z))) / wd;
  const Real e_exact = std::abs(std::exp(-z * w * ts) * (std::cos(wd * ts) - z * w / wd * std::sin(wd * ts)));
  Real first = 0, last = 0;
  for (Real f : {0.1, 0.05, 0.025, 0.0125}) {
    const Collision c = collide(f, false, z);
    const Real e = c.exit_speed / 0.05;
    const Real err = std::abs(e - e_exact) / e_exact;
    const Real wdt = f * std::sqrt(2.0);
    std::printf("  f = %-6g restitution %.5f (exact %.5f) error %.2e (bound %.2e)\n", f, e, e_exact, err, z * wdt);
    EXPECT_LT(err, z * wdt);
    if (f == 0.1) first = err;
    last = err;
  }
  EXPECT_LT(last, first / 5);
}

// numerics.fines_mass_radius (EngineParams::fines_mass_radius): a sphere under the radius weighs as a sphere of that
// radius. A fine (r 0.1 mm, scaled to the mass of a 0.2 mm sphere: 8x) hits a coarse sphere (0.3 mm) at rest, head-on,
// undamped. The linear contact's duration is pi sqrt(m*/k) with m* of the scaled mass (leapfrog's bound as above; the
// unscaled fine's would be 2.5x shorter), the pair's momentum with the scaled masses is conserved to rounding (pair
// forces are equal and opposite each step: 1e-12, where a run of the unscaled masses would miss by 1.7 times it), and the exit
// velocities are the elastic collision's of those masses. The step is f sqrt(m(r_f) / k_max): 2^1.5 = 2.83x the
// unscaled run's; the rolling limit sqrt(I_min / k_r) has I_min = 2/5 m(r_f) r_min^2.
TEST(Collision, AFineWeighsAsASphereOfTheFinesMassRadius) {
  const Real rs = 0.1e-3, rb = 0.3e-3, rf = 0.2e-3, V = 0.05, f = 0.05;
  const Real ms = test::sphere_mass(rf), mb = test::sphere_mass(rb), k = 100e6 * 0.5 * (rs + rb);
  EngineParams p;
  p.contact = test::reference_contact();
  p.damping = 0;
  p.dt_factor = f;
  p.skin = 0.05e-3;
  p.fines_mass_radius = rf;
  ParticleSetup s;
  const Real gap0 = 10e-6;
  s.x = {{0, 0, 0}, {rs + rb + gap0, 0, 0}};
  s.v = {{V, 0, 0}, {0, 0, 0}};
  s.r = {rs, rb};
  Engine eng(s, p, WallSet{}, false);
  EXPECT_NEAR(eng.dt(), f * std::sqrt(ms / (100e6 * rb)), 1e-12 * eng.dt());
  {
    EngineParams off = p;
    off.fines_mass_radius = 0;
    const Engine spec(s, off, WallSet{}, false);
    EXPECT_NEAR(eng.dt() / spec.dt(), std::pow(rf / rs, 1.5), 1e-12);
    EngineParams big = p;
    big.fines_mass_radius = 0.5 * rs;  // under every radius: SPEC §1's masses, to the bit
    EXPECT_EQ(Engine(s, big, WallSet{}, false).dt(), spec.dt());
  }
  const StableStep st = stable_step(s.r, 2650, 1, p);
  const Real rbar = 0.5 * (rs + rb);
  EXPECT_NEAR(st.roll, std::sqrt(0.4 * ms * rs * rs / (100e6 * rbar * rbar * rbar)), 1e-12 * st.roll);
  EXPECT_NEAR(st.m_min, ms, 1e-12 * ms);
  const Real duration = contact_duration(eng, [&] {
    const auto x = eng.positions();
    return x[1][0] - x[0][0] - rs - rb;
  });
  ASSERT_GT(duration, 0) << "no separation";
  const Real T = M_PI * std::sqrt(ms * mb / (ms + mb) / k);
  const Real wdt = eng.dt() * std::sqrt(k * (ms + mb) / (ms * mb));
  std::printf("  duration %.6e s (exact %.6e, unscaled fine %.6e), omega dt %.3f\n", duration, T,
              M_PI * std::sqrt(test::sphere_mass(rs) * mb / (test::sphere_mass(rs) + mb) / k), wdt);
  EXPECT_LT(std::abs(duration - T) / T, 1.25 * wdt * wdt / 24);
  const auto v = eng.velocities();
  EXPECT_NEAR(ms * v[0][0] + mb * v[1][0], ms * V, 1e-12 * ms * V);
  // Elastic exit velocities of the scaled masses, to leapfrog's exit-speed bound (above).
  EXPECT_NEAR(v[0][0], (ms - mb) / (ms + mb) * V, 0.5 * wdt * wdt * V);
  EXPECT_NEAR(v[1][0], 2 * ms / (ms + mb) * V, 0.5 * wdt * wdt * V);
}
