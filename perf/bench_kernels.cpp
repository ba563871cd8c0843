// Kernel benchmarks (Google Benchmark). Each timed region is fenced before and after, and the rate is
// reported as particle-steps/s (items_per_second). Scenes: an FCC lattice of polydisperse spheres whose
// radii are scaled so nearest neighbours overlap by ~1 %: dense, 12 contacts per sphere, any size.
// Run: build/perf/bench_kernels [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>

#include "src/engine.hpp"
#include "src/packing.hpp"
#include "perf/scene.hpp"
#include "perf/traffic.hpp"

using namespace grainlab;

namespace {

struct Scene {
  ParticleSetup setup;
  Vec3d lo, hi;
};

Scene fcc_scene(int n_target, std::uint64_t seed) {
  const Real a = 1.6e-3;                         // cell edge: nearest neighbours at a / sqrt(2) = 1.13 mm
  const Real rn = a / std::sqrt(2.0) / 2 * 1.01;  // mean radius: 1 % overlap
  Rng rng(seed);
  Scene s;
  const int c = perf::fcc_lattice(n_target, a, [&] { return rn * (0.98 + 0.04 * rng.uniform()); }, s.setup.x, s.setup.r);
  s.lo = {0, 0, 0};
  s.hi = {c * a, c * a, c * a};
  // Morton order, as race_bench gives the race scene (perf/scene.hpp): lattice order puts a sphere's y and
  // z neighbours c and c^2 rows away in memory, which at 1M spheres measured the cache, not the kernels
  // (step 1.35x slower per particle than at 32k). (The engine itself does not reorder: generated packings
  // come in the generator's cell order, loaded samples in their saved order.)
  perf::morton_sort(s.setup.x, s.setup.r, 2 * rn);
  return s;
}

EngineParams bench_params(bool rolling) {
  EngineParams p;
  p.contact.mu = 0.5;
  p.contact.mu_r = rolling ? 0.1 : 0.0;
  p.damping = 0.7;
  p.skin = 0.1e-3;
  return p;
}

// Steps per benchmark iteration of the full-step benchmarks (see BM_Step).
constexpr int kSteps = 50;

// A full step (contacts, wall loads, gather + integration, rebuild check).
void BM_Step(benchmark::State& st) {
  const bool rolling = st.range(1) != 0;
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(rolling), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);  // warm-up: first touches, history in place
  const int rebuilds0 = eng.rebuild_count();
  // The packing starts at 1 % overlap and relaxes, so steps include neighbour rebuilds (~2 per 100 steps
  // at 32k). One benchmark iteration is kSteps steps, so that the rebuilds are sampled at their average
  // rate even at 1M, where Google Benchmark runs a single iteration: with one step per iteration that
  // iteration either held a whole rebuild (measured 1.7e6 instead of ~3.5e6 particle-steps/s) or none.
  compat::fence("grainlab::bench::before");
  for (auto _ : st) eng.run(kSteps);
  compat::fence("grainlab::bench::after");
  st.SetItemsProcessed(st.iterations() * long(kSteps) * eng.num_particles());
  st.counters["particles"] = eng.num_particles();
  st.counters["pairs"] = eng.pairs().npairs;
  st.counters["rebuilds_per_100_steps"] = 100.0 * (eng.rebuild_count() - rebuilds0) / double(st.iterations() * kSteps);
}

// BM_Step (rolling on) as a damped cyclic stage steps: Engine::step_measuring_drag, whose fused pass also sums the
// damping's drag moment (CycleLoop's loops less the drag). Its rate against BM_Step/N/1's is that feature's cost.
void BM_StepMeasuringDrag(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);
  Vec3d c{};
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (sc.lo[a] + sc.hi[a]);
  double sink = 0;
  compat::fence("grainlab::bench::before");
  for (auto _ : st)
    for (int k = 0; k < kSteps; ++k) sink += eng.step_measuring_drag(c)[2];
  compat::fence("grainlab::bench::after");
  benchmark::DoNotOptimize(sink);
  st.SetItemsProcessed(st.iterations() * long(kSteps) * eng.num_particles());
  st.counters["particles"] = eng.num_particles();
}

// The contact kernel alone (SPEC §2), rolling on and off; third argument the kernel (0 row, 1 pair lanes,
// 2 one pair per work item; kernels/dem.hpp). On the FCC scene every listed pair touches, the pair-lane kernel's best case.
void BM_ContactForces(benchmark::State& st) {
  const bool rolling = st.range(1) != 0;
  const PairKernel kernel = st.range(2) == 1 ? PairKernel::Lanes : st.range(2) == 2 ? PairKernel::Pairs : PairKernel::Row;
  if (kernel == PairKernel::Lanes && !kPairLanesBuilt) {
    st.SkipWithError("the pair-lane kernel is not built here");
    return;
  }
  Scene sc = fcc_scene(int(st.range(0)), 1);
  EngineParams p = bench_params(rolling);
  p.pair_kernel = kernel;
  Engine eng(sc.setup, p, make_box_walls(sc.lo, sc.hi), true);
  const ContactParams cp = eng.params().contact;
  const ContactFeatures feat{rolling, false};
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    compute_pair_forces(eng.particles(), eng.pairs(), eng.history(), eng.pair_forces(), cp, feat, kernel);
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
  st.counters["pairs"] = eng.pairs().npairs;
}

// Neighbour list build (binning, count, fill, transpose).
void BM_NeighborBuild(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(false), make_box_walls(sc.lo, sc.hi), true);
  CellGrid grid;
  PairList list;
  const Real skin = eng.params().skin;
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    build_neighbor_list(eng.particles().x, eng.particles().r, skin, grid, list);
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
}

// Neighbour list build on SPEC §6.1 packings (p(r) ~ r^-3.63, so most spheres are small) with r_max / r_min
// the second argument in tenths (15: 1.5), at solid fraction 0.35 (random placement; monodisperse placement jams near 0.38). The wider the
// size ratio, the more small spheres a cell sized for the largest pair holds: `candidates` (per particle)
// against `pairs` (per particle) is the search's overhead, the work a size-class grid exists to cut.
void BM_NeighborBuildPSD(benchmark::State& st) {
  PackingSpec ps;
  ps.count = int(st.range(0));
  ps.r_max = 0.6e-3;
  ps.r_min = ps.r_max * 10 / Real(st.range(1));
  ps.seed = 5;
  ps.solid_fraction = 0.35;
  const Packing pk = generate_packing(ps);
  ParticleSetup s;
  s.x = pk.x;
  s.r = pk.r;
  Engine eng(s, bench_params(false), make_box_walls(pk.lo, pk.hi), true);
  CellGrid grid;
  PairList list;
  const Real skin = eng.params().skin;
  NeighborStats ns;
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    ns = build_neighbor_list(eng.particles().x, eng.particles().r, skin, grid, list);
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
  st.counters["candidates"] = double(ns.examined) / eng.num_particles();
  st.counters["pairs"] = double(ns.npairs) / eng.num_particles();
}

// The inner-list filter (EngineParams::inner_skin, perf/NOTES.md attempt 18): one pass over the Verlet
// list's rows plus the inner list's transposed index, no binning. What a filter costs against a full
// build (BM_NeighborBuild) is what the two-level list saves at each filter.
void BM_InnerFilter(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(false), make_box_walls(sc.lo, sc.hi), true);
  CellGrid grid;
  PairList outer, inner;
  const Real skin = eng.params().skin;
  build_neighbor_list(eng.particles().x, eng.particles().r, skin, grid, outer, false);
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    filter_pair_list(eng.particles().x, eng.particles().r, 0.1 * skin, outer, inner);
    compat::fence("grainlab::bench::kernel");
  }
  st.counters["verlet_pairs"] = outer.npairs;
  st.counters["inner_pairs"] = inner.npairs;
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
}

// The SPEC §7 analysis (three passes over the pairs plus rattlers and wall moments). Its cost per call,
// divided by the output interval (1000 steps by default), is its share of the time-step loop.
void BM_Analysis(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);
  eng.evaluate();
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    benchmark::DoNotOptimize(eng.analyze());
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
  st.counters["pairs"] = eng.pairs().npairs;
}

// The solids in the interior box (the wall box inset by two mean diameters: series e_inner, once an output row):
// Engine::solid_volume_in, exact, with the octant sums for the spheres on the box's edges and corners.
void BM_SolidInBox(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  double rsum = 0;
  for (Real r : sc.setup.r) rsum += r;
  const double inset = 4 * rsum / double(sc.setup.r.size());  // two mean diameters
  Vec3d lo = sc.lo, hi = sc.hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] += inset;
    hi[a] -= inset;
  }
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    benchmark::DoNotOptimize(eng.solid_volume_in(lo, hi));
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
}

// The integration alone (gather of the pair outputs, walls, damping, leapfrog).
void BM_Integrate(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);
  eng.evaluate();
  const Particles P = eng.particles();
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    // dt = 0: the state does not move, so every iteration does the same work
    benchmark::DoNotOptimize(gather_and_integrate(P, eng.pairs(), eng.history().flags, eng.pair_forces(), eng.walls(),
                                                  eng.params().E_wall, 0.7, 0.0));
    compat::fence("grainlab::bench::kernel");
  }
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
}

// Sphere-wall contacts: the per-wall deterministic load sums that feed the servo.
void BM_WallLoads(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  DeterministicSum red;
  compat::fence("grainlab::bench::before");
  for (auto _ : st) benchmark::DoNotOptimize(reduce_wall_loads(eng.particles(), eng.walls(), eng.params().E_wall, red));
  compat::fence("grainlab::bench::after");
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
}

// Memory bandwidth of this machine: a device copy of 2 x 128 MB (read + write counted).
void BM_Copy(benchmark::State& st) {
  const long n = 16L << 20;
  RealView a(Kokkos::view_alloc("grainlab::bench::a", Kokkos::WithoutInitializing), n);
  RealView b("grainlab::bench::b", n);
  Kokkos::deep_copy(a, 1.0);
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    Kokkos::parallel_for(
        "grainlab::bench::copy", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long i) { b(i) = a(i); });
    compat::fence("grainlab::bench::kernel");
  }
  st.SetBytesProcessed(st.iterations() * 2 * n * long(sizeof(Real)));
}

// The full step with its traffic estimate and memory per particle (device bytes of the engine's arrays).
void BM_StepTraffic(benchmark::State& st) {
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(true), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);
  const double bytes = perf::step_bytes(eng);
  compat::fence("grainlab::bench::before");
  for (auto _ : st) eng.run(kSteps);  // kSteps per iteration: rebuilds at their average rate (BM_Step)
  compat::fence("grainlab::bench::after");
  st.SetItemsProcessed(st.iterations() * long(kSteps) * eng.num_particles());
  st.SetBytesProcessed(int64_t(st.iterations() * kSteps * bytes));
  st.counters["bytes_per_particle_step"] = bytes / eng.num_particles();
  st.counters["pairs_per_particle"] = double(eng.pairs().npairs) / eng.num_particles();
}

}  // namespace

BENCHMARK(BM_Copy)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StepTraffic)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_SolidInBox)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_Integrate)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_WallLoads)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_Analysis)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_Step)->ArgsProduct({{4000, 32000, 256000, 1024000}, {0, 1}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_StepMeasuringDrag)->Arg(4000)->Arg(32000)->Arg(256000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_ContactForces)->ArgsProduct({{4000, 32000, 256000, 1024000}, {0, 1}, {0, 1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_NeighborBuild)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_NeighborBuildPSD)->ArgsProduct({{32000, 256000}, {15, 30, 100}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_InnerFilter)->Arg(4000)->Arg(32000)->Arg(256000)->Arg(1024000)->Unit(benchmark::kMicrosecond)->UseRealTime();

int main(int argc, char** argv) {
  compat::initialize(0);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  Kokkos::finalize();
  return 0;
}
