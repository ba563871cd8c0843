#pragma once
// The one Kokkos version shim (3.4 .. 4.x). Everything version-dependent lives here; the rest of
// grainlab calls grainlab::math::* and grainlab::compat::*. Facts: ../shared/DEPENDENCIES.md.
#include <Kokkos_Core.hpp>

namespace grainlab {
namespace math {
// Math functions moved from Kokkos::Experimental to Kokkos:: in 3.7.
#if KOKKOS_VERSION >= 30700
using Kokkos::fabs;
using Kokkos::isfinite;
using Kokkos::sqrt;
#else
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::isfinite;
using Kokkos::Experimental::sqrt;
#endif
}  // namespace math

namespace compat {
// Labelled fences exist only from 3.6 on.
inline void fence(const char* label) {
#if KOKKOS_VERSION >= 30600
  Kokkos::fence(label);
#else
  (void)label;
  Kokkos::fence();
#endif
}

// Thread count through the API, never through stale command-line flags (--kokkos-threads in 3.x vs
// --kokkos-num-threads in 4.x). nthreads <= 0 keeps the backend default (OMP_NUM_THREADS).
inline void initialize(int nthreads) {
#if KOKKOS_VERSION >= 30700
  Kokkos::InitializationSettings s;
  if (nthreads > 0) s.set_num_threads(nthreads);
  s.set_disable_warnings(true);
  Kokkos::initialize(s);
#else
  Kokkos::InitArguments a;
  a.num_threads = nthreads > 0 ? nthreads : -1;
  a.disable_warnings = true;
  Kokkos::initialize(a);
#endif
}
}  // namespace compat
}  // namespace grainlab
