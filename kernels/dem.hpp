#pragma once
// The per-step DEM kernels (SPEC §2-4) over the structure-of-arrays state. Host code in src/ decides
// when to call them; nothing here allocates except the grow-only history buffers at rebuilds.
#include <stdexcept>
#include <string>
#include <utility>

#include "contact_law.hpp"
#include "neighbor.hpp"

namespace grainlab {

struct Particles {
  VecView x, v, w;  // position, half-step velocity, half-step angular velocity
  VecView f, t;     // total force and torque of the last evaluation (undamped: unbalanced force)
  VecView x_ref;    // positions at the last neighbour build (rebuild criterion)
  RealView r, m, inertia;
  IntView id;
  int n = 0;
};

// Per-pair state aligned with a PairList (index p).
struct PairHistory {
  PairVecView ft, mr;
  FlagView flags;
};
// Output of the contact kernel. It walks row i of the half list with particle i in registers, so i's
// share of every pair is summed there (row_f, row_t: per particle) and only j's share is stored per pair
// (f, tj), for the gather through the transposed index. Entries of non-touching pairs are stale: readers
// check the pair's kTouching flag. A separated pair writes nothing but (once) its flag and history,
// and most listed pairs in a dense packing with a 0.1 mm skin are separated (40 % on the race scene).
// (perf/NOTES.md attempt 5: writing j's share straight into transposed order, for a contiguous gather,
// measured 4 % slower: scattered stores cost more than the gather's scattered loads.)
struct PairForces {
  PairVecView f;         // per pair: force on j (force on i is -f); valid where flags has kTouching
  PairVecView tj;        // per pair: torque on j
  VecView row_f, row_t;  // per particle: sum of i's shares over its row (row kernel)
  PairVecView ti;        // per pair: torque on i (PairKernel::Lanes and Pairs)
};

// Three contact kernels compute the same bits (perf/NOTES.md attempts 20 and 30). Row: one work item per row i
// of the half list, i's share summed in registers (CPUs without wide vectors). Lanes: C consecutive pairs of
// the list side by side in vector registers, i's share stored per pair (PairForces::ti) and summed by the
// integration in the row kernel's order. Lanes is built where CMake's GRAINLAB_PAIR_LANES is on (the
// default) for a host backend whose target has AVX2 or AVX-512: 2-wide SSE2 vectors do not pay for the
// gathers (attempt 11 measured 0.88x at that width). Pairs: one work item per pair with Lanes' outputs, for
// GPUs: a row's few pairs one after another in one thread leave most of a GPU idle at small N and its pair
// loads uncoalesced (attempt 30); built on every backend.
enum class PairKernel { Row, Lanes, Pairs };
// Where i's share of a pair goes: into the pair's own slots (PairForces::ti, read back by the integration)
// or, for Row, into the per-particle row sums.
constexpr bool per_pair_shares(PairKernel k) { return k != PairKernel::Row; }
#if GRAINLAB_PAIR_LANES && (defined(__AVX2__) || defined(__AVX512F__))
constexpr bool kPairLanesBuilt = kHostBackend;
#else
constexpr bool kPairLanesBuilt = false;
#endif
constexpr PairKernel kDefaultPairKernel =
    kPairLanesBuilt ? PairKernel::Lanes : kHostBackend ? PairKernel::Row : PairKernel::Pairs;
// 16 since the staged loads (perf/NOTES.md attempt 33). perf/ab2.sh against the gathering kernel at 8 lanes: staged
// 4 lanes 0.82x, 8 lanes 1.11x, 16 lanes 1.23x; 32 lanes 0.985x against 16 (spills). With the in-loop gathers of
// attempt 20, 16 lanes had measured the same as 8 (1.001x): the gathers bound the loop.
constexpr int kPairLanesWidth = 16;

constexpr int kMaxWalls = 8;
struct WallSet {
  int count = 0;
  Wall w[kMaxWalls];
};

// Sums of one step's sphere-wall contacts, per wall (deterministic, see DeterministicSum).
struct WallLoads {
  Real force[kMaxWalls] = {};      // normal force received, along the wall's outward direction [N]
  Real stiffness[kMaxWalls] = {};  // sum of k_w over touching spheres                         [N/m]
  int touching[kMaxWalls] = {};
};

// Fixed-chunk reduction: the chunk boundaries depend only on n, each chunk is summed sequentially and
// the chunk partials are summed in chunk order, so the result is bitwise the same on any thread count
// (a plain parallel_reduce would not be, and these sums feed the wall servo, i.e. the dynamics).
class DeterministicSum {
 public:
  static constexpr int kChunk = 256;
  static constexpr int kMaxValues = 64;  // wall loads use 3 per wall; the analysis up to 64
  // f(i, acc) adds particle/pair i's contributions to acc[0..nv).
  template <class F>
  void run(const char* label, int n, int nv, const F& f, Real* out) {
    run_with_max(label, n, nv, KOKKOS_LAMBDA(int i, Real* acc, Real&) { f(i, acc); }, out);
  }

  // run()'s sums, bitwise, for an f that adds at most one term to each value per item (the wall loads).
  // run() gives each chunk to one thread: on a GPU that is a serial loop of 256 global-memory latencies
  // per step at any N (with the serial chunk sum below, ~200 us per step measured on an H100; perf/NOTES.md
  // attempt 19). Here a team evaluates a chunk's items in parallel, each into its own zeroed accumulator,
  // and one thread per value adds the items' values in item order. Item i's accumulator then holds
  // 0 + t = t for its one term t (a -0 becomes +0), and 0 for no term; the running sum s is never -0, so
  // s + 0 = s and s + (+0) = s + (-0): the additions are run()'s. Host backends keep run() (one pass, no
  // scratch); Team = true takes the team path on any backend (tests compare the two on the host).
  template <bool Team = !kHostBackend, class F>
  void run_one_term(const char* label, int n, int nv, const F& f, Real* out) {
    if constexpr (!Team) {
      run(label, n, nv, f, out);
    } else {
      run_one_term_on_device(label, n, nv, f);
      fetch(nv, out);
    }
  }

  // run_one_term()'s team path without the copy to the host: the sums stay in device_slot(0 .. nv), for a
  // later fetch() that brings them over with whatever else the caller left beside them (the GPU's step puts
  // the displacement max there, so one copy, one synchronisation per step; perf/NOTES.md attempt 32).
  template <class F>
  void run_one_term_on_device(const char* label, int n, int nv, const F& f) {
    // kPass x nv values of scratch per team must fit a GPU block's 48 KB with room for Kokkos' own.
    if (nv > kOneTermMaxValues)
      throw std::logic_error("DeterministicSum::run_one_term: at most " + std::to_string(kOneTermMaxValues) + " values (" + std::to_string(nv) + " asked)");
    const int nchunks = prepare(n);
    auto partial = partial_;
    using Member = Kokkos::TeamPolicy<ExecSpace>::member_type;
    const std::size_t bytes = ScratchMatrix::shmem_size(kPass, nv) + ScratchVector::shmem_size(nv);
    Kokkos::parallel_for(
        label, Kokkos::TeamPolicy<ExecSpace>(nchunks, team_size()).set_scratch_size(0, Kokkos::PerTeam(bytes)),
        KOKKOS_LAMBDA(const Member& t) {
          ScratchMatrix item(t.team_scratch(0), kPass, nv);  // item(q, k): value k of item q of the pass
          ScratchVector sum(t.team_scratch(0), nv);          // the chunk's running sums
          const int c = t.league_rank();
          const int end = (c + 1) * kChunk < n ? (c + 1) * kChunk : n;
          Kokkos::parallel_for(Kokkos::TeamThreadRange(t, nv), [&](int k) { sum(k) = 0; });
          for (int h = c * kChunk; h < end; h += kPass) {
            const int m = end - h < kPass ? end - h : kPass;
            Kokkos::parallel_for(Kokkos::TeamThreadRange(t, m), [&](int q) {
              Real acc[kMaxValues];
              for (int k = 0; k < nv; ++k) acc[k] = 0;
              f(h + q, acc);
              for (int k = 0; k < nv; ++k) item(q, k) = acc[k];
            });
            t.team_barrier();
            Kokkos::parallel_for(Kokkos::TeamThreadRange(t, nv), [&](int k) {
              Real s = sum(k);
              for (int q = 0; q < m; ++q) s += item(q, k);  // item order: run()'s order
              sum(k) = s;
            });
            t.team_barrier();
          }
          Kokkos::parallel_for(Kokkos::TeamThreadRange(t, nv), [&](int k) { partial(c, k) = sum(k); });
        });
    sum_chunks<true>(nchunks, nv);
  }

  // Value k of the last reduction, in device memory (k < kMaxValues; a caller may write past the sums).
  Real* device_slot(int k) { return result_.data() + k; }
  // The first nv values of the device result to out[0 .. nv), in one copy.
  void fetch(int nv, Real* out) {
    Kokkos::deep_copy(Kokkos::subview(host_, std::make_pair(0, nv)), Kokkos::subview(result_, std::make_pair(0, nv)));
    for (int k = 0; k < nv; ++k) out[k] = host_(k);
  }

  // run(), from a kernel that does more per item than adding to acc: f(i, acc, mx) may also raise mx, and
  // the largest mx over all items is returned (an exact max, so in any order). Each chunk is one work item,
  // summed in item order; the schedule is dynamic, which no bit depends on. The host integration uses it to
  // sum the wall loads in its own pass (Engine::step).
  template <class F>
  Real run_with_max(const char* label, int n, int nv, const F& f, Real* out) {
    const int nchunks = prepare(n);
    auto partial = partial_;
    Real mx = 0;
    Kokkos::parallel_reduce(
        label, dynamic_range(nchunks),
        KOKKOS_LAMBDA(int c, Real& m) {
          Real acc[kMaxValues];
          for (int k = 0; k < nv; ++k) acc[k] = 0;
          const int end = (c + 1) * kChunk < n ? (c + 1) * kChunk : n;
          for (int i = c * kChunk; i < end; ++i) f(i, acc, m);
          for (int k = 0; k < nv; ++k) partial(c, k) = acc[k];
        },
        Kokkos::Max<Real>(mx));
    finish(nchunks, nv, out);
    return n > 0 ? mx : Real(0);
  }
  // Building blocks of run() and run_one_term(). Public only because nvcc refuses device lambdas in private
  // member functions.
  static constexpr int kPass = 128;  // items per team pass: 128 x 24 values x 8 B = 24 KB of scratch
  static constexpr int kOneTermMaxValues = 3 * kMaxWalls;  // run_one_term: the wall loads, 3 per wall
  using ScratchMatrix = Kokkos::View<Real**, Kokkos::LayoutRight, ExecSpace::scratch_memory_space,
                                     Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  using ScratchVector = Kokkos::View<Real*, ExecSpace::scratch_memory_space, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  static int team_size() { return kHostBackend ? 1 : kPass; }

  int prepare(int n) {
    const int nchunks = (n + kChunk - 1) / kChunk;
    if (int(partial_.extent(0)) < nchunks)
      partial_ = Kokkos::View<Real* [kMaxValues], MemSpace>("grainlab::reduce::partial", nchunks + 16);
    if (result_.data() == nullptr) {
      result_ = Kokkos::View<Real[kMaxValues], MemSpace>("grainlab::reduce::result");
      host_ = Kokkos::create_mirror_view(result_);
    }
    return nchunks;
  }

  // The chunk partials summed in chunk order, value by value. On a host backend one thread per value walks
  // the chunks. On a GPU that walk is a serial chain of global loads (43 000 chunks at 11M particles), so a
  // team per value first stages a block of partials in scratch with parallel loads and one thread then adds
  // them in chunk order: the same additions. Team = true takes the team path on any backend (the tests).
  template <bool Team = !kHostBackend>
  void finish(int nchunks, int nv, Real* out) {
    sum_chunks<Team>(nchunks, nv);
    fetch(nv, out);
  }
  template <bool Team>
  void sum_chunks(int nchunks, int nv) {
    if constexpr (!Team && kHostBackend) {
      // On the calling thread, chunk by chunk (the partials' rows in memory order): the nv sums (18 for six walls)
      // of 40 chunks at 10^4 spheres, 3 900 at 10^6, where a parallel region for them cost ~7 us of fork, join and
      // barrier at 2 threads, one of the four the lab's step opened (perf/NOTES.md, session 72). Each value gets the
      // same additions in the same (chunk) order as ChunkSums', so the same bits.
      Real s[kMaxValues] = {};
      for (int c = 0; c < nchunks; ++c)
        for (int k = 0; k < nv; ++k) s[k] += partial_(c, k);
      for (int k = 0; k < nv; ++k) result_(k) = s[k];
    } else if constexpr (!Team) {
      Kokkos::parallel_for("grainlab::reduce::chunks", Kokkos::RangePolicy<ExecSpace>(0, nv),
                           ChunkSums{partial_, result_, nchunks});
    } else {
      Kokkos::parallel_for(
          "grainlab::reduce::chunks",
          Kokkos::TeamPolicy<ExecSpace>(nv, team_size())
              .set_scratch_size(0, Kokkos::PerTeam(ScratchVector::shmem_size(ChunkSums::kBlock))),
          ChunkSums{partial_, result_, nchunks});
    }
  }

  // finish()'s kernels: value k summed over the chunks in chunk order. A named functor, not a lambda:
  // finish() is the same instantiation in every translation unit that reduces, and with a lambda there
  // nvcc's extended-lambda wrapper called a null function pointer on an H100 (race_bench, session 12, when
  // attempt 31 changed finish()'s signature), presumably where the linker kept another unit's copy.
  struct ChunkSums {
    static constexpr int kBlock = 1024;
    Kokkos::View<Real* [kMaxValues], MemSpace> partial;
    Kokkos::View<Real[kMaxValues], MemSpace> result;
    int nchunks;
    // One thread per value walks the chunks (host backends).
    KOKKOS_INLINE_FUNCTION void operator()(int k) const {
      Real s = 0;
      for (int c = 0; c < nchunks; ++c) s += partial(c, k);
      result(k) = s;
    }
    // A team per value stages blocks of partials in scratch with parallel loads; one thread adds them.
    KOKKOS_INLINE_FUNCTION void operator()(const Kokkos::TeamPolicy<ExecSpace>::member_type& t) const {
      const int k = t.league_rank();
      ScratchVector block(t.team_scratch(0), kBlock);
      Real s = 0;  // lives in the thread that runs the single() below: the same thread every block
      for (int c0 = 0; c0 < nchunks; c0 += kBlock) {
        const int m = nchunks - c0 < kBlock ? nchunks - c0 : kBlock;
        Kokkos::parallel_for(Kokkos::TeamThreadRange(t, m), [&](int q) { block(q) = partial(c0 + q, k); });
        t.team_barrier();
        Kokkos::single(Kokkos::PerTeam(t), [&]() {
          for (int q = 0; q < m; ++q) s += block(q);
        });
        t.team_barrier();
      }
      Kokkos::single(Kokkos::PerTeam(t), [&]() { result(k) = s; });
    }
  };

 private:
  Kokkos::View<Real* [kMaxValues], MemSpace> partial_;
  Kokkos::View<Real[kMaxValues], MemSpace> result_;
  typename Kokkos::View<Real[kMaxValues], MemSpace>::HostMirror host_;
};

// Touching contacts of particle i (its row and its transposed row), counting up to `limit` (callers only
// need to know 0, 1 or more).
struct TouchCounter {
  IntView off, toff, tpairs;
  FlagView flags;
  KOKKOS_INLINE_FUNCTION int operator()(int i, int limit) const {
    int c = 0;
    for (int p = off(i); p < off(i + 1) && c < limit; ++p) c += (flags(p) & kTouching) ? 1 : 0;
    for (int k = toff(i); k < toff(i + 1) && c < limit; ++k) c += (flags(tpairs(k)) & kTouching) ? 1 : 0;
    return c;
  }
};

struct ContactFeatures {
  bool rolling = false;  // mu_r > 0
  bool viscous = false;  // normal_damping > 0
};

// SPEC §2 on every listed pair: history update and per-pair force/torques; separated pairs lose history.
// `kernel` must match the one given to gather_and_integrate and ensure_pair_arrays (it decides where i's
// share goes); PairKernel::Lanes where kPairLanesBuilt is false throws std::logic_error.
void compute_pair_forces(const Particles& P, const PairList& L, const PairHistory& H, const PairForces& F,
                         const ContactParams& cp, ContactFeatures feat, PairKernel kernel = kDefaultPairKernel);

// Per particle, in a fixed order: sum of pair forces (row i, then transposed row), wall forces, then
// Cundall damping (SPEC §4) and the leapfrog kick-drift. Returns max |x - x_ref|^2 (exact reduction).
// store_forces: the undamped sums go to P.f and P.t (for output; nothing in the dynamics reads them).
Real gather_and_integrate(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                          const WallSet& walls, Real E_wall, Real alpha, Real dt,
                          PairKernel kernel = kDefaultPairKernel, bool store_forces = true);

// The first half of gather_and_integrate: P.f and P.t, the total (undamped) force and torque on each
// particle from the current pair forces and walls, with the same bits; nothing moves.
void gather_forces(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                   const WallSet& walls, Real E_wall, PairKernel kernel = kDefaultPairKernel);

// The local damping's drag of a step's kick as its first moment about c, per axis a: sum_i (x_i - c)_a d_i,a with
// d_i = damped(f_i, v_i) - f_i at x(t) (Engine::damping_moment's expression). A cyclic stage takes it every step for
// its loops less the drag (CycleLoop).
struct DragMeasure {
  Vec3 c;
  Vec3 moment;
};

// reduce_wall_loads at the positions before the drift, then gather_and_integrate (store_forces = false: P.f
// and P.t are left alone): the same bits for both (DeterministicSum's chunks and order). Host backends do
// both in one pass over the particles (one 256-particle chunk per work item). A GPU keeps two kernels (inside
// the integration the team path cost more than the pass it saves, perf/NOTES.md attempt 31), but the loads
// and the displacement max stay on the device until one copy brings both over (attempt 32).
// drag (host backends only; a GPU throws): the same pass also sums drag->moment after the wall terms, in
// DeterministicSum's chunks: Engine::damping_moment's bits without its own gather pass, the dynamics unchanged
// (the Drag terms are a compile-time branch of the kernel: the step that measures nothing has none).
Real gather_integrate_and_load_walls(const Particles& P, const PairList& L, const FlagView& flags, const PairForces& F,
                                     const WallSet& walls, Real E_wall, Real alpha, Real dt, PairKernel kernel,
                                     DeterministicSum& red, WallLoads& loads, DragMeasure* drag = nullptr);

// Affine remap of the positions with a moving box (beyond SPEC §6.2, Engine::set_affine_box): per axis a,
// x_a <- lo1_a + (x_a - lo0_a) * scale_a, so every particle keeps its relative place in the box as the walls move
// (LAMMPS `fix deform ... remap x`). Velocities are left alone. Returns max |x - x_ref|^2 after the remap (exact
// reduction), so the neighbour-list criterion sees the remap's displacement in the step that makes it.
Real remap_affine(const Particles& P, const Vec3& lo0, const Vec3& scale, const Vec3& lo1);

// Wall loads at the current positions (SPEC §3 per-wall force reduction).
// team: DeterministicSum::run_one_term's team path (default on a GPU); the same bits either way.
WallLoads reduce_wall_loads(const Particles& P, const WallSet& walls, Real E_wall, DeterministicSum& red,
                            bool team = !kHostBackend);

// Copies history from the old list to the new one by pair identity (i, j); new pairs start at zero.
void transfer_history(const PairList& old_list, const PairHistory& old_h, const PairList& new_list,
                      const PairHistory& new_h);

// Grow-only allocation of per-pair arrays for at least n pairs (and what `kernel` needs for i's share: the
// per-particle row sums or the per-pair torque on i).
void ensure_pair_arrays(PairHistory& h, int n);
void ensure_pair_arrays(PairForces& f, int n, int nparticles, PairKernel kernel = kDefaultPairKernel);

}  // namespace grainlab
