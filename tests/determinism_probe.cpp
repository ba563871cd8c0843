// Writes the final state of the determinism scene as raw bytes; CTest runs it with 1 and 2 threads and
// compares the files (bitwise: the dynamics use no thread-count-dependent reduction).
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "helpers.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: determinism_probe OUTFILE\n");
    return 2;
  }
  grainlab::compat::initialize(0);
  int rc = 0;
  const char* env = std::getenv("OMP_NUM_THREADS");
  // On a host backend the two runs must use the thread counts CTest asks for (a stale backend flag would
  // make the 1- and 2-thread runs identical and the comparison vacuous). On a GPU the thread count does not
  // apply: the two runs then test run-to-run determinism of the device backend.
  constexpr bool host_backend = Kokkos::SpaceAccessibility<grainlab::ExecSpace, Kokkos::HostSpace>::accessible;
  if (!host_backend)
    std::printf("backend %s: OMP_NUM_THREADS does not apply; comparing two runs on the device\n",
                grainlab::ExecSpace::name());
  else if (env && std::atoi(env) != grainlab::ExecSpace().concurrency()) {
    std::fprintf(stderr, "backend runs %d threads, OMP_NUM_THREADS=%s\n", grainlab::ExecSpace().concurrency(), env);
    rc = 1;
  }
  if (rc == 0) {
    const grainlab::test::ShearRun r = grainlab::test::sheared_scene(false);
    std::printf("threads %d: %d rebuilds, %d contacts, %d sliding\n", grainlab::ExecSpace().concurrency(), r.rebuilds,
                r.contacts, r.sliding);
    if (r.rebuilds < 3 || r.contacts < 400 || r.sliding < 1) {
      std::fprintf(stderr, "determinism scene is trivial\n");
      rc = 1;
    }
    std::ofstream out(argv[1], std::ios::binary);
    out.write(reinterpret_cast<const char*>(r.state.data()), std::streamsize(r.state.size() * sizeof(r.state[0])));
    if (!out) rc = 1;
  }
  Kokkos::finalize();
  return rc;
}
