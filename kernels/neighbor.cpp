#include "neighbor.hpp"
#include "huge_pages.hpp"

#include <algorithm>
#include <string>
#include <cmath>
#include <limits>
#include <type_traits>

namespace grainlab {
namespace {

// Insertion sort of a short device-side segment (cells hold a few particles, rows a few tens).
KOKKOS_INLINE_FUNCTION void sort_segment(const IntView& a, int begin, int end) {
  for (int k = begin + 1; k < end; ++k) {
    const int v = a(k);
    int m = k - 1;
    while (m >= begin && a(m) > v) {
      a(m + 1) = a(m);
      --m;
    }
    a(m + 1) = v;
  }
}

// Exclusive scan of counts(0..n-1) into offsets(0..n); returns the total. The last item's final pass writes the
// tail, offsets(n): no kernel of its own (a parallel region fewer on host backends, perf/NOTES.md session 72).
int exclusive_scan(const IntView& counts, const IntView& offsets, int n) {
  int total = 0;
  Kokkos::parallel_scan(
      "grainlab::neighbor::scan", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(int i, int& upd, bool final) {
        const int c = counts(i);
        if (final) {
          offsets(i) = upd;
          if (i == n - 1) offsets(n) = upd + c;
        }
        upd += c;
      },
      total);
  if (n == 0) Kokkos::deep_copy(Kokkos::subview(offsets, 0), 0);
  return total;
}

// Counting sort of the items 0..nitems-1 by key(item) in [0, nkeys): items(start(k)) .. items(start(k+1)-1)
// are the items with key k, ascending. The atomic counts are exact integers; the per-bucket sort makes the
// order independent of which thread inserted first. Used for the cell bins and the transposed pair index.
void group_by_key(const IntView& key, int nitems, int nkeys, const IntView& cursor, const IntView& start,
                  const IntView& items) {
  Kokkos::parallel_for(
      "grainlab::neighbor::group_zero", Kokkos::RangePolicy<ExecSpace>(0, nkeys),
      KOKKOS_LAMBDA(int k) { cursor(k) = 0; });
  Kokkos::parallel_for(
      "grainlab::neighbor::group_count", Kokkos::RangePolicy<ExecSpace>(0, nitems),
      KOKKOS_LAMBDA(int i) { Kokkos::atomic_fetch_add(&cursor(key(i)), 1); });
  exclusive_scan(cursor, start, nkeys);
  // The fill counts each key's items down from its count (c, c - 1, ..., 1: slots start + c - 1 down to start),
  // so the cursor needs no copy of start (a kernel fewer); the sort below fixes the order within a key either way.
  Kokkos::parallel_for(
      "grainlab::neighbor::group_fill", Kokkos::RangePolicy<ExecSpace>(0, nitems), KOKKOS_LAMBDA(int i) {
        const int k = key(i);
        const int slot = start(k) + Kokkos::atomic_fetch_sub(&cursor(k), 1) - 1;
        items(slot) = i;
      });
  Kokkos::parallel_for(
      "grainlab::neighbor::group_sort", Kokkos::RangePolicy<ExecSpace>(0, nkeys),
      KOKKOS_LAMBDA(int k) { sort_segment(items, start(k), start(k + 1)); });
}

// Transposed index for the gather: pairs grouped by j, ascending pair index within a row.
void build_transpose(PairList& list, int n) {
  grow_view(list.t_pairs, "grainlab::pairs::t_pairs", list.npairs);
  grow_view(list.t_offsets, "grainlab::pairs::t_offsets", n + 1);
  group_by_key(list.pair_j, list.npairs, n, list.counts, list.t_offsets, list.t_pairs);
}

// Pair search as a tagged functor (Cabana VerletList style): Count, Fill (count_then_fill) and Slots (fill_rows,
// one pass into per-row slots). For each size class b, the cells
// of b's grid within r_i + r_cap[b] + skin of x_i (at most 3 per axis for the classes up to i's own size, more
// for the few large spheres looking into a small class's finer grid).
struct PairSearch {
  struct Count {};
  struct Fill {};
  struct Slots {};
  VecView x;
  RealView r;
  IntView cell_start, cell_particles, counts, offsets, pair_i, pair_j, slot_offsets, slots;
  Kokkos::View<Real* [4], VecLayout, MemSpace> binned;
  SizeClassGrid g;
  Real skin;

  // Returns the pairs of row i; `examined` counts the candidates looked at (the visited cells' particles), the
  // search's work, which stays O(1) per particle for any N (test Neighbor.SearchWorkPerParticleIsIndependentOfN).
  // Sink: Count writes nothing, Fill writes (i, j) to pair_i, pair_j from `out`, Slots writes j to slots from
  // `out` while fewer than `cap` (and counts on).
  template <class Sink>
  KOKKOS_INLINE_FUNCTION int visit(int i, int out, int cap, long& examined) const {
    const Real xi = x(i, 0), yi = x(i, 1), zi = x(i, 2), ri = r(i);
    int n = 0;
    for (int b = 0; b < g.nclasses; ++b) {
      if (g.count[b] == 0) continue;
      // Any j of class b within the cutoff lies within `reach` of x_i on every axis; binning is monotone in
      // the coordinate, so its cell lies between the cells of x_i - reach and x_i + reach. The 1e-9 relative
      // pad covers the rounding of x_i -+ reach for a pair exactly at the cutoff; it widens no range but
      // where a cell boundary lies within that pad.
      const Real reach = (ri + g.r_cap[b] + skin) * Real(1 + 1e-9);
      const int x0 = g.coord(b, 0, xi - reach), x1 = g.coord(b, 0, xi + reach);
      const int y0 = g.coord(b, 1, yi - reach), y1 = g.coord(b, 1, yi + reach);
      const int z0 = g.coord(b, 2, zi - reach), z1 = g.coord(b, 2, zi + reach);
      const int n0 = g.nc[b][0], n1 = g.nc[b][1], base = g.base[b];
      for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y) {
          // The cells x0..x1 of one row are contiguous, and so are their particles.
          const int c = base + (z * n1 + y) * n0;
          const int k0 = cell_start(c + x0), k1 = cell_start(c + x1 + 1);
          examined += k1 - k0;
          for (int k = k0; k < k1; ++k) {
            const int j = cell_particles(k);
            const Real ex = binned(k, 0) - xi, ey = binned(k, 1) - yi, ez = binned(k, 2) - zi;
            const Real cut = ri + binned(k, 3) + skin;
            // One test for both conditions, without a branch on j > i alone: half the candidates fail that,
            // in no order a predictor could learn, while the combined test is true only for the few listed
            // pairs among tens of candidates (perf/NOTES.md attempt 50).
            const bool hit = (j > i) & (ex * ex + ey * ey + ez * ez < cut * cut);
            if constexpr (std::is_same_v<Sink, Fill>) {
              if (hit) {
                pair_i(out + n) = i;
                pair_j(out + n) = j;
              }
            } else if constexpr (std::is_same_v<Sink, Slots>) {
              if (hit && n < cap) slots(out + n) = j;
            }
            n += hit ? 1 : 0;
          }
        }
    }
    return n;
  }
  KOKKOS_INLINE_FUNCTION void operator()(Count, int i, long& examined) const {
    counts(i) = visit<Count>(i, 0, 0, examined);
  }
  KOKKOS_INLINE_FUNCTION void operator()(Fill, int i) const {
    const int begin = offsets(i);
    long unused = 0;
    visit<Fill>(i, begin, 0, unused);
    sort_segment(pair_j, begin, offsets(i + 1));  // deterministic row order: ascending j
  }
  KOKKOS_INLINE_FUNCTION void operator()(Slots, int i, long& examined) const {
    const int begin = slot_offsets(i);
    counts(i) = visit<Slots>(i, begin, slot_offsets(i + 1) - begin, examined);
  }
  static constexpr bool kSortRows = true;  // candidates come cell by cell, not in j order
};

// Filter of a sorted CSR list (the inner list of Engine, perf/NOTES.md attempt 18), in one pass (fill_rows): a
// row's kept pairs stay in their order, so the inner rows are sorted by j like the Verlet rows.
struct PairFilter {
  struct Fill {};
  struct Slots {};
  VecView x;
  RealView r;
  IntView outer_offsets, outer_j, counts, offsets, pair_i, pair_j, slot_offsets, slots;
  Real margin;

  KOKKOS_INLINE_FUNCTION bool keep(const Vec3& xi, Real ri, int j) const {
    const Vec3 d = load(x, j) - xi;
    const Real cut = ri + r(j) + margin;
    return norm2(d) < cut * cut;
  }
  KOKKOS_INLINE_FUNCTION void operator()(Fill, int i) const {
    const Vec3 xi = load(x, i);
    const Real ri = r(i);
    int q = offsets(i);
    for (int p = outer_offsets(i); p < outer_offsets(i + 1); ++p) {
      const int j = outer_j(p);
      if (!keep(xi, ri, j)) continue;
      pair_i(q) = i;
      pair_j(q) = j;
      ++q;
    }
  }
  // The outer row is the inner row's exact bound, so the slots are the outer row's own (slot_offsets = outer
  // offsets) and never overflow.
  KOKKOS_INLINE_FUNCTION void operator()(Slots, int i, long& examined) const {
    const Vec3 xi = load(x, i);
    const Real ri = r(i);
    const int begin = slot_offsets(i);
    int c = 0;
    for (int p = outer_offsets(i); p < outer_offsets(i + 1); ++p) {
      const int j = outer_j(p);
      if (keep(xi, ri, j)) slots(begin + c++) = j;
    }
    counts(i) = c;
    examined += outer_offsets(i + 1) - outer_offsets(i);
  }
  static constexpr bool kSortRows = false;  // a sorted row filtered stays sorted
};

// Runs a row functor with Count and Fill tags (PairSearch) into `list`: counts per row, scan
// into offsets, then each row fills its own slots (no atomics, so the rows' order is the functor's). The count
// also sums the candidates examined (an integer sum: exact, whatever the thread count) into `examined`.
template <class F>
int count_then_fill(F f, int n, PairList& list, const char* count_label, const char* fill_label, long& examined) {
  grow_view(list.offsets, "grainlab::pairs::offsets", n + 1);
  grow_view(list.counts, "grainlab::pairs::counts", n);
  f.counts = list.counts;
  f.offsets = list.offsets;
  examined = 0;
  Kokkos::parallel_reduce(count_label, Kokkos::RangePolicy<ExecSpace, typename F::Count>(0, n), f, examined);
  const int np = exclusive_scan(list.counts, list.offsets, n);
  grow_view(list.pair_i, "grainlab::pairs::i", np);
  grow_view(list.pair_j, "grainlab::pairs::j", np);
  f.pair_i = list.pair_i;
  f.pair_j = list.pair_j;
  Kokkos::parallel_for(fill_label, Kokkos::RangePolicy<ExecSpace, typename F::Fill>(0, n), f);
  list.npairs = np;
  return np;
}

// The same list in one pass where row i's pairs fit the slots [slot_offsets(i), slot_offsets(i + 1)): F's Slots
// pass writes each row there and its length to counts, and the rows are then copied into CSR order (sorted
// where F's rows come unsorted). Where some row outgrew its slots (only the search's estimate can fall short),
// the counts are exact by then, so F's Fill pass runs as the second half of count_then_fill. Returns the pair
// count; `passes` is the number of passes that searched (1 or 2).
template <class F>
int fill_rows(F f, int n, PairList& list, const IntView& slot_offsets, IntView& slots, long nslots,
              const char* slots_label, const char* fill_label, long& examined, int& passes) {
  grow_view(list.counts, "grainlab::pairs::counts", n);
  grow_view(slots, "grainlab::pairs::slots", nslots);
  f.counts = list.counts;
  f.slot_offsets = slot_offsets;
  f.slots = slots;
  examined = 0;
  Kokkos::parallel_reduce(slots_label, Kokkos::RangePolicy<ExecSpace, typename F::Slots>(0, n), f, examined);
  auto counts = list.counts;
  int overflow = 0;
  Kokkos::parallel_reduce(
      "grainlab::neighbor::slots_overflow", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(int i, int& o) { o += counts(i) > slot_offsets(i + 1) - slot_offsets(i) ? 1 : 0; }, overflow);
  grow_view(list.offsets, "grainlab::pairs::offsets", n + 1);
  const int np = exclusive_scan(list.counts, list.offsets, n);
  grow_view(list.pair_i, "grainlab::pairs::i", np);
  grow_view(list.pair_j, "grainlab::pairs::j", np);
  list.npairs = np;
  if (overflow > 0) {
    f.offsets = list.offsets;
    f.pair_i = list.pair_i;
    f.pair_j = list.pair_j;
    Kokkos::parallel_for(fill_label, Kokkos::RangePolicy<ExecSpace, typename F::Fill>(0, n), f);
    passes = 2;
    return np;
  }
  auto off = list.offsets;
  auto pi = list.pair_i;
  auto pj = list.pair_j;
  auto sl = slots;
  Kokkos::parallel_for(
      "grainlab::neighbor::compact_rows", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
        const int begin = off(i), len = off(i + 1) - begin, from = slot_offsets(i);
        for (int k = 0; k < len; ++k) {
          pi(begin + k) = i;
          pj(begin + k) = sl(from + k);
        }
        if constexpr (F::kSortRows) sort_segment(pj, begin, begin + len);
      });
  passes = 1;
  return np;
}

}  // namespace

NeighborStats build_neighbor_list(const VecView& x, const RealView& r, Real skin, CellGrid& grid, PairList& list,
                                  bool transposed) {
  const int n = int(x.extent(0));
  NeighborStats st;

  // Bounding box and radius range (min/max reductions are exact, so thread-count independent).
  Real lo[3], hi[3], rlo = 0, rhi = 0;
  for (int d = 0; d < 3; ++d) {
    Kokkos::parallel_reduce(
        "grainlab::neighbor::bbox_lo", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, Real& m) { m = x(i, d) < m ? x(i, d) : m; }, Kokkos::Min<Real>(lo[d]));
    Kokkos::parallel_reduce(
        "grainlab::neighbor::bbox_hi", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, Real& m) { m = x(i, d) > m ? x(i, d) : m; }, Kokkos::Max<Real>(hi[d]));
  }
  Kokkos::parallel_reduce(
      "grainlab::neighbor::r_lo", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) { m = r(i) < m ? r(i) : m; }, Kokkos::Min<Real>(rlo));
  Kokkos::parallel_reduce(
      "grainlab::neighbor::r_hi", Kokkos::RangePolicy<ExecSpace>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) { m = r(i) > m ? r(i) : m; }, Kokkos::Max<Real>(rhi));
  if (n == 0) {
    for (int d = 0; d < 3; ++d) lo[d] = hi[d] = 0;
    rlo = rhi = 0;
  }

  // Size classes a factor 2 wide from the smallest radius: class c < K - 1 holds [rlo 2^c, rlo 2^(c+1)), the
  // last one the rest up to rhi. A factor 2 keeps a class's cells no coarser than twice what its smallest
  // member needs; the cap of 8 classes covers r_max / r_min up to 128 before the last class widens.
  SizeClassGrid& g = grid.g;
  g = SizeClassGrid{};
  int K = 1;
  while (K < kMaxSizeClasses && rlo > 0 && rlo * Real(1 << K) <= rhi) ++K;
  g.nclasses = K;
  for (int c = 0; c + 1 < K; ++c) g.r_cap[c] = rlo * Real(1 << (c + 1));
  g.r_cap[K - 1] = rhi;
  for (int d = 0; d < 3; ++d) g.lo[d] = lo[d];
  st.size_classes = K;

  grow_view(grid.cell_of, "grainlab::cells::of", n);
  auto cell_of = grid.cell_of;
  {
    const SizeClassGrid gc = g;
    Kokkos::parallel_for(
        "grainlab::neighbor::size_class", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i) { cell_of(i) = gc.class_of(r(i)); });
  }
  for (int c = 0; c < K; ++c) {
    int cnt = 0;
    if (K == 1) {
      cnt = n;
    } else {
      Kokkos::parallel_reduce(
          "grainlab::neighbor::class_count", Kokkos::RangePolicy<ExecSpace>(0, n),
          KOKKOS_LAMBDA(int i, int& s) { s += cell_of(i) == c ? 1 : 0; }, cnt);
    }
    g.count[c] = cnt;
  }

  // Each class's cells have edge >= 2 r_cap + skin (a same-class pair is then found within the 27 cells around
  // a sphere); if a stray particle stretches the box, coarsen so a class keeps <= 8 n_c + 27 cells (memory and
  // time stay O(N) whatever happens to the geometry).
  long total = 0;
  for (int c = 0; c < K; ++c) {
    Real h = 2 * g.r_cap[c] + skin;
    const long cap = 8L * g.count[c] + 27;
    for (;;) {
      long cells = 1;
      for (int d = 0; d < 3; ++d) cells *= std::max(1L, long(std::floor((hi[d] - lo[d]) / h)));
      if (cells <= cap) break;
      h *= 1.5;
    }
    g.base[c] = int(total);
    long cells = 1;
    for (int d = 0; d < 3; ++d) {
      g.nc[c][d] = int(std::max(1L, long(std::floor((hi[d] - lo[d]) / h))));
      const Real edge = (hi[d] - lo[d]) / g.nc[c][d];
      g.inv_h[c][d] = edge > 0 ? Real(1) / edge : Real(0);
      cells *= g.nc[c][d];
    }
    total += cells;
  }
  g.base[K] = int(total);
  const int nc = int(total);
  st.ncells = nc;
  grow_view(grid.cell_start, "grainlab::cells::start", nc + 1);
  grow_view(grid.cell_particles, "grainlab::cells::particles", n);
  grow_view(grid.cursor, "grainlab::cells::cursor", std::max(n, nc + 1));

  // Bin: the cell of each particle in its class's grid, then the particles grouped by cell (ascending
  // within a cell).
  {
    const SizeClassGrid gc = g;
    Kokkos::parallel_for(
        "grainlab::neighbor::bin", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
          const int c = cell_of(i);
          cell_of(i) = gc.base[c] + (gc.coord(c, 2, x(i, 2)) * gc.nc[c][1] + gc.coord(c, 1, x(i, 1))) * gc.nc[c][0] +
                       gc.coord(c, 0, x(i, 0));
        });
    group_by_key(cell_of, n, nc, grid.cursor, grid.cell_start, grid.cell_particles);
  }
  grow_view(grid.binned, "grainlab::cells::binned", n);
  {
    auto binned = grid.binned;
    auto cp = grid.cell_particles;
    Kokkos::parallel_for(
        "grainlab::neighbor::binned_copy", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int k) {
          const int j = cp(k);
          binned(k, 0) = x(j, 0);
          binned(k, 1) = x(j, 1);
          binned(k, 2) = x(j, 2);
          binned(k, 3) = r(j);
        });
  }

  // Pairs (rows sorted by j). The first build of a list counts, scans and fills: two searches. Later builds give
  // row i the slots its last length needs plus a quarter plus 4 (particles moved at most skin/2 since, so a row
  // rarely gains more) and search once (fill_rows); an outgrown row costs the second search after all.
  PairSearch ps{x, r, grid.cell_start, grid.cell_particles, {}, {}, {}, {}, {}, {}, grid.binned, g, skin};
  long nslots = -1;  // the single pass's slots, or -1: count and fill
  if (list.built_n == n && n > 0) {
    grow_view(list.slot_offsets, "grainlab::pairs::slot_offsets", n + 1);
    auto off = list.offsets;
    auto so = list.slot_offsets;
    Kokkos::parallel_scan(
        "grainlab::neighbor::slot_scan", Kokkos::RangePolicy<ExecSpace>(0, n + 1),
        KOKKOS_LAMBDA(int i, long& upd, bool final) {
          if (final) so(i) = int(upd);
          if (i < n) {
            const int len = off(i + 1) - off(i);
            upd += len + len / 4 + 4;
          }
        },
        nslots);
  }
  if (nslots >= 0 && nslots <= std::numeric_limits<int>::max()) {  // slot indices are ints, as pair indices are
    st.npairs = fill_rows(ps, n, list, list.slot_offsets, list.slots, nslots, "grainlab::neighbor::slot_pairs",
                          "grainlab::neighbor::fill_pairs", st.examined, st.searches);
  } else {
    st.npairs = count_then_fill(ps, n, list, "grainlab::neighbor::count_pairs", "grainlab::neighbor::fill_pairs",
                                st.examined);
    st.searches = 2;
  }
  list.built_n = n;

  if (transposed) build_transpose(list, n);
  {
    auto off = list.offsets;
    int mr = 0;
    Kokkos::parallel_reduce(
        "grainlab::neighbor::max_row", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(int i, int& m) {
          const int len = off(i + 1) - off(i);
          m = len > m ? len : m;
        },
        Kokkos::Max<int>(mr));
    st.max_row = n > 0 ? mr : 0;
  }
  return st;
}

int filter_pair_list(const VecView& x, const RealView& r, Real margin, PairList& outer, PairList& inner) {
  const int n = int(x.extent(0));
  PairFilter pf{x, r, outer.offsets, outer.pair_j, {}, {}, {}, {}, {}, {}, margin};
  long examined = 0;
  int passes = 0;
  // The outer list's slots as scratch (its build is done with them): one such array per engine, not per list.
  const int np = fill_rows(pf, n, inner, outer.offsets, outer.slots, outer.npairs, "grainlab::neighbor::slot_inner",
                           "grainlab::neighbor::fill_inner", examined, passes);
  build_transpose(inner, n);
  return np;
}

void brute_force_pairs(const VecView& x, const RealView& r, Real skin, std::vector<std::pair<int, int>>& out) {
  auto hx = Kokkos::create_mirror_view_and_copy(HostSpace(), x);
  auto hr = Kokkos::create_mirror_view_and_copy(HostSpace(), r);
  const int n = int(x.extent(0));
  out.clear();
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      Real d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += (hx(j, k) - hx(i, k)) * (hx(j, k) - hx(i, k));
      const Real cut = hr(i) + hr(j) + skin;
      if (d2 < cut * cut) out.emplace_back(i, j);
    }
}

}  // namespace grainlab
