// GoogleTest entry point: Kokkos is initialised once per process from the environment
// (OMP_NUM_THREADS, set per test by CTest), and the test refuses to run when the backend did not get
// the thread count it was asked for: a 1-thread and a 2-thread run must really differ in threads.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "kernels/compat.hpp"
#include "kernels/types.hpp"
#include "scratch.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  grainlab::compat::initialize(0);
  int rc = 0;
  const char* env = std::getenv("OMP_NUM_THREADS");
  const int got = grainlab::ExecSpace().concurrency();
  std::printf("[grainlab] backend %s, concurrency %d (OMP_NUM_THREADS=%s)\n", grainlab::ExecSpace::name(), got,
              env ? env : "unset");
#if defined(KOKKOS_ENABLE_OPENMP)
  if (env && std::is_same<grainlab::ExecSpace, Kokkos::OpenMP>::value && std::atoi(env) != got) {
    std::fprintf(stderr, "backend runs %d threads but OMP_NUM_THREADS=%s\n", got, env);
    rc = 1;
  }
#endif
  if (rc == 0) rc = RUN_ALL_TESTS();
  Kokkos::finalize();
  // The scratch files (scratch.hpp): gone after a green run, kept for inspection after a red one or on request.
  const std::filesystem::path scratch = grainlab::test::scratch_root();
  if (std::filesystem::exists(scratch)) {
    if (rc == 0 && !std::getenv("GRAINLAB_KEEP_SCRATCH")) {
      std::error_code ec;
      std::filesystem::remove_all(scratch, ec);
    } else {
      std::printf("[grainlab] scratch files kept in %s\n", scratch.c_str());
    }
  }
  return rc;
}
