// CycleLoop (src/cycle_loop.hpp) on loops whose modulus and damping ratio are known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "src/cycle_loop.hpp"

using grainlab::CycleLoop;

namespace {
// The ellipse q = Q sin(t), eps = E sin(t - phi), t over one period in n steps (compression first, as a cyclic stage
// loads): area pi Q E sin(phi), so D = sin(phi) / 2, and E_eq = Q / E.
CycleLoop ellipse(double Q, double E, double phi, int n) {
  CycleLoop L;
  L.start(0, E * std::sin(-phi), 0);
  for (int k = 1; k <= n; ++k) {
    const double t = 2 * M_PI * k / n;
    L.add(Q * std::sin(t), E * std::sin(t - phi), 0);
  }
  return L;
}
}  // namespace

// The trapezoid rule integrates a smooth periodic loop to spectral accuracy; the sampled extremes miss the true ones
// by ~(2 pi / n)^2 / 8 of the amplitude: 5e-6 at n = 1000, so 1e-4 is the tolerance on D and E_eq.
TEST(CycleLoop, EllipseGivesSinPhiOverTwo) {
  for (double phi : {0.05, 0.3, 1.0}) {
    SCOPED_TRACE(phi);
    const CycleLoop L = ellipse(40e3, 1e-3, phi, 1000);
    EXPECT_NEAR(L.damping(), std::sin(phi) / 2, 1e-4);
    EXPECT_NEAR(L.modulus() / (40e3 / 1e-3), 1.0, 1e-4);
    EXPECT_GT(L.work, 0) << "a loop run compression first and lagging in strain dissipates";
  }
}

// An elastic loop (q proportional to eps, loaded and unloaded along one line) has no area: the trapezoids of a linear
// q telescope to zero, so D is zero to rounding.
TEST(CycleLoop, ElasticLineHasNoDamping) {
  const CycleLoop L = ellipse(40e3, 1e-3, 0.0, 997);
  EXPECT_LT(std::abs(L.damping()), 1e-12);
  EXPECT_NEAR(L.modulus(), 4e7, 4e7 * 1e-4);
}

// A rigid-plastic loop, the rectangle 2 q_a x 2 eps_a, dissipates the most a loop of these amplitudes can: D = 2/pi.
TEST(CycleLoop, RigidPlasticRectangleGivesTwoOverPi) {
  CycleLoop L;
  const double q = 50e3, e = 2e-3;
  L.start(q, -e, 0);
  L.add(q, e, 0);    // loading at +q
  L.add(-q, e, 0);   // the turn: q drops at constant strain
  L.add(-q, -e, 0);  // unloading at -q
  L.add(q, -e, 0);   // back to the start
  EXPECT_DOUBLE_EQ(L.damping(), 2 / M_PI);
  EXPECT_DOUBLE_EQ(L.modulus(), q / e);
}

// The largest u, and the state round trip a checkpoint relies on (a restored loop goes on to the same numbers).
TEST(CycleLoop, StateRoundTripAndPorePressure) {
  CycleLoop a = ellipse(40e3, 1e-3, 0.3, 100);
  a.add(1e3, 2e-4, 7e3);
  a.add(2e3, 3e-4, 5e3);
  EXPECT_EQ(a.u_max, 7e3);
  CycleLoop b;
  b.set_state(a.state());
  a.add(3e3, 1e-4, 1e3);
  b.add(3e3, 1e-4, 1e3);
  EXPECT_EQ(a.state(), b.state());
  EXPECT_THROW(b.set_state({1.0, 2.0}), std::runtime_error);
}
