#pragma once
// Transparent huge pages for the large host arrays (perf/NOTES.md attempt 39). The pair-lane kernel reads its j
// particles, and the integration its transposed pairs, scattered over arrays of up to hundreds of MB; with 4 KiB
// pages most of those reads also miss the TLB (its ~3k entries map ~12 MiB). Linux's default THP mode on this
// project's machines is "madvise": only ranges marked MADV_HUGEPAGE get 2 MiB pages, and only where they are
// touched after the mark. So the arrays are allocated without initialization, marked, then filled. Elsewhere
// (THP off or "never", other systems, device memory) this does nothing, and nothing depends on it but speed.
#include <cstddef>
#include <cstdint>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "types.hpp"

namespace grainlab {

// Marks the 2 MiB-aligned part of [p, p + bytes) for huge pages (a hint: its result is not checked).
inline void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
  const std::uintptr_t b = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (b + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (b + bytes) & ~(kHuge - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

// A View of n entries, huge-page backed where host memory and THP allow, uninitialized (zero = false) or zeroed
// after the mark (zero = true: a plain View's contents).
template <class V>
V huge_page_view(const std::string& label, std::size_t n, bool zero) {
  V v(Kokkos::view_alloc(label, Kokkos::WithoutInitializing), n);
  if constexpr (kHostBackend) advise_huge_pages(v.data(), v.span() * sizeof(typename V::value_type));
  if (zero) Kokkos::deep_copy(v, typename V::value_type(0));
  return v;
}

// Grow-only reallocation of a per-pair or per-list array (the pair list, the history, the pair outputs): at least
// n entries, 25 % slack, so a steady pair count allocates nothing in the step loop. The contents are not kept.
template <class V>
void grow_view(V& v, const char* label, long n) {
  if (long(v.extent(0)) < n) {
    const long cap = n > long(1.25 * double(n)) + 16 ? n : long(1.25 * double(n)) + 16;
    v = huge_page_view<V>(label, std::size_t(cap), false);
  }
}

}  // namespace grainlab
