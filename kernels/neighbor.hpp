#pragma once
// Neighbour search, SPEC §5: cell binning + Verlet half list (pairs i < j closer than r_i + r_j + skin).
// Storage is CSR by i, each row sorted by j, plus the transposed index (for each j, the pairs in which
// it is the second particle, sorted by pair index). Sorted rows make the list a pure function of the
// positions: the same pairs in the same order for any thread count, which is what makes the
// per-particle gather (and so the dynamics) bitwise reproducible, and lets contact history be found by
// pair identity with a binary search after a rebuild.
#include <utility>
#include <vector>

#include "types.hpp"

namespace grainlab {

// Cells per size class (the "multi" binning of LAMMPS' neigh_modify, Ogarko & Luding 2012, Comput. Phys.
// Commun. 183:931): radii split into classes a factor 2 wide, each class binned on its own grid with cells of
// edge >= 2 r_cap + skin (r_cap: a bound on the class's radii). A sphere looks in each class's grid only as far
// as a pair with that class can reach, r_i + r_cap + skin, so a small sphere no longer scans cells sized for the
// largest pair. With r_max / r_min < 2 there is one class and the scheme is the classic single grid.
// Trivially copyable: kernels take it by value.
constexpr int kMaxSizeClasses = 8;
struct SizeClassGrid {
  int nclasses = 1;
  Real r_cap[kMaxSizeClasses] = {};     // class c holds radii < r_cap[c] (the last class: <= r_cap, the r_max)
  int count[kMaxSizeClasses] = {};      // spheres in class c
  int base[kMaxSizeClasses + 1] = {};   // class c's cells are [base[c], base[c + 1])
  int nc[kMaxSizeClasses][3] = {};
  Real inv_h[kMaxSizeClasses][3] = {};
  Real lo[3] = {0, 0, 0};

  KOKKOS_INLINE_FUNCTION int class_of(Real r) const {
    int c = 0;
    while (c + 1 < nclasses && r >= r_cap[c]) ++c;
    return c;
  }
  KOKKOS_INLINE_FUNCTION int coord(int c, int d, Real v) const {
    const int k = int((v - lo[d]) * inv_h[c][d]);
    return k < 0 ? 0 : (k >= nc[c][d] ? nc[c][d] - 1 : k);
  }
};

struct CellGrid {
  IntView cell_start;      // ncells + 1
  IntView cell_particles;  // N, particle indices grouped by cell, ascending within a cell
  IntView cell_of;         // N
  IntView cursor;          // scratch, max(N, ncells + 1)
  // x, y, z, r of cell_particles(k) at k: the search scans a cell row's candidates as one contiguous range
  // instead of gathering each through its index.
  Kokkos::View<Real* [4], VecLayout, MemSpace> binned;
  SizeClassGrid g;
  long ncells() const { return g.base[g.nclasses]; }
};

struct PairList {
  IntView offsets;    // N + 1: pairs of row i are [offsets(i), offsets(i+1))
  IntView pair_i;     // capacity >= npairs
  IntView pair_j;     // capacity >= npairs
  IntView t_offsets;  // N + 1: transposed rows
  IntView t_pairs;    // capacity >= npairs: pair indices with pair_j == row, ascending
  IntView counts;     // N: each row's length in the last build (scratch during one)
  // Single-pass build (fill_rows): row i's pairs first go to slots(slot_offsets(i) ...), sized from the last
  // build's row lengths, then are compacted into pair_i, pair_j.
  IntView slot_offsets;  // N + 1
  IntView slots;         // scratch (also filter_pair_list's, when this is the outer list)
  int built_n = -1;      // offsets hold the rows of a list built by the search for this many particles (-1: none)
  int npairs = 0;
  int capacity() const { return int(pair_i.extent(0)); }
};

struct NeighborStats {
  int npairs = 0;
  long ncells = 0;
  int max_row = 0;     // longest row, for diagnostics
  long examined = 0;   // candidates the search looked at (every particle of the cells it visited)
  int size_classes = 1;
  int searches = 1;    // passes over the cells: 1 when the last build's row lengths held every row, else 2
};

// Bins particles into size classes and cells (SizeClassGrid) and rebuilds the pair list for cutoff
// r_i + r_j + skin. The list is a pure function of the positions and radii, whatever the binning: rows are
// sorted by j.
// From a list's second build on, each row is searched once into slots sized from its last length (NeighborStats::
// searches; perf/NOTES.md attempt 52); the first build, or one where a row outgrew its slots, counts and fills.
// The list only grows its storage (25 % slack), so a steady state allocates nothing. Without `transposed`
// the transposed index is left empty (a list that is only filtered, never gathered over).
NeighborStats build_neighbor_list(const VecView& x, const RealView& r, Real skin, CellGrid& grid,
                                  PairList& list, bool transposed = true);

// Inner list: the pairs of the sorted list `outer` closer than r_i + r_j + margin, in the same order, with
// their transposed index. O(pairs), no cell search: the cheap half of a two-level Verlet scheme (Engine).
// Returns the pair count.
// One pass into the slots of `outer`'s rows (outer.slots is the scratch), then compacted.
int filter_pair_list(const VecView& x, const RealView& r, Real margin, PairList& outer, PairList& inner);

// Brute-force O(N^2) reference (test oracle): the same pairs, row-major sorted, on the host.
void brute_force_pairs(const VecView& x, const RealView& r, Real skin, std::vector<std::pair<int, int>>& out);

}  // namespace grainlab
