// Device residency (issue 6): the time-step loop moves no per-particle or per-pair data between memory
// spaces; only reduction results (wall loads, max displacement, the few numbers a servo or a stop
// criterion reads) cross. Measured with Kokkos' deep-copy profiling hook, so it holds on any backend:
// the bytes copied per step must be small and must not grow with the number of particles. On CUDA the
// host and device spaces differ, so any per-step array transfer would show as a large crossing copy; on
// OpenMP a host mirror is the array itself (no copy happens), so there the test checks the reductions.
#include <gtest/gtest.h>

#include <string>

#include "helpers.hpp"

using namespace grainlab;

namespace {
struct Tally {
  std::uint64_t small_bytes = 0, crossing_large = 0, same_space_large = 0;
};
Tally g;
void on_deep_copy(Kokkos::Tools::SpaceHandle dst, const char*, const void*, Kokkos::Tools::SpaceHandle src, const char*,
                  const void*, std::uint64_t size) {
  if (size <= 1024) g.small_bytes += size;                            // reduction results
  else if (std::string(dst.name) != std::string(src.name)) g.crossing_large += size;  // host <-> device arrays
  else g.same_space_large += size;  // device-to-device, e.g. x_ref = x at a rebuild
}

Tally per_step(int n, double& small_per_step) {
  test::DenseScene sc = test::consolidated_scene(n, 3, 3, 0.5, 0.2, 200);
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  for (int k = 0; k < 6; ++k) {  // servoed walls: the servo reads reductions every step
    eng.wall_control(k).mode = WallMode::Servo;
    eng.wall_control(k).target_stress = 190e3;
  }
  eng.run(20);
  const int rebuilds0 = eng.rebuild_count();
  g = Tally{};
  Kokkos::Tools::Experimental::set_begin_deep_copy_callback(on_deep_copy);
  const int steps = 300;
  eng.run(steps);
  Kokkos::Tools::Experimental::set_begin_deep_copy_callback(nullptr);
  small_per_step = double(g.small_bytes) / steps;
  std::printf("  N = %d: %.1f bytes of reductions per step; %llu bytes of large host<->device copies; %llu bytes "
              "of device-to-device copies over %d rebuilds\n", n, small_per_step, (unsigned long long)g.crossing_large,
              (unsigned long long)g.same_space_large, eng.rebuild_count() - rebuilds0);
  EXPECT_GT(eng.rebuild_count() - rebuilds0, 0) << "the measured steps must include neighbour rebuilds";
  return g;
}
}  // namespace

TEST(Residency, StepLoopCopiesOnlyReductions) {
  double small_n = 0, large_n = 0;
  const Tally a = per_step(300, small_n), b = per_step(2400, large_n);
  EXPECT_EQ(a.crossing_large, 0u);
  EXPECT_EQ(b.crossing_large, 0u);
  // Reductions per step: wall loads (18 values) and a few scalars, the same at 8x the particles.
  EXPECT_LT(large_n, 512.0);
  EXPECT_LT(large_n, 1.2 * small_n + 16);
}
