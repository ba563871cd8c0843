#pragma once
// The one Kokkos version shim (3.4 .. 4.x). Everything version-dependent lives here; the rest of
// grainlab calls grainlab::math::* and grainlab::compat::*. Facts: ../shared/DEPENDENCIES.md.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>
#if defined(KOKKOS_ENABLE_OPENMP)
#include <omp.h>
#endif

namespace grainlab {
namespace math {
// Math functions moved from Kokkos::Experimental to Kokkos:: in 3.7.
#if KOKKOS_VERSION >= 30700
using Kokkos::atan2;
using Kokkos::fabs;
using Kokkos::isfinite;
using Kokkos::sqrt;
#else
using Kokkos::Experimental::atan2;
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

// Kokkos's OpenMP backend keeps its threads' data in a fixed pool of 512 (OpenMPExec::MAX_THREAD_COUNT in 3.x,
// OpenMPTraits::MAX_THREAD_COUNT in 4.x) and does not check the count against it: more threads write past the pool
// (Kokkos 3.4, measured: 700 threads segfault in HostThreadTeamData::disband_pool). grainlab refuses more.
constexpr int kMaxHostThreads = 512;
// The host threads initialize(nthreads) starts: nthreads, or the OpenMP default (OMP_NUM_THREADS) where <= 0.
inline int host_threads(int nthreads) {
  if (nthreads > 0) return nthreads;
#if defined(KOKKOS_ENABLE_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}
// The OpenMP places, each a list of CPU ids, where OpenMP binds its threads (OMP_PROC_BIND true, spread, close or
// primary, or OMP_PLACES set); empty where it does not bind, or on a backend without OpenMP. Where it binds, libgomp
// pins the initial thread to the first place as the library loads, before main: from then on the process's affinity
// (sched_getaffinity) is that one place, and only the places still say which CPUs the process was given (libgomp
// builds them from the affinity it found, and drops an OMP_PLACES entry outside it).
inline std::vector<std::vector<int>> openmp_places() {
  std::vector<std::vector<int>> places;
#if defined(KOKKOS_ENABLE_OPENMP)
  if (omp_get_proc_bind() == omp_proc_bind_false) return places;
  for (int p = 0; p < omp_get_num_places(); ++p) {
    std::vector<int> ids(size_t(std::max(0, omp_get_place_num_procs(p))));
    if (!ids.empty()) omp_get_place_proc_ids(p, ids.data());
    places.push_back(std::move(ids));
  }
#endif
  return places;
}
// The most threads OpenMP gives a parallel region, whatever is asked: 1 where OMP_MAX_ACTIVE_LEVELS=0 makes every
// region serial, else OMP_THREAD_LIMIT (INT_MAX unset); `why` names the variable. Kokkos's OpenMP backend needs every thread
// it starts in each region: asked for more, Kokkos 3.4 aborted in its initialisation ("organize_pool ERROR pool
// already exists"). Without OpenMP, no cap.
inline int openmp_thread_cap(std::string* why = nullptr) {
#if defined(KOKKOS_ENABLE_OPENMP)
  if (omp_get_max_active_levels() < 1) {
    if (why) *why = "OMP_MAX_ACTIVE_LEVELS=0";
    return 1;
  }
  const int limit = std::max(1, omp_get_thread_limit());
  if (why) *why = "OMP_THREAD_LIMIT=" + std::to_string(limit);
  return limit;
#else
  if (why) *why = "";
  return std::numeric_limits<int>::max();
#endif
}
// Places in OMP_PLACES's notation: {0,64},{1,65}.
inline std::string places_text(const std::vector<std::vector<int>>& places) {
  std::string t;
  for (const auto& place : places) {
    t += t.empty() ? "{" : ",{";
    for (size_t k = 0; k < place.size(); ++k) t += (k ? "," : "") + std::to_string(place[k]);
    t += "}";
  }
  return t;
}
// Thread count through the API, never through stale command-line flags (--kokkos-threads in 3.x vs
// --kokkos-num-threads in 4.x). nthreads <= 0 keeps the backend default (OMP_NUM_THREADS).
inline void initialize(int nthreads) {
  if (host_threads(nthreads) > kMaxHostThreads)
    throw std::runtime_error(std::to_string(host_threads(nthreads)) + " threads (" +
                             (nthreads > 0 ? "asked for" : "OMP_NUM_THREADS") + "): Kokkos's OpenMP backend runs at most " +
                             std::to_string(kMaxHostThreads));
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
