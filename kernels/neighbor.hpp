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

struct CellGrid {
  IntView cell_start;      // ncells + 1
  IntView cell_particles;  // N, particle indices grouped by cell, ascending within a cell
  IntView cell_of;         // N
  IntView cursor;          // scratch, max(N, ncells)
  int nc[3] = {1, 1, 1};
  Real lo[3] = {0, 0, 0};
  Real inv_h[3] = {1, 1, 1};
  long ncells() const { return long(nc[0]) * nc[1] * nc[2]; }
};

struct PairList {
  IntView offsets;    // N + 1: pairs of row i are [offsets(i), offsets(i+1))
  IntView pair_i;     // capacity >= npairs
  IntView pair_j;     // capacity >= npairs
  IntView t_offsets;  // N + 1: transposed rows
  IntView t_pairs;    // capacity >= npairs: pair indices with pair_j == row, ascending
  IntView counts;     // scratch, N
  int npairs = 0;
  int capacity() const { return int(pair_i.extent(0)); }
};

struct NeighborStats {
  int npairs = 0;
  long ncells = 0;
  int max_row = 0;     // longest row, for diagnostics
  long examined = 0;   // candidates the search looked at (every particle of the 27 cells around each particle)
};

// Bins particles into cells of edge >= cell_min and rebuilds the pair list for cutoff r_i + r_j + skin.
// The list only grows its storage (25 % slack), so a steady state allocates nothing. Without `transposed`
// the transposed index is left empty (a list that is only filtered, never gathered over).
NeighborStats build_neighbor_list(const VecView& x, const RealView& r, Real skin, Real cell_min, CellGrid& grid,
                                  PairList& list, bool transposed = true);

// Inner list: the pairs of the sorted list `outer` closer than r_i + r_j + margin, in the same order, with
// their transposed index. O(pairs), no cell search: the cheap half of a two-level Verlet scheme (Engine).
// Returns the pair count.
int filter_pair_list(const VecView& x, const RealView& r, Real margin, const PairList& outer, PairList& inner);

// Brute-force O(N^2) reference (test oracle): the same pairs, row-major sorted, on the host.
void brute_force_pairs(const VecView& x, const RealView& r, Real skin, std::vector<std::pair<int, int>>& out);

}  // namespace grainlab
