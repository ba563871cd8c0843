#pragma once
// Scenes shared by the tests.
#include <cmath>
#include <cstring>
#include <memory>
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
                                     Real pressure = 190e3, Real servo_max_step = 2e-3) {
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
  s.params.servo_max_step = servo_max_step;
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

namespace grainlab::test {

// The determinism scene: a consolidated frictional, rolling-resistant sample sheared by its walls (axial
// walls at constant speed, lateral walls servoed), so contacts slide, roll, open and close and the list
// is rebuilt. Returns the final state (x, v, w, then the six wall offsets) as raw doubles.
struct ShearRun {
  std::vector<Vec3d> state;
  std::vector<double> measures;  // diagnostics and descriptors at the end (must be as reproducible)
  int rebuilds = 0, refilters = 0, contacts = 0, sliding = 0, rolling_sliding = 0;
};

// kernel, normal_damping, mu_r: the contact kernel and the law's optional terms (negative: the scene's own).
// split_steps: evaluate() + advance() instead of step() (which fuses the wall loads into the integration).
inline ShearRun sheared_scene(bool rebuild_every_step, Real skin = 20e-6, int shear_steps = 2000,
                              int restart_at = -1, Real inner_skin = EngineParams{}.inner_skin,
                              PairKernel kernel = kDefaultPairKernel, Real normal_damping = -1, Real mu_r = -1,
                              bool split_steps = false) {
  static const DenseScene base = consolidated_scene(400, 3, 9, 0.3, 0.3, 5000);
  DenseScene sc = base;
  sc.params.contact.mu = 0.5;
  sc.params.contact.mu_r = 0.3;
  sc.params.damping = 0.2;
  sc.params.skin = skin;
  sc.params.inner_skin = inner_skin;
  sc.params.pair_kernel = kernel;
  if (normal_damping >= 0) sc.params.contact.normal_damping = normal_damping;
  if (mu_r >= 0) sc.params.contact.mu_r = mu_r;
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  eng.set_rebuild_every_step(rebuild_every_step);
  const Real H = sc.hi[2] - sc.lo[2];
  for (int k = 0; k < 6; ++k) {
    WallControl& c = eng.wall_control(k);
    if (k >= 4) {
      c.mode = WallMode::Velocity;
      c.velocity = 0.5 * 20.0 * H;  // 20 /s axial strain rate: large slips in a short test
    } else {
      c.mode = WallMode::Servo;
      c.target_stress = 190e3;
    }
  }
  ShearRun out;
  std::unique_ptr<Engine> resumed;  // after restart_at steps, continue in a fresh engine from a capture
  for (int s = 0; s < shear_steps; ++s) {
    if (s == restart_at) {
      const EngineState st = eng.capture();
      resumed = std::make_unique<Engine>(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
      resumed->restore(st);
    }
    Engine& e = resumed ? *resumed : eng;
    if (split_steps) {
      e.evaluate();
      e.advance();
    } else {
      e.step();
    }
    if (s % 100 == 99) {
      const Diagnostics d = e.diagnostics();
      out.sliding = std::max(out.sliding, d.sliding);
      out.rolling_sliding = std::max(out.rolling_sliding, d.rolling_sliding);
    }
  }
  Engine& eng_end = resumed ? *resumed : eng;
  {
    eng_end.evaluate();  // measure at one instant, then finish the step
    const Diagnostics d = eng_end.diagnostics();
    const Descriptors D = eng_end.analyze();
    out.measures = {d.kinetic, d.potential, d.unbalanced_ratio, d.mean_contact_force, D.p, D.q, D.p_walls,
                    D.all.a_c, D.all.a_d, D.all.a_n, D.all.a_t, D.strong.a_n, D.weak.a_t, D.sff, D.share[3], D.f_mean,
                    D.z_mech};
    eng_end.advance();
  }
  out.contacts = eng_end.diagnostics().contacts;
  out.rebuilds = eng.rebuild_count() + (resumed ? resumed->rebuild_count() : 0);
  out.refilters = eng.refilter_count() + (resumed ? resumed->refilter_count() : 0);
  auto x = eng_end.positions(), v = eng_end.velocities(), w = eng_end.angular_velocities();
  out.state.insert(out.state.end(), x.begin(), x.end());
  out.state.insert(out.state.end(), v.begin(), v.end());
  out.state.insert(out.state.end(), w.begin(), w.end());
  Vec3d walls[2];
  for (int k = 0; k < 6; ++k) walls[k / 3][k % 3] = eng_end.walls().w[k].offset;
  out.state.push_back(walls[0]);
  out.state.push_back(walls[1]);
  return out;
}

}  // namespace grainlab::test
