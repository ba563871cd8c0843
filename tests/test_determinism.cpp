// Bitwise reproducibility. Issue 2 items 8 (history across rebuilds) and 9 (determinism); the
// 1-thread vs 2-thread comparison runs determinism_probe in two processes (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "helpers.hpp"

using namespace grainlab;

TEST(Determinism, SameRunTwiceIsBitwiseIdentical) {
  const test::ShearRun a = test::sheared_scene(false);
  const test::ShearRun b = test::sheared_scene(false);
  ASSERT_GT(a.rebuilds, 3);
  EXPECT_TRUE(test::bitwise_equal(a.state, b.state));
}

// History is found by pair identity after a rebuild; pairs that are listed but not touching contribute
// exact zeros in the same fixed gather order. So rebuilding every step must give the very same bits as
// rebuilding only when the skin criterion asks for it.
TEST(Determinism, HistorySurvivesRebuildsBitwise) {
  const test::ShearRun lazy = test::sheared_scene(false);
  const test::ShearRun eager = test::sheared_scene(true);
  std::printf("  lazy: %d rebuilds, eager: %d; contacts %d, max sliding %d, max rolling-sliding %d\n", lazy.rebuilds,
              eager.rebuilds, lazy.contacts, lazy.sliding, lazy.rolling_sliding);
  ASSERT_GT(eager.rebuilds, 10 * lazy.rebuilds);
  ASSERT_GT(lazy.sliding, 0) << "the scene must exercise the tangential history";
  ASSERT_GT(lazy.rolling_sliding, 0) << "the scene must exercise the rolling history";
  EXPECT_TRUE(test::bitwise_equal(lazy.state, eager.state));
}

// Different skins give different lists (more or fewer non-touching pairs) rebuilt at different moments;
// the touching pairs, their history and the gather order are the same, so the bits are too.
TEST(Determinism, SkinDoesNotChangeTheTrajectory) {
  const test::ShearRun a = test::sheared_scene(false, 20e-6);
  const test::ShearRun b = test::sheared_scene(false, 60e-6);
  std::printf("  skin 20 um: %d rebuilds, skin 60 um: %d rebuilds\n", a.rebuilds, b.rebuilds);
  ASSERT_NE(a.rebuilds, b.rebuilds);
  EXPECT_TRUE(test::bitwise_equal(a.state, b.state));
  // Measurements too: their sums run per particle over touching pairs, whatever else the list holds.
  ASSERT_EQ(a.measures.size(), b.measures.size());
  EXPECT_EQ(0, std::memcmp(a.measures.data(), b.measures.data(), a.measures.size() * sizeof(double)));
}

// The inner list (EngineParams::inner_skin) holds fewer non-touching pairs and is refiltered between
// Verlet builds; with it off the kernels stream the Verlet list. Same touching pairs, history and gather
// order: the same bits, measurements included.
TEST(Determinism, InnerListDoesNotChangeTheTrajectory) {
  const test::ShearRun off = test::sheared_scene(false, 60e-6, 2000, -1, 0.0);
  const test::ShearRun on = test::sheared_scene(false, 60e-6, 2000, -1, 0.1);
  std::printf("  inner list off: %d rebuilds; inner 0.1: %d rebuilds, %d filters\n", off.rebuilds, on.rebuilds,
              on.refilters);
  ASSERT_EQ(off.refilters, 0);
  ASSERT_GT(on.refilters, 5) << "the run must exercise the filter between Verlet builds";
  EXPECT_TRUE(test::bitwise_equal(off.state, on.state));
  ASSERT_EQ(off.measures.size(), on.measures.size());
  EXPECT_EQ(0, std::memcmp(off.measures.data(), on.measures.data(), off.measures.size() * sizeof(double)));
}

namespace {
// `other` against the row kernel on the sheared scene, for each of the law's four instantiations (rolling,
// viscous normal damping): the same trajectory bits and the same measurements.
void expect_kernel_equals_row_bitwise(PairKernel other) {
  for (const Real beta : {0.0, 0.3}) {
    for (const Real mu_r : {0.0, 0.3}) {
      SCOPED_TRACE("normal_damping " + std::to_string(beta) + ", mu_r " + std::to_string(mu_r));
      const test::ShearRun row = test::sheared_scene(false, 60e-6, 1500, -1, 0.1, PairKernel::Row, beta, mu_r);
      const test::ShearRun run = test::sheared_scene(false, 60e-6, 1500, -1, 0.1, other, beta, mu_r);
      std::printf("  beta %g mu_r %g: %d rebuilds, %d filters, %d contacts, max sliding %d, max rolling-sliding %d\n",
                  beta, mu_r, row.rebuilds, row.refilters, row.contacts, row.sliding, row.rolling_sliding);
      ASSERT_GT(row.rebuilds + row.refilters, 3) << "contacts must open and close";
      ASSERT_GT(row.sliding, 0);
      if (mu_r > 0) {
        ASSERT_GT(row.rolling_sliding, 0);
      }
      EXPECT_TRUE(test::bitwise_equal(row.state, run.state));
      ASSERT_EQ(row.measures.size(), run.measures.size());
      EXPECT_EQ(0, std::memcmp(row.measures.data(), run.measures.data(), row.measures.size() * sizeof(double)));
    }
  }
}
}  // namespace

// The contact kernels (kernels/dem.hpp PairKernel) evaluate the same law in the same operation order, and the
// integration sums i's share in the same order from each, so the trajectories are the same bits. The pair-lane
// kernel also writes +0 where the row kernel skips a separated pair; the sums prove that harmless. Where the
// lanes kernel is not built (a GPU, a CPU without AVX2) it has nothing to compare.
TEST(Determinism, PairLaneKernelEqualsRowKernelBitwise) {
  if constexpr (!kPairLanesBuilt) {  // constexpr: no unreachable loop for nvcc to warn about
    GTEST_SKIP() << "the pair-lane kernel is not built for this target";
  } else {
    expect_kernel_equals_row_bitwise(PairKernel::Lanes);
  }
}

// The one-pair-per-work-item kernel (the GPUs' default, built everywhere) with its +0 shares for separated pairs.
TEST(Determinism, PairKernelEqualsRowKernelBitwise) { expect_kernel_equals_row_bitwise(PairKernel::Pairs); }

// Engine::step() sums the wall loads inside the integration's pass on host backends; evaluate() + advance()
// sums them in their own pass (reduce_wall_loads). Same chunks, same order: the same loads, and through the
// servoed walls (the lateral walls follow their loads every step) the same trajectory, bit for bit.
TEST(Determinism, FusedWallLoadsEqualSeparatePass) {
  const test::ShearRun fused = test::sheared_scene(false, 60e-6, 1500, -1, 0.1, kDefaultPairKernel, 0.3, 0.3, false);
  const test::ShearRun split = test::sheared_scene(false, 60e-6, 1500, -1, 0.1, kDefaultPairKernel, 0.3, 0.3, true);
  ASSERT_GT(fused.contacts, 0);
  EXPECT_TRUE(test::bitwise_equal(fused.state, split.state));
  ASSERT_EQ(fused.measures.size(), split.measures.size());
  EXPECT_EQ(0, std::memcmp(fused.measures.data(), split.measures.data(), fused.measures.size() * sizeof(double)));
}

// A capture restored into a fresh engine (new list built at the restored positions, history carried by
// pair identity) continues bitwise like the uninterrupted run.
TEST(Determinism, CaptureRestoreContinuesBitwise) {
  const test::ShearRun straight = test::sheared_scene(false);
  const test::ShearRun restarted = test::sheared_scene(false, 20e-6, 2000, 1000);
  EXPECT_TRUE(test::bitwise_equal(straight.state, restarted.state));
  EXPECT_EQ(0, std::memcmp(straight.measures.data(), restarted.measures.data(),
                           straight.measures.size() * sizeof(double)));
}

namespace {
// Outside the test body: nvcc refuses device lambdas in private member functions (gtest's TestBody).
void sum_both_ways(const Kokkos::View<Real**, Kokkos::LayoutRight, MemSpace>& terms, Real* chunk, Real* team) {
  const int n = int(terms.extent(0)), nv = int(terms.extent(1));
  auto f = KOKKOS_LAMBDA(int i, Real* acc) {
    for (int k = 0; k < nv; ++k)
      if (terms(i, k) != 0 || (i + k) % 2) acc[k] += terms(i, k);  // some items add a zero, some add none
  };
  DeterministicSum red;
  red.run("test::chunk", n, nv, f, chunk);
  red.run_one_term<true>("test::team", n, nv, f, team);
}
}  // namespace

// DeterministicSum::run_one_term's team path (the GPU's: items in parallel, then added in item order) must
// give run()'s bits for any f with at most one term per value per item. Oracle: run() on the same items.
// Terms span 12 decades with both signs and exact zeros (so any change of the addition order shows in the
// last bits), some items add nothing, and n covers a partial chunk, one chunk, and more chunks than the
// GPU's stage-2 block (1 024) so every path of the team code runs, stage 2 included. On a host backend
// the team path runs with team size 1: the same code, serial.
TEST(Determinism, TeamReductionEqualsChunkReductionBitwise) {
  for (const int n : {1, 255, 257, 5000, 300000}) {
    const int nv = 17;
    Kokkos::View<Real**, Kokkos::LayoutRight, MemSpace> terms("test::terms", n, nv);
    auto h = Kokkos::create_mirror_view(terms);
    std::mt19937_64 g(n);
    std::uniform_real_distribution<double> U(0, 1);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < nv; ++k) {
        const double u = U(g);
        h(i, k) = u < 0.3 ? 0.0 : (u < 0.35 ? -0.0 : (U(g) < 0.5 ? -1 : 1) * std::pow(10.0, 12 * U(g) - 6));
      }
    Kokkos::deep_copy(terms, h);
    Real chunk[DeterministicSum::kMaxValues] = {}, team[DeterministicSum::kMaxValues] = {};
    sum_both_ways(terms, chunk, team);
    EXPECT_EQ(0, std::memcmp(chunk, team, nv * sizeof(Real))) << "n = " << n;
    // The sums are not trivially equal: a different order (pairwise halves) changes the last bits.
    if (n == 300000) {
      double fwd = 0, rev = 0;
      for (int i = 0; i < n; ++i) fwd += h(i, 0);
      for (int i = n - 1; i >= 0; --i) rev += h(i, 0);
      EXPECT_NE(fwd, rev) << "the data must be order sensitive for this test to mean anything";
    }
  }
}

// The wall loads, the servo's input, through both paths on a packing pressed against its walls.
TEST(Determinism, WallLoadsTeamPathEqualsChunkPath) {
  test::DenseScene sc = test::consolidated_scene(2000, 3, 7, 0.3, 0.1, 1500);
  Engine eng(sc.setup, sc.params, make_box_walls(sc.lo, sc.hi), true);
  DeterministicSum red;
  const WallLoads a = reduce_wall_loads(eng.particles(), eng.walls(), eng.params().E_wall, red, /*team=*/false);
  const WallLoads b = reduce_wall_loads(eng.particles(), eng.walls(), eng.params().E_wall, red, /*team=*/true);
  int touching = 0;
  for (int k = 0; k < 6; ++k) {
    touching += a.touching[k];
    EXPECT_EQ(0, std::memcmp(&a.force[k], &b.force[k], sizeof(Real))) << "wall " << k;
    EXPECT_EQ(0, std::memcmp(&a.stiffness[k], &b.stiffness[k], sizeof(Real))) << "wall " << k;
    EXPECT_EQ(a.touching[k], b.touching[k]) << "wall " << k;
    EXPECT_GT(a.force[k], 0) << "wall " << k << " must carry load for the comparison to mean anything";
  }
  std::printf("  %d sphere-wall contacts compared\n", touching);
}

// More values than the team path's scratch holds is refused, not launched.
TEST(Determinism, TeamReductionRefusesTooManyValues) {
  Kokkos::View<Real**, Kokkos::LayoutRight, MemSpace> terms("test::terms", 10, DeterministicSum::kOneTermMaxValues + 1);
  Real chunk[DeterministicSum::kMaxValues] = {}, team[DeterministicSum::kMaxValues] = {};
  EXPECT_THROW(sum_both_ways(terms, chunk, team), std::logic_error);
}
