// Bitwise reproducibility. Issue 2 items 8 (history across rebuilds) and 9 (determinism); the
// 1-thread vs 2-thread comparison runs determinism_probe in two processes (tests/CMakeLists.txt).
#include <gtest/gtest.h>

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

// A capture restored into a fresh engine (new list built at the restored positions, history carried by
// pair identity) continues bitwise like the uninterrupted run.
TEST(Determinism, CaptureRestoreContinuesBitwise) {
  const test::ShearRun straight = test::sheared_scene(false);
  const test::ShearRun restarted = test::sheared_scene(false, 20e-6, 2000, 1000);
  EXPECT_TRUE(test::bitwise_equal(straight.state, restarted.state));
  EXPECT_EQ(0, std::memcmp(straight.measures.data(), restarted.measures.data(),
                           straight.measures.size() * sizeof(double)));
}
