// Kernel benchmarks (Google Benchmark). Each timed region is fenced before and after, and the rate is
// reported as particle-steps/s (items_per_second). Scenes: an FCC lattice of polydisperse spheres whose
// radii are scaled so nearest neighbours overlap by ~1 %: dense, 12 contacts per sphere, any size.
// Run: build/perf/bench_kernels [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>

#include "src/engine.hpp"
#include "src/packing.hpp"

using namespace grainlab;

namespace {

struct Scene {
  ParticleSetup setup;
  Vec3d lo, hi;
};

Scene fcc_scene(int n_target, std::uint64_t seed) {
  const int c = std::max(1, int(std::cbrt(n_target / 4.0) + 0.5));
  const Real a = 1.6e-3;                         // cell edge: nearest neighbours at a / sqrt(2) = 1.13 mm
  const Real rn = a / std::sqrt(2.0) / 2 * 1.01;  // mean radius: 1 % overlap
  Rng rng(seed);
  Scene s;
  const Real basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int z = 0; z < c; ++z)
    for (int y = 0; y < c; ++y)
      for (int x = 0; x < c; ++x)
        for (auto& b : basis) {
          s.setup.x.push_back({(x + b[0] + 0.25) * a, (y + b[1] + 0.25) * a, (z + b[2] + 0.25) * a});
          s.setup.r.push_back(rn * (0.98 + 0.04 * rng.uniform()));
        }
  s.lo = {0, 0, 0};
  s.hi = {c * a, c * a, c * a};
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

// A full step (contacts, wall loads, gather + integration, rebuild check).
void BM_Step(benchmark::State& st) {
  const bool rolling = st.range(1) != 0;
  Scene sc = fcc_scene(int(st.range(0)), 1);
  Engine eng(sc.setup, bench_params(rolling), make_box_walls(sc.lo, sc.hi), true);
  eng.run(20);  // warm-up: first touches, history in place
  compat::fence("grainlab::bench::before");
  for (auto _ : st) eng.step();
  compat::fence("grainlab::bench::after");
  st.SetItemsProcessed(st.iterations() * eng.num_particles());
  st.counters["particles"] = eng.num_particles();
  st.counters["pairs"] = eng.pairs().npairs;
}

// The contact kernel alone (SPEC §2), rolling on and off.
void BM_ContactForces(benchmark::State& st) {
  const bool rolling = st.range(1) != 0;
  Scene sc = fcc_scene(int(st.range(0)), 1);
  EngineParams p = bench_params(rolling);
  Engine eng(sc.setup, p, make_box_walls(sc.lo, sc.hi), true);
  const ContactParams cp = eng.params().contact;
  const ContactFeatures feat{rolling, false};
  compat::fence("grainlab::bench::before");
  for (auto _ : st) {
    compute_pair_forces(eng.particles(), eng.pairs(), eng.history(), eng.pair_forces(), cp, feat);
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
    build_neighbor_list(eng.particles().x, eng.particles().r, skin, 2 * eng.r_max() + skin, grid, list);
    compat::fence("grainlab::bench::kernel");
  }
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

}  // namespace

BENCHMARK(BM_Analysis)->Arg(4000)->Arg(32000)->Arg(256000)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_Step)->ArgsProduct({{4000, 32000, 256000}, {0, 1}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_ContactForces)->ArgsProduct({{4000, 32000, 256000}, {0, 1}})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_NeighborBuild)->Arg(4000)->Arg(32000)->Arg(256000)->Unit(benchmark::kMicrosecond)->UseRealTime();

int main(int argc, char** argv) {
  compat::initialize(0);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  Kokkos::finalize();
  return 0;
}
