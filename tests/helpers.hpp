#pragma once
// Scenes shared by the tests.
#include <cmath>
#include <cstring>
#include <vector>

#include "src/engine.hpp"
#include "src/packing.hpp"

namespace grainlab::test {

inline ContactParams reference_contact() {
  ContactParams c;
  c.E = 100e6;
  c.kappa = 1;
  c.mu = 0.5;
  c.mu_r = 0;
  c.roll_arm = 0.05;
  return c;
}

inline Real sphere_mass(Real r, Real rho = 2650) { return 4.0 / 3.0 * M_PI * r * r * r * rho; }

// A loose SPEC-like sample consolidated by servo walls for `steps` steps (friction mu, rolling mu_r):
// a dense, frictional, well-connected packing in a few thousand steps.
struct DenseScene {
  ParticleSetup setup;
  EngineParams params;
  Vec3d lo, hi;
};

inline DenseScene consolidated_scene(int n, Real size_ratio, std::uint64_t seed, Real mu, Real mu_r, long steps,
                                     Real pressure = 190e3) {
  PackingSpec ps;
  ps.count = n;
  ps.r_max = 0.6e-3;
  ps.r_min = ps.r_max / size_ratio;
  ps.D = size_ratio > 5 ? 2.5 : 3.63;  // fewer dust particles at ratio 10: keeps the tests small
  ps.seed = seed;
  ps.solid_fraction = 0.3;
  Packing pk = generate_packing(ps);
  DenseScene s;
  s.setup.x = pk.x;
  s.setup.r = pk.r;
  s.setup.density_scaling = 1000;
  s.params.contact = reference_contact();
  s.params.contact.mu = mu;
  s.params.contact.mu_r = mu_r;
  s.params.damping = 0.7;
  s.params.servo_max_step = 2e-3;
  Engine eng(s.setup, s.params, make_box_walls(pk.lo, pk.hi), true);
  for (int k = 0; k < 6; ++k) {
    eng.wall_control(k).mode = WallMode::Servo;
    eng.wall_control(k).target_stress = pressure;
  }
  eng.run(steps);
  s.setup.x = eng.positions();
  s.setup.v.clear();
  s.setup.w.clear();
  for (int k = 0; k < 3; ++k) {
    s.lo[k] = eng.wall_position(2 * k);
    s.hi[k] = eng.wall_position(2 * k + 1);
  }
  return s;
}

// Bitwise equality of two host arrays of vectors.
inline bool bitwise_equal(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3d)) == 0;
}

inline std::vector<Vec3d> host_vec(const VecView& v, int n) {
  auto all = Engine::to_host(v);
  all.resize(n);
  return all;
}

}  // namespace grainlab::test
