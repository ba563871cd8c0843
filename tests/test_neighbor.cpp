// The Verlet list against a brute-force N^2 oracle. Issue 2 item 7.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "helpers.hpp"

using namespace grainlab;

namespace {

std::vector<std::pair<int, int>> listed_pairs(const PairList& L) {
  auto pi = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_i);
  auto pj = Kokkos::create_mirror_view_and_copy(HostSpace(), L.pair_j);
  std::vector<std::pair<int, int>> out;
  for (int p = 0; p < L.npairs; ++p) out.emplace_back(pi(p), pj(p));
  return out;
}

std::vector<std::pair<int, int>> listed_pairs(const Engine& eng) { return listed_pairs(eng.pairs()); }

// A granular gas in a box: 600 spheres at solid fraction 0.25, r_max = 0.6 mm and r_min = r_max / size_ratio, at rest;
// skin 0.1 r_max.
struct Gas {
  PackingSpec spec;
  Packing pk;
  ParticleSetup setup;
  EngineParams params;
};
Gas make_gas(Real size_ratio, std::uint64_t seed) {
  Gas g;
  g.spec.count = 600;
  g.spec.r_max = 0.6e-3;
  g.spec.r_min = g.spec.r_max / size_ratio;
  g.spec.D = 2.5;
  g.spec.seed = seed;
  g.spec.solid_fraction = 0.25;
  g.pk = generate_packing(g.spec);
  g.setup.x = g.pk.x;
  g.setup.r = g.pk.r;
  g.params.contact = test::reference_contact();
  g.params.skin = 0.1 * g.spec.r_max;
  return g;
}

// Between builds every touching pair must be in the kernels' list (the skin/2 criterion guarantees it). Returns the
// number of touching pairs.
int expect_touching_listed(const Engine& eng) {
  std::vector<std::pair<int, int>> oracle;
  brute_force_pairs(eng.particles().x, eng.particles().r, 0, oracle);
  const auto listed = listed_pairs(eng);
  const std::set<std::pair<int, int>> have(listed.begin(), listed.end());
  int missing = 0;
  for (auto& pr : oracle)
    if (!have.count(pr) && missing++ == 0) ADD_FAILURE() << pr.first << "," << pr.second << " touching but unlisted";
  EXPECT_EQ(missing, 0) << "at step " << eng.step_count();
  return int(oracle.size());
}

// A granular gas in a box with collisions: particles cross cells, the list is rebuilt often. With
// inner_skin > 0 the kernels' list is the inner list: after every Verlet build or filter it must equal
// the oracle for the inner margin (so the Verlet list held every pair the filter needed).
void check_against_oracle(Real size_ratio, std::uint64_t seed, Real inner_skin) {
  Gas gas = make_gas(size_ratio, seed);
  const Packing& pk = gas.pk;
  ParticleSetup& s = gas.setup;
  EngineParams& p = gas.params;
  p.damping = 0;
  p.inner_skin = inner_skin;
  // Speeds such that the fastest particles cross skin/2 in ~20 steps: many rebuilds in a short run.
  const Real dt = Engine(s, p, make_box_walls(pk.lo, pk.hi), true).dt();
  const Real V = 0.5 * p.skin / (20 * dt);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<Real> U(-1, 1);
  for (size_t i = 0; i < s.r.size(); ++i) s.v.push_back({V * U(g), V * U(g), V * U(g)});
  Engine eng(s, p, make_box_walls(pk.lo, pk.hi), true);
  int checked_builds = 0, checked_filters = 0, last_builds = eng.rebuild_count(), last_filters = eng.refilter_count();
  std::vector<std::pair<int, int>> oracle;
  for (int k = 0; k < 1500; ++k) {
    eng.step();
    const bool built = eng.rebuild_count() != last_builds, filtered = eng.refilter_count() != last_filters;
    if (built) {
      // Just rebuilt at the current positions: the list must equal the oracle, pair for pair, in order.
      last_builds = eng.rebuild_count();
      brute_force_pairs(eng.particles().x, eng.particles().r, p.skin, oracle);
      ASSERT_EQ(listed_pairs(eng.verlet_pairs()), oracle) << "after rebuild " << last_builds;
      ++checked_builds;
    }
    if (filtered) {
      last_filters = eng.refilter_count();
      ++checked_filters;
    }
    if ((built || filtered) && inner_skin > 0) {
      brute_force_pairs(eng.particles().x, eng.particles().r, inner_skin * p.skin, oracle);
      ASSERT_EQ(listed_pairs(eng), oracle) << "inner list after rebuild " << last_builds << ", filter " << last_filters;
    } else if (!built && k % 10 == 0) {
      expect_touching_listed(eng);
      if (::testing::Test::HasFailure()) return;
    }
  }
  std::printf("  ratio %g, inner %g: %d rebuilds and %d filters checked, %d pairs listed (Verlet %d)\n", size_ratio,
              inner_skin, checked_builds, checked_filters, eng.pairs().npairs, eng.verlet_pairs().npairs);
  EXPECT_GT(checked_builds, 20);
  if (inner_skin > 0) EXPECT_GT(checked_filters, 20);
  else EXPECT_EQ(checked_filters, 0);
}

}  // namespace

TEST(Neighbor, MatchesBruteForceSizeRatio3) { check_against_oracle(3, 21, 0); }
TEST(Neighbor, MatchesBruteForceSizeRatio10) { check_against_oracle(10, 22, 0); }
TEST(Neighbor, InnerListMatchesBruteForceSizeRatio3) { check_against_oracle(3, 23, 0.3); }
TEST(Neighbor, InnerListMatchesBruteForceSizeRatio10) { check_against_oracle(10, 24, 0.3); }

// A particle far outside the rest must not blow up the cell grid (memory stays O(N)).
TEST(Neighbor, StrayParticleKeepsGridSmall) {
  ParticleSetup s;
  for (int i = 0; i < 100; ++i) s.x.push_back({1e-3 * (i % 10), 1e-3 * (i / 10), 0});
  s.x.push_back({1e3, 1e3, 1e3});
  s.r.assign(s.x.size(), 0.4e-3);
  EngineParams p;
  p.contact = test::reference_contact();
  Engine eng(s, p, WallSet{}, false);
  EXPECT_LE(eng.last_build().ncells, 8L * 101 + 27);
  std::vector<std::pair<int, int>> oracle;
  brute_force_pairs(eng.particles().x, eng.particles().r, p.skin, oracle);
  EXPECT_EQ(listed_pairs(eng.verlet_pairs()), oracle);
}

namespace {
// The engine's first Verlet build on a SPEC §6.1 packing of n spheres (r_max = 0.6 mm, r_max / r_min = ratio,
// random placement at the given solid fraction, skin 0.06 mm).
NeighborStats first_build(int n, Real ratio, std::uint64_t seed, Real solid_fraction) {
  PackingSpec spec;
  spec.count = n;
  spec.r_max = 0.6e-3;
  spec.r_min = spec.r_max / ratio;
  spec.seed = seed;
  spec.solid_fraction = solid_fraction;
  const Packing pk = generate_packing(spec);
  EngineParams p;
  p.contact = test::reference_contact();
  p.skin = 0.1 * spec.r_max;
  ParticleSetup s;
  s.x = pk.x;
  s.r = pk.r;
  return Engine(s, p, make_box_walls(pk.lo, pk.hi), true).last_build();
}
}  // namespace

// Issue 5: "O(N) neighbour search, no hidden N^2". The search's own count of the candidates it examined
// (NeighborStats::examined, summed in the count kernel) per particle, on the same kind of packing at 16k and 128k
// spheres (SPEC §6.1 radii, r_max / r_min = 3, solid fraction 0.3). Per particle it is the mean occupancy of the
// cells visited around a sphere: independent of N but for the box's boundary layer (cells at a face have fewer
// neighbour cells: <= 10 % on grids of >= 20 cells per side, 1 - (1 - 2/(3m))^3) and the grid's rounding of
// the cell edge (box / floor(box / edge), a few % at these sizes). An N^2 search would examine N candidates
// per particle (8x from 16k to 128k), and a grid that coarsened with N grows with it (mutation checked: cell
// edge scaled by cbrt(N / 16k) gave 1074 against 133 with the single grid). Tolerance 1.20, the issue's own 20 %.
// Measured: 35.4 and 36.1 candidates per particle with the size-class grids (132.8 and 130.8 with one grid).
TEST(Neighbor, SearchWorkPerParticleIsIndependentOfN) {
  std::vector<double> per_particle;
  for (int n : {16000, 128000}) {
    const NeighborStats st = first_build(n, 3, 31, 0.3);
    per_particle.push_back(double(st.examined) / n);
    std::printf("  N = %d: %.2f candidates examined and %.2f pairs listed per particle, %.3f cells per particle\n", n,
                per_particle.back(), double(st.npairs) / n, double(st.ncells) / n);
    // Exact lower bound: every listed pair is examined from both ends (from the higher index it is skipped)
    // and every sphere examines itself in its own cell; a count below it would mean the counter misses cells.
    EXPECT_GE(st.examined, 2L * st.npairs + n);
    EXPECT_LE(st.ncells, 8L * n + 27);
  }
  EXPECT_LE(per_particle[1], 1.20 * per_particle[0]) << "search work per particle grows with N";
}

// The size-class grids (SizeClassGrid) keep the search's work per sphere near what a narrow size range costs
// when r_max / r_min is wide. With one grid sized for the largest pair, a SPEC §6.1 packing (p(r) ~ r^-3.63:
// most spheres are small) examined 44 candidates per sphere at r_max / r_min = 1.5 and 1796 at 10, 41x
// (perf/bench_kernels BM_NeighborBuildPSD, 32k, solid fraction 0.35). With classes a factor 2 wide each class
// pair is searched over a box a few times its cutoff sphere, whatever the ratio: measured here (16k, skin
// 0.06 mm) 32.3 and 43.6, 1.35x. Bound 3x: a wider ratio lists more pairs per sphere (1.47 against 0.73 here),
// and the classes are a factor 2 wide, so some growth is real; a single grid fails the bound by an order of
// magnitude (mutation checked: nclasses forced to 1 gave 753 against 32, 23x). The lists themselves are
// checked against the N^2 oracle above at ratios 3 and 10.
TEST(Neighbor, SizeClassesKeepWideSizeRatiosCheap) {
  double per_particle[2] = {0, 0};
  const double ratios[2] = {1.5, 10};
  for (int k = 0; k < 2; ++k) {
    const int n = 16000;
    const NeighborStats st = first_build(n, ratios[k], 5, 0.35);
    per_particle[k] = double(st.examined) / n;
    std::printf("  r_max / r_min = %g: %d size classes, %.2f candidates examined and %.2f pairs listed per particle\n",
                ratios[k], st.size_classes, per_particle[k], double(st.npairs) / n);
    EXPECT_EQ(st.size_classes, k == 0 ? 1 : 4);  // classes a factor 2 wide: 1.5 -> 1, 10 -> 4
    EXPECT_GE(st.examined, 2L * st.npairs + n);
  }
  EXPECT_LE(per_particle[1], 3.0 * per_particle[0]) << "a wide size ratio multiplies the search's work";
}

// The single-pass build (fill_rows): from the second build of a list on, each row is searched once into slots
// sized from its last length (+ a quarter + 4), then compacted. Both the single pass and its fallback (a row
// outgrew its slots: count and fill after all) must give the oracle's list, pair for pair. Mutation checked:
// without the fallback the compressed build loses pairs (the rows are cut at their slots).
TEST(Neighbor, SinglePassBuildMatchesBruteForceAndFallsBack) {
  PackingSpec spec;
  spec.count = 2000;
  spec.r_max = 0.6e-3;
  spec.r_min = spec.r_max / 3;
  spec.seed = 41;
  spec.solid_fraction = 0.3;
  const Packing pk = generate_packing(spec);
  const int n = spec.count;
  const Real skin = 0.1 * spec.r_max;
  VecView x("x", n);
  RealView r("r", n);
  auto hx = Kokkos::create_mirror_view(x);
  auto hr = Kokkos::create_mirror_view(r);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) hx(i, d) = pk.x[i][d];
    hr(i) = pk.r[i];
  }
  Kokkos::deep_copy(r, hr);
  CellGrid grid;
  PairList list;
  std::vector<std::pair<int, int>> oracle;
  auto build = [&](int expected_searches, const char* what) {
    Kokkos::deep_copy(x, hx);
    const NeighborStats st = build_neighbor_list(x, r, skin, grid, list);
    brute_force_pairs(x, r, skin, oracle);
    EXPECT_EQ(listed_pairs(list), oracle) << what;
    EXPECT_EQ(st.searches, expected_searches) << what;
    return st.npairs;
  };
  const int first = build(2, "first build: count, then fill");
  std::mt19937_64 g(7);
  std::uniform_real_distribution<Real> U(-1, 1);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) hx(i, d) += 0.2 * skin * U(g);  // less than skin / 2, as between builds
  build(1, "moved by < skin/2: every row fits its slots");
  Vec3d c{0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) c[d] += hx(i, d) / n;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) hx(i, d) = c[d] + 0.8 * (hx(i, d) - c[d]);
  const int compressed = build(2, "compressed to 0.8: rows outgrow their slots");
  EXPECT_GT(compressed, 2 * first);
  build(1, "the same positions again: the rows fit");
}

// The affine box (Engine::set_affine_box): servo walls close on a still gas, every position is remapped with them.
// Before any two spheres touch, each keeps its place relative to the box, (x - lo) / L, to round-off, and no velocity
// appears (the remap moves positions only); a mutant without the remap fails that at once. Then, compressed on into
// contact, the list must hold every touching pair between builds and equal the N^2 oracle after each build: the
// remap moves every sphere, and the rebuild criterion must see that displacement (a remap that also moved x_ref
// would hide it).
TEST(Neighbor, AffineBoxRemapsPositionsAndKeepsTheListComplete) {
  Gas gas = make_gas(3, 31);
  const PackingSpec& ps = gas.spec;
  const ParticleSetup& s = gas.setup;
  EngineParams& p = gas.params;
  p.servo_max_step = 0.05;  // the walls close fast: a rebuild every few steps near them
  Engine eng(s, p, make_box_walls(gas.pk.lo, gas.pk.hi), true);
  for (int k = 0; k < 6; ++k) {
    eng.wall_control(k).mode = WallMode::Servo;
    eng.wall_control(k).target_stress = 1e5;
  }
  eng.set_affine_box(true);
  const auto relative = [&] {
    std::vector<Vec3d> u = eng.positions();
    for (auto& ui : u)
      for (int a = 0; a < 3; ++a)
        ui[a] = (ui[a] - eng.wall_position(2 * a)) / (eng.wall_position(2 * a + 1) - eng.wall_position(2 * a));
    return u;
  };
  const std::vector<Vec3d> u0 = relative();
  // The spheres with no other (and no wall) within 0.02 r_max: a few steps that shrink the box by less than 0.99 close the gap of a
  // pair at centre distance D < 2.02 r_max (any other is far apart) by (1 - L1 / L0) D < 0.02 r_max, so they stay
  // free and nothing but the remap moves them.
  std::vector<std::pair<int, int>> oracle;
  brute_force_pairs(eng.particles().x, eng.particles().r, 0.02 * ps.r_max, oracle);
  std::vector<bool> free(u0.size(), true);
  for (auto& pr : oracle) free[pr.first] = free[pr.second] = false;
  const std::vector<Vec3d> x0 = eng.positions();
  for (size_t i = 0; i < x0.size(); ++i)  // nor within 0.02 r_max of a wall (a wall closes on a sphere's surface too)
    for (int a = 0; a < 3; ++a)
      if (x0[i][a] - s.r[i] - eng.wall_position(2 * a) < 0.02 * ps.r_max ||
          eng.wall_position(2 * a + 1) - x0[i][a] - s.r[i] < 0.02 * ps.r_max)
        free[i] = false;
  const long nfree = std::count(free.begin(), free.end(), true);
  ASSERT_GT(nfree, long(u0.size()) / 2) << "most spheres of a gas at solid fraction 0.25 are free";
  const Real L0 = eng.wall_position(1) - eng.wall_position(0);
  eng.run(3);
  const Real L1 = eng.wall_position(1) - eng.wall_position(0);
  ASSERT_LT(L1, 0.9995 * L0) << "the walls moved";
  ASSERT_GT(L1, 0.99 * L0) << "but less than the free spheres' margin";
  const std::vector<Vec3d> u1 = relative();
  double worst = 0;
  for (size_t i = 0; i < u0.size(); ++i)
    for (int a = 0; a < 3 && free[i]; ++a) worst = std::max(worst, std::abs(u1[i][a] - u0[i][a]));
  EXPECT_LT(worst, 1e-14) << "relative positions of free spheres moved";  // 3 steps, a few roundings of numbers < 1
  const std::vector<Vec3d> v = eng.velocities();
  for (size_t i = 0; i < u0.size(); ++i) {
    if (free[i]) {
      EXPECT_EQ(v[i], (Vec3d{0, 0, 0})) << i;
    }
  }
  int builds = 0, last = eng.rebuild_count(), touching = 0;
  for (int k = 0; k < 1500; ++k) {
    eng.step();
    if (eng.rebuild_count() != last) {
      last = eng.rebuild_count();
      ++builds;
      brute_force_pairs(eng.particles().x, eng.particles().r, p.skin, oracle);
      ASSERT_EQ(listed_pairs(eng.verlet_pairs()), oracle) << "after rebuild " << last;
    } else if (k % 10 == 0) {
      touching = expect_touching_listed(eng);
      if (::testing::Test::HasFailure()) return;
    }
  }
  std::printf("  box %.3f of its length, %d rebuilds checked, %d touching pairs at the last check\n",
              (eng.wall_position(1) - eng.wall_position(0)) / L0, builds, touching);
  EXPECT_GT(builds, 20);
  EXPECT_GT(touching, 300);  // compressed into a contact network, not only a shrunken gas
}

// The initial placement (generate_packing, random sequential addition on a grid of cells of 2 r_max) against the
// N^2 oracle: no two spheres closer than the sum of their radii (the placement's own test, d^2 >= (r_i + r_j)^2,
// so the bound is exact), every centre a radius inside the box [0, L]^3, the drawn radii all placed, and the spheres
// in cell order (z, y, x). Placed again with one flat slot a cell (every further sphere in a cell's overflow list,
// asserted), the packing is the same bit for bit: whether a try overlaps does not depend on the layout.
TEST(Packing, PlacedSpheresAreApartInsideTheBoxAndInCellOrder) {
  // equal spheres jam earlier (cli_bad_placement); the dilute sample (fraction 1e-5) has its cells capped at ~4 N
  const std::pair<Real, Real> cases[] = {{1.0, 0.2}, {3.0, 0.3}, {20.0, 0.3}, {3.0, 1e-5}};
  for (const auto& [ratio, fraction] : cases) {
    PackingSpec spec;
    spec.count = 4000;
    spec.r_max = 0.6e-3;
    spec.r_min = spec.r_max / ratio;
    spec.seed = 11;
    spec.solid_fraction = fraction;
    const Packing pk = generate_packing(spec);
    const int n = int(pk.x.size());
    ASSERT_EQ(n, spec.count);
    const Real L = pk.hi[0];
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < 3; ++d) {
        EXPECT_GE(pk.x[i][d], pk.r[i]) << "ratio " << ratio << " sphere " << i;
        EXPECT_LE(pk.x[i][d], L - pk.r[i]) << "ratio " << ratio << " sphere " << i;
      }
      for (int j = i + 1; j < n; ++j) {
        Real d2 = 0;
        for (int d = 0; d < 3; ++d) d2 += (pk.x[i][d] - pk.x[j][d]) * (pk.x[i][d] - pk.x[j][d]);
        ASSERT_GE(d2, (pk.r[i] + pk.r[j]) * (pk.r[i] + pk.r[j])) << "ratio " << ratio << ": " << i << ", " << j;
      }
    }
    std::vector<Real> placed = pk.r;
    std::sort(placed.begin(), placed.end(), std::greater<Real>());
    EXPECT_EQ(placed, packing_radii(spec));
    // cells of twice the largest radius drawn, at most ~4 N of them
    const int nc = std::max(1, int(std::min<double>(L / (2 * placed.front()), std::cbrt(4.0 * n))));
    auto cell_of = [&](const Vec3d& x) {
      long k = 0;
      for (int d = 2; d >= 0; --d) k = k * nc + std::min(nc - 1, std::max(0, int(x[d] / (L / nc))));
      return k;
    };
    for (int i = 1; i < n; ++i) ASSERT_LE(cell_of(pk.x[i - 1]), cell_of(pk.x[i])) << "ratio " << ratio << " sphere " << i;
    const Packing one = generate_packing(spec, 1);
    EXPECT_GT(one.overflowed, 0) << "ratio " << ratio;
    EXPECT_EQ(one.r, pk.r) << "ratio " << ratio;
    for (int i = 0; i < n; ++i) ASSERT_EQ(one.x[i], pk.x[i]) << "ratio " << ratio << " sphere " << i;
    std::printf("r_max / r_min = %g at %g: %d spheres apart, in %d^3 cells in order; %ld past their cell's slots (%ld "
                "with one slot, the same packing)\n", ratio, fraction, n, nc, pk.overflowed, one.overflowed);
  }
}

// sample.D (p(r) ~ r^-D on [r_min, r_max], SPEC §1) against its CDF F(r) = (r^(1-D) - a^(1-D)) / (b^(1-D) - a^(1-D)),
// at D = 1 its limit ln(r/a) / ln(b/a), written out here: 200 000 radii drawn as a run draws them (packing_radii), the
// share below each of 9 radii within 5 binomial standard errors sqrt(F (1 - F) / N) of F (a false alarm ~1e-6 a check;
// the D = 3.63 law read as D = 1 misses by 210-360 of them). At D = 1 and 1 +- 1e-9 the inverse CDF is the log-uniform
// one to 1e-8 at every u: the general form, used there before D = 1 was refused, was ~1e-7 off at 1 + 1e-9 (kNearOne
// in power_law_radius). Its ends are a and b to 1e-12 for every D (the general form just past kNearOne is 1e-13 off;
// at 1 + 2e-6 it was 5e-11).
TEST(Packing, PowerLawRadiiFollowTheirDistribution) {
  const double a = 0.2e-3, b = 0.6e-3, kSigmas = 5, kNearOneTol = 1e-8;
  const auto cdf = [&](double D, double r) {
    const double e = 1 - D;
    return e == 0 ? std::log(r / a) / std::log(b / a)
                  : (std::pow(r, e) - std::pow(a, e)) / (std::pow(b, e) - std::pow(a, e));
  };
  for (const double D : {3.63, 1.0, 0.0, 2.0, 6.0}) {
    PackingSpec spec;
    spec.count = 200000;
    spec.seed = 7;
    spec.D = D;
    spec.r_min = a;
    spec.r_max = b;
    const std::vector<Real> r = packing_radii(spec);
    ASSERT_EQ(long(r.size()), spec.count);
    EXPECT_GE(*std::min_element(r.begin(), r.end()), a) << "D " << D;
    EXPECT_LE(*std::max_element(r.begin(), r.end()), b) << "D " << D;
    for (int k = 1; k <= 9; ++k) {
      const double at = a + (b - a) * k / 10, want = cdf(D, at);
      const double got = double(std::count_if(r.begin(), r.end(), [&](Real x) { return x < at; })) / double(r.size());
      const double se = std::sqrt(want * (1 - want) / double(r.size()));
      EXPECT_LE(std::abs(got - want), kSigmas * se) << "D " << D << " at r = " << at << ": " << got << " drawn";
    }
  }
  for (const double u : {0.0, 0.1, 0.37, 0.5, 0.9, 0.999999}) {
    const double log_uniform = a * std::exp(u * std::log(b / a));
    for (const double D : {1.0, 1 - 1e-9, 1 + 1e-9})
      EXPECT_NEAR(power_law_radius(u, D, a, b), log_uniform, kNearOneTol * log_uniform) << "D " << D << ", u " << u;
  }
  for (const double D : {3.63, 1.0, 1 + 1e-9, 1 - 2e-3, 1 + 2e-3, 0.0}) {  // 1 +- 2e-3: the general form's
    EXPECT_NEAR(power_law_radius(0, D, a, b), a, 1e-12 * a) << "D " << D;
    EXPECT_NEAR(power_law_radius(std::nextafter(1.0, 0.0), D, a, b), b, 1e-12 * b) << "D " << D;
  }
}

// sample.grading (a sieve curve: percent passing by mass, linear in ln d between sieves) against its own definition,
// on 400 000 radii drawn as a run draws them (packing_radii). At each sieve, and at each interval's geometric middle
// (where the curve passes the mean of its ends), the drawn mass share finer must be within 5 standard errors of the
// curve's: the standard error of a ratio of sums, Var(R) ~ mean[(v (1_finer - R))^2] / (N mean[v]^2) (the delta
// method; v a sphere's volume), measured on the draw itself. 5 sigma: a false alarm ~1e-6 a check, while a
// sampler of mass uniform in d instead of ln d missed the middles by 1.6-2.9 points (7-18 sigma; seen failing). A flat step (a gap grading)
// draws no sphere inside it. The indices of a known curve: d = 1, 2, 4 mm passing 0, 50, 100 % has D50 = 2 mm, D10 =
// 2^0.2 mm, D60 = 2^1.2 mm (log-linear), so Cu = 2 and Cc = 2^-0.2.
TEST(Packing, AGradingIsDrawnByMassAsItsCurve) {
  PackingSpec spec;
  spec.count = 400000;
  spec.seed = 5;
  spec.grading.diameter = {0.2e-3, 0.3e-3, 0.5e-3, 0.8e-3, 1.6e-3};
  spec.grading.passing = {0, 30, 30, 70, 100};  // nothing between 0.3 and 0.5 mm
  spec.r_min = spec.grading.diameter.front() / 2;
  spec.r_max = spec.grading.diameter.back() / 2;
  const std::vector<Real> r = packing_radii(spec);
  ASSERT_EQ(long(r.size()), spec.count);
  const Grading& g = spec.grading;
  const auto [at, want, sieve] = grading_check_points(g);  // sieves and interval middles, the curve's percent there
  ASSERT_EQ(at.size(), 8u);  // 5 sieves, 3 middles (none in the flat step)
  EXPECT_EQ(sieve, (std::vector<char>{1, 0, 1, 1, 0, 1, 0, 1}));
  EXPECT_EQ(want[1], 15);
  EXPECT_NEAR(at[1], std::sqrt(0.2e-3 * 0.3e-3), 1e-18);
  const std::vector<Real> got = passing_at(r, at);
  double vmean = 0;
  for (Real ri : r) vmean += double(ri) * ri * ri / double(r.size());
  for (size_t k = 0; k < at.size(); ++k) {
    const double R = got[k] / 100;
    double s2 = 0;
    for (Real ri : r) {
      const double x = double(ri) * ri * ri * ((2 * ri <= at[k] ? 1 : 0) - R);
      s2 += x * x / double(r.size());
    }
    const double se = 100 * std::sqrt(s2 / double(r.size())) / vmean;  // percentage points
    EXPECT_LE(std::abs(got[k] - want[k]), std::max(5 * se, 1e-9))
        << "at d = " << at[k] * 1e3 << " mm: " << got[k] << " % passing drawn, " << want[k] << " % asked, se " << se;
    std::printf("d = %.4g mm: %.3f %% passing drawn, %g asked (se %.3f points)\n", at[k] * 1e3, double(got[k]),
                double(want[k]), se);
  }
  long in_gap = 0;
  for (Real ri : r) in_gap += (2 * ri > 0.3e-3 && 2 * ri < 0.5e-3) ? 1 : 0;
  EXPECT_EQ(in_gap, 0);
  EXPECT_GE(*std::min_element(r.begin(), r.end()), spec.r_min);
  EXPECT_LE(r.front(), spec.r_max);
  // the sampler's ends: u = 0 is the finest sieve's sphere
  EXPECT_NEAR(GradingSampler(g).radius(0), spec.r_min, 1e-12 * spec.r_min);

  Grading known;
  known.diameter = {1e-3, 2e-3, 4e-3};
  known.passing = {0, 50, 100};
  const GradingIndices x = grading_indices(known);
  EXPECT_NEAR(x.d50, 2e-3, 1e-15);
  EXPECT_NEAR(x.d10, 1e-3 * std::pow(2.0, 0.2), 1e-15);
  EXPECT_NEAR(x.d60, 1e-3 * std::pow(2.0, 1.2), 1e-15);
  EXPECT_NEAR(x.cu, 2, 1e-12);
  EXPECT_NEAR(x.cc, std::pow(2.0, -0.2), 1e-12);
  // a sample of equal spheres is uniform: every D_x its diameter
  const GradingIndices eq = grading_indices(std::vector<Real>(10, 0.3e-3));
  EXPECT_EQ(eq.d10, 0.6e-3);
  EXPECT_EQ(eq.d60, 0.6e-3);
  EXPECT_EQ(eq.cu, 1);
  // 80 spheres of 1 mm and 20 of 2 mm: by mass 33.3 % at 1 mm, 100 % at 2 mm (tests/sieve_check.py, the figure's)
  std::vector<Real> two(80, 0.5e-3);
  two.insert(two.end(), 20, 1.0e-3);
  const GradingIndices tw = grading_indices(two);
  EXPECT_NEAR(tw.d50, 1e-3 * std::pow(2.0, 0.25), 1e-15);
  EXPECT_NEAR(tw.d60, 1e-3 * std::pow(2.0, 0.4), 1e-15);
  EXPECT_EQ(tw.d10, 1e-3);
  EXPECT_NEAR(tw.cc, std::pow(2.0, -0.4), 1e-12);
  // the drawn sample's D50 against the curve's (0.8 mm at 70 %: D50 in the 0.5-0.8 mm interval), to its scatter
  EXPECT_NEAR(grading_indices(r).d50 / grading_diameter(g, 50), 1, 0.01);
}
