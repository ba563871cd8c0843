#pragma once
// Memory-traffic model of one step and the machine's copy bandwidth, shared by bench_kernels and race_bench
// so that "bytes per particle-step against the bandwidth floor" means the same in both reports.
#include <algorithm>
#include <chrono>
#include <vector>

#include "src/engine.hpp"

namespace grainlab::perf {

// Compulsory memory traffic of one step, from the step's own arrays (each byte counted once, as if every
// neighbour read hit cache), for the engine's contact kernel (kernels/dem.hpp PairKernel):
// - both: particles x, v, w read + written, x_ref, r, m, I read, f, t written, the two offsets arrays;
// - row kernel: the row sums written + read; per listed pair j's index, the transposed index and the flag
//   read + written; per touching pair the history (ft, mr) read + written and the pair output (f, tj)
//   written + read (separated pairs are skipped);
// - pair-lane kernel: every listed pair is computed: i's and j's index, the transposed index, the flag
//   written, the history read + written, f, tj, ti written, f read twice (row and transposed sums), tj and
//   ti read once.
// Divided by the step time it is the bandwidth the step would need if it were memory bound; set against the
// measured copy bandwidth it says how far from the memory floor the step runs.
inline double step_bytes(Engine& eng) {
  const Diagnostics d = eng.diagnostics();
  const double pv = 3 * double(sizeof(PairReal));  // one per-pair vector: 24 B in double, 12 B in float
  const double particles = eng.num_particles(), pairs = eng.pairs().npairs;
  const double shared = 6 * 24 + 24 + 3 * 8 + 2 * 24 + 2 * 4;
  if (per_pair_shares(eng.params().pair_kernel))
    return shared * particles + (4 + 4 + 4 + 1 + 4 * pv + 7 * pv) * pairs;
  return (shared + 4 * 24) * particles + (4 + 4 + 2) * pairs + (4 * pv + 4 * pv) * d.contacts;
}

inline const char* kernel_name(PairKernel k) {
  return k == PairKernel::Row ? "row" : k == PairKernel::Lanes ? "lanes" : "pairs";
}

struct CopyBandwidth {
  double kernel;     // bytes/s (read + write) of a one-element-per-thread copy kernel, the step's access shape
  double deep_copy;  // bytes/s of Kokkos::deep_copy between two device views (cudaMemcpy on a GPU)
};

// Medians of `reps` timed copies of n doubles each way, fenced before and after each; one warm-up copy each.
inline CopyBandwidth copy_bandwidth(long n, int reps) {
  RealView a(Kokkos::view_alloc("grainlab::bench::copy_a", Kokkos::WithoutInitializing), n);
  RealView b(Kokkos::view_alloc("grainlab::bench::copy_b", Kokkos::WithoutInitializing), n);
  Kokkos::deep_copy(a, 1.0);
  auto median_rate = [&](auto&& copy) {
    std::vector<double> t;
    copy();
    compat::fence("grainlab::bench::copy_warm");
    for (int r = 0; r < reps; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      copy();
      compat::fence("grainlab::bench::copy");
      t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return 2.0 * double(n) * sizeof(Real) / t[t.size() / 2];
  };
  CopyBandwidth bw;
  bw.kernel = median_rate([&] {
    Kokkos::parallel_for(
        "grainlab::bench::copy", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(long i) { b(i) = a(i); });
  });
  bw.deep_copy = median_rate([&] { Kokkos::deep_copy(b, a); });
  return bw;
}

}  // namespace grainlab::perf
