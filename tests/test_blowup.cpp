// Blow-up detection (issue 7): each trigger is named with step, particle ids, quantity and a suggested
// dt; the lab stops before a broken state can overwrite a good checkpoint.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "helpers.hpp"
#include "src/h5io.hpp"
#include "src/simulation.hpp"
#include "scratch.hpp"

using namespace grainlab;
namespace fs = std::filesystem;

namespace {
// Two spheres in a box, at rest, touching lightly.
struct Pair2 {
  ParticleSetup s;
  EngineParams p;
  WallSet walls;
  Pair2() {
    s.x = {{1e-3, 1e-3, 1e-3}, {1.0e-3 + 0.59e-3, 1e-3, 1e-3}};
    s.r = {0.3e-3, 0.3e-3};
    p.contact = test::reference_contact();
    walls = make_box_walls({0, 0, 0}, {3e-3, 3e-3, 3e-3});
  }
};
HealthReport health_after(const std::function<void(EngineState&)>& corrupt) {
  Pair2 sc;
  Engine eng(sc.s, sc.p, sc.walls, true);
  eng.run(3);
  EngineState st = eng.capture();
  corrupt(st);
  eng.restore(st);
  return eng.check_health(HealthLimits{});
}
void expect_named(const HealthReport& h, const char* what, const char* particle) {
  EXPECT_FALSE(h.ok);
  EXPECT_NE(h.what.find("at step 3"), std::string::npos) << h.what;
  EXPECT_NE(h.what.find(what), std::string::npos) << h.what;
  EXPECT_NE(h.what.find(particle), std::string::npos) << h.what;
  EXPECT_NE(h.what.find("suggested: dt <="), std::string::npos) << h.what;
}
}  // namespace

TEST(BlowUp, HealthyStatePasses) { EXPECT_TRUE(health_after([](EngineState&) {}).ok); }

TEST(BlowUp, NonFiniteStateIsNamed) {
  expect_named(health_after([](EngineState& s) { s.v[1][2] = std::numeric_limits<double>::quiet_NaN(); }),
               "non-finite", "particle 1");
  expect_named(health_after([](EngineState& s) { s.x[0][0] = std::numeric_limits<double>::infinity(); }),
               "non-finite", "particle 0");
}

TEST(BlowUp, ExplodingSpeedIsNamed) {
  // 1e3 m/s moves far more than half a radius per step.
  expect_named(health_after([](EngineState& s) { s.v[1] = {1e3, 0, 0}; }), "per step", "particle 1");
}

TEST(BlowUp, EscapeIsNamed) {
  expect_named(health_after([](EngineState& s) { s.x[1] = {1e-3, 1e-3, 4e-3}; }), "escaped through a wall",
               "particle 1");
}

TEST(BlowUp, OverlapAboveThresholdIsNamed) {
  // centres ~0.45 mm apart with radii 0.3 mm: overlap ~0.15 mm = 0.5 r (particle 0 moved a little in 3 steps).
  // An impact: particle 1 closes in at 10 % of the overlap per step, so the time step is a suspect.
  expect_named(health_after([](EngineState& s) {
                 s.x[1] = {1.45e-3, 1e-3, 1e-3};
                 s.v[1] = {-0.1 * 0.15e-3 / s.dt, 0, 0};
               }),
               "overlap by 0.49", "particles 0 and 1");
}

TEST(BlowUp, SlowSqueezeDoesNotBlameTheTimeStep) {
  // The same overlap at rest (closing by ~0 % per step) is a soft contact under load: the advice is the
  // stiffness or numerics.max_overlap, and no dt, which could not help.
  const HealthReport h = health_after([](EngineState& s) { s.x[1] = {1.45e-3, 1e-3, 1e-3}; });
  EXPECT_FALSE(h.ok);
  EXPECT_NE(h.what.find("overlap by 0.49"), std::string::npos) << h.what;
  EXPECT_NE(h.what.find("a slow squeeze, not an impact"), std::string::npos) << h.what;
  EXPECT_NE(h.what.find("numerics.max_overlap"), std::string::npos) << h.what;
  EXPECT_EQ(h.what.find("suggested: dt"), std::string::npos) << h.what;
}

// A material far too soft for the pressure (E = 2 MPa at 190 kPa) overlaps beyond 20 %: the run stops with
// the diagnostic (also in blowup.txt), and the newest checkpoint predates the event and is healthy.
TEST(BlowUp, LabStopsAndKeepsTheLastGoodCheckpoint) {
  const fs::path dir = test::scratch("blowup");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "soft.yaml") << "sample: {count: 300, seed: 3, density_scaling: 1000}\n"
                                      "material: {E: 2.0e6}\n"
                                      "stages:\n  - {name: consolidate, type: isotropic, mu: 0.3, max_steps: 40000}\n"
                                      "output: {every: 200, checkpoint_every: 1000, checkpoint_minutes: 0}\n";
  const RunConfig cfg = load_run_config((dir / "soft.yaml").string());
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.quiet = true;
  std::string msg;
  try {
    run_simulation(cfg, o);
  } catch (const BlowUpError& e) {
    msg = e.what();
  }
  ASSERT_NE(msg.find("numerical blow-up at step"), std::string::npos) << msg;
  EXPECT_NE(msg.find("overlap by"), std::string::npos) << msg;
  EXPECT_NE(msg.find("raise material.E"), std::string::npos) << msg;
  EXPECT_TRUE(fs::exists(dir / "out" / "blowup.txt"));
  const long event = std::stol(msg.substr(msg.find("at step ") + 8));
  std::vector<std::string> ck;
  for (auto& f : fs::directory_iterator(dir / "out" / "checkpoints")) ck.push_back(f.path());
  std::sort(ck.begin(), ck.end());
  ASSERT_FALSE(ck.empty());
  H5Reader r(ck.back());
  const EngineState s = read_state(r);
  EXPECT_LT(s.step, event);
  ParticleSetup setup;
  setup.x = s.x;
  setup.r = s.r;
  setup.density_scaling = 1000;
  EngineParams p = cfg.engine;
  Engine eng(setup, p, s.walls, true);
  eng.restore(s);
  EXPECT_TRUE(eng.check_health(cfg.health).ok) << "the kept checkpoint must be a good state";
}
