#pragma once
// Basic device types: the scalar alias, a 3-vector usable on host and device, and the View aliases
// for the structure-of-arrays particle and contact storage.
#include <cstdint>

#include "compat.hpp"

namespace grainlab {

// The one place precision is chosen (issue 2: keep the scalar a single alias so float can be measured).
using Real = double;

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;
using HostSpace = Kokkos::HostSpace;
// True for the CPU backends (OpenMP, Serial), false on a GPU: selects, at compile time, the reduction
// shape that suits the backend where two shapes compute the same bits (DeterministicSum).
constexpr bool kHostBackend = Kokkos::SpaceAccessibility<ExecSpace, HostSpace>::accessible;

// A dynamic schedule over [0, n): on cores of unequal speed the threads finish together (perf/NOTES.md, attempt 20),
// and no bit depends on which thread takes an item (each writes its own outputs; maxima are exact). On one thread,
// one chunk: nothing to balance, and Kokkos 3.4 hands out every chunk under a lock (work stealing on a 16-byte range),
// ~6 % of a 300-sphere run at 1 thread (perf/NOTES.md, session 72). Kokkos' automatic chunk otherwise.
using DynamicRange = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
inline DynamicRange dynamic_range(int n) {
  const DynamicRange p(0, n);
  return ExecSpace().concurrency() == 1 && n > 0 ? p.set_chunk_size(n) : p;
}

// Structure of arrays at the field level (x, v, w, f, ... are separate Views). Within a vector field the
// component layout follows the backend (perf/NOTES.md): on GPUs LayoutLeft (x, y, z each contiguous, so
// a warp reads consecutive addresses); on CPUs LayoutRight (x, y, z of one particle in one cache line,
// which the random neighbour reads of the contact kernel need: measured 1.3x faster step on 2 cores).
using VecLayout = ExecSpace::array_layout;
using VecView = Kokkos::View<Real* [3], VecLayout, MemSpace>;
using RealView = Kokkos::View<Real*, MemSpace>;
using IntView = Kokkos::View<int*, MemSpace>;
using FlagView = Kokkos::View<std::uint8_t*, MemSpace>;

// Storage precision of the per-pair arrays (tangential and rolling history, per-pair force and torque on
// j): CMake option GRAINLAB_PAIR_FLOAT (default OFF = double). Arithmetic stays in Real: values are loaded
// into a double Vec3 and rounded only when stored, i.e. "float storage with double accumulation". The
// per-pair arrays are the largest ones (12 values per listed pair, 4.5 listed pairs per particle on the
// race scene): float cuts its memory per particle by 23 % (926 -> 709 B) and runs 1.05x faster
// (perf/NOTES.md attempt 8, perf/ab.sh); the price is a relative rounding of 6e-8 of the history per step (errors in
// perf/SPEED_VS_ERROR.md).
#ifdef GRAINLAB_PAIR_FLOAT
using PairReal = float;
#else
using PairReal = double;
#endif
using PairVecView = Kokkos::View<PairReal* [3], VecLayout, MemSpace>;

struct Vec3 {
  Real x, y, z;
  KOKKOS_FORCEINLINE_FUNCTION Vec3() : x(0), y(0), z(0) {}
  KOKKOS_FORCEINLINE_FUNCTION Vec3(Real a, Real b, Real c) : x(a), y(b), z(c) {}
  KOKKOS_FORCEINLINE_FUNCTION Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  KOKKOS_FORCEINLINE_FUNCTION Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  KOKKOS_FORCEINLINE_FUNCTION Vec3& operator*=(Real s) { x *= s; y *= s; z *= s; return *this; }
  KOKKOS_FORCEINLINE_FUNCTION Real operator[](int k) const { return k == 0 ? x : (k == 1 ? y : z); }
};
KOKKOS_FORCEINLINE_FUNCTION Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
KOKKOS_FORCEINLINE_FUNCTION Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
KOKKOS_FORCEINLINE_FUNCTION Vec3 operator-(const Vec3& a) { return Vec3(-a.x, -a.y, -a.z); }
KOKKOS_FORCEINLINE_FUNCTION Vec3 operator*(Real s, Vec3 a) { return a *= s; }
KOKKOS_FORCEINLINE_FUNCTION Vec3 operator*(Vec3 a, Real s) { return a *= s; }
KOKKOS_FORCEINLINE_FUNCTION Real dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
KOKKOS_FORCEINLINE_FUNCTION Vec3 cross(const Vec3& a, const Vec3& b) {
  return Vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
KOKKOS_FORCEINLINE_FUNCTION Real norm2(const Vec3& a) { return dot(a, a); }
KOKKOS_FORCEINLINE_FUNCTION Real norm(const Vec3& a) { return math::sqrt(dot(a, a)); }

template <class V>
KOKKOS_FORCEINLINE_FUNCTION Vec3 load(const V& v, int i) { return Vec3(v(i, 0), v(i, 1), v(i, 2)); }
template <class V>
KOKKOS_FORCEINLINE_FUNCTION void store(const V& v, int i, const Vec3& a) {
  using T = typename V::non_const_value_type;  // rounds explicitly where the View stores PairReal = float
  v(i, 0) = T(a.x);
  v(i, 1) = T(a.y);
  v(i, 2) = T(a.z);
}

KOKKOS_FORCEINLINE_FUNCTION Real sign0(Real a) { return a > 0 ? Real(1) : (a < 0 ? Real(-1) : Real(0)); }

}  // namespace grainlab
