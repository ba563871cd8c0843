// Energy drift of a frictionless, undamped dense packing (issue 5, speed against error): the race scene
// (or a corner of it) between fixed walls, mu = mu_r = 0, no damping, random velocities of 0.01 m/s,
// SPEC stiffness k_n = E r̄ with E = 100 MPa. Leapfrog's shadow energy E = PE(x_n) + (KE_{n-1/2} +
// KE_{n+1/2}) / 2 is measured every step; the drift is |mean of the last tenth - mean of the first
// tenth| / E_0 (tests/test_conservation.cpp uses the same measure).
//
//   energy_drift --scene FILE --box FILE [--crop F] [--dt-factor f] [--skin m] [--steps N]
// prints: drift=<rel> band=<rel> particle_steps_per_s=<rate> dt=<s> rebuilds=<n>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <random>
#include <string>

#include "scene.hpp"
#include "src/energy_tally.hpp"

using namespace grainlab;

int main(int argc, char** argv) {
  perf::SceneArgs sa;
  double f = 0.2, skin = 1e-4;
  long steps = 10000;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) {
      std::cerr << "energy_drift: missing value after " << k << "\n";
      return 2;
    }
    const std::string v = argv[++i];
    if (sa.parse(k, v)) continue;
    if (k == "--dt-factor") f = std::stod(v);
    else if (k == "--skin") skin = std::stod(v);
    else if (k == "--steps") steps = std::stol(v);
    else {
      std::cerr << "energy_drift: unknown option " << k << "\n";
      return 2;
    }
  }
  compat::initialize(0);
  {
    perf::Scene sc = perf::load_scene(sa);
    std::mt19937_64 g(5);
    std::uniform_real_distribution<Real> U(-1, 1);
    for (size_t i = 0; i < sc.s.r.size(); ++i) sc.s.v.push_back({0.01 * U(g), 0.01 * U(g), 0.01 * U(g)});
    EngineParams p;
    p.contact.E = 100e6;
    p.contact.mu = 0;
    p.contact.mu_r = 0;
    p.damping = 0;
    p.dt_factor = f;
    p.skin = skin;
    Engine eng(sc.s, p, make_box_walls(sc.lo, sc.hi), true);
    EnergyTally tally(steps, eng.diagnostics().kinetic);
    double stepping = 0;  // time inside step() only (the energy sums are diagnostics, not timed)
    for (long k = 0; k < steps; ++k) {
      const Real pe = eng.diagnostics().potential;
      compat::fence("grainlab::drift::before");
      const auto t0 = std::chrono::steady_clock::now();
      eng.step();
      compat::fence("grainlab::drift::after");
      stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      tally.add(pe, eng.diagnostics().kinetic);
    }
    std::printf("drift=%.4e band=%.4e particle_steps_per_s=%.4g dt=%.4e rebuilds=%d particles=%d steps=%ld\n",
                tally.drift(), tally.band(), double(eng.num_particles()) * steps / stepping,
                eng.dt(), eng.rebuild_count(), eng.num_particles(), steps);
  }
  Kokkos::finalize();
  return 0;
}
