#include "packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <iomanip>
#include <sstream>
#include <string>
#include <unordered_map>

namespace grainlab {
namespace {
std::uint64_t splitmix64(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace

Rng::Rng(std::uint64_t seed) : s_{} {
  for (auto& s : s_) s = splitmix64(seed);
}
std::uint64_t Rng::next() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

Real power_law_radius(Real u, Real D, Real a, Real b) {
  if (a == b) return a;
  const Real e = 1 - D;
  // Near D = 1 the general form below loses digits as 1/e grows: its base lo + u (hi - lo) differs from a^e by about
  // e ln(b/a) a^e, so one ulp of it becomes ~1e-16 / |e| of r (1e-4 at |1 - D| = 1e-12, where the config refused D).
  // The same inverse CDF in ratios to a, r = a (1 + u ((b/a)^e - 1))^(1/e) = a exp(log1p(u expm1(e L)) / e) with
  // L = ln(b/a), keeps them, and at D = 1 is its limit a exp(u L): p(r) ~ 1/r, uniform in ln r. Used only there
  // (|e| < kNearOne, where the general form would be good to ~1e-13 or less): elsewhere every radius a config has
  // drawn is kept bit for bit.
  constexpr Real kNearOne = 1e-3;
  if (std::abs(e) < kNearOne) {
    const Real L = std::log(b / a);
    return e == 0 ? a * std::exp(u * L) : a * std::exp(std::log1p(u * std::expm1(e * L)) / e);
  }
  const Real lo = std::pow(a, e), hi = std::pow(b, e);
  return std::pow(lo + u * (hi - lo), 1 / e);
}

GradingSampler::GradingSampler(const Grading& g) {
  // Interval k, [d_k, d_k+1], holds the mass share dP_k spread uniformly in ln d, and p(d) ~ d^-4 there: its number
  // share is dP_k (d_k^-3 - d_k+1^-3) / (3 ln(d_k+1 / d_k)) up to a common factor. Radii relative to the largest keep
  // the powers finite for any sizes a config admits (a ratio past ~1e100 makes them infinite: the caller's check).
  const Real top = g.diameter.back();
  std::vector<Real> w;
  for (size_t k = 0; k + 1 < g.diameter.size(); ++k) {
    const Real dp = g.passing[k + 1] - g.passing[k];
    if (!(dp > 0)) continue;  // a flat step (a gap grading): no sphere there
    const Real a = g.diameter[k] / top, b = g.diameter[k + 1] / top;
    a_.push_back(g.diameter[k] / 2);
    b_.push_back(g.diameter[k + 1] / 2);
    // (sieves a rounding apart, a == b here: the interval's limit, a^-3)
    w.push_back(dp * (b > a ? (std::pow(a, -3) - std::pow(b, -3)) / (3 * std::log(b / a)) : std::pow(a, -3)));
  }
  Real sum = 0;
  for (Real x : w) sum += x;
  Real run = 0;
  for (Real x : w) cum_.push_back((run += x) / sum);
  if (!cum_.empty()) cum_.back() = 1;  // so that every u < 1 finds its interval
}

Real GradingSampler::radius(Real u) const {
  const size_t k = size_t(std::upper_bound(cum_.begin(), cum_.end(), u) - cum_.begin());
  const size_t i = std::min(k, cum_.size() - 1);
  const Real lo = i == 0 ? 0 : cum_[i - 1];
  const Real v = std::min<Real>(std::max<Real>((u - lo) / (cum_[i] - lo), 0), 1);
  return power_law_radius(v, 4, a_[i], b_[i]);
}

Real grading_diameter(const Grading& g, Real percent) {
  const std::vector<Real>& d = g.diameter;
  const std::vector<Real>& p = g.passing;
  if (percent <= p.front()) return d.front();
  for (size_t k = 0; k + 1 < d.size(); ++k)
    if (percent <= p[k + 1] && p[k + 1] > p[k])
      return d[k] * std::pow(d[k + 1] / d[k], (percent - p[k]) / (p[k + 1] - p[k]));
  return d.back();
}

GradingPoints grading_check_points(const Grading& g) {
  GradingPoints p;
  for (size_t k = 0; k < g.diameter.size(); ++k) {
    p.at.push_back(g.diameter[k]);
    p.want.push_back(g.passing[k]);
    p.sieve.push_back(1);
    if (k + 1 < g.diameter.size() && g.passing[k + 1] > g.passing[k]) {
      p.at.push_back(std::sqrt(g.diameter[k] * g.diameter[k + 1]));
      p.want.push_back((g.passing[k] + g.passing[k + 1]) / 2);
      p.sieve.push_back(0);
    }
  }
  return p;
}

std::vector<Real> passing_at(std::vector<Real> r, const std::vector<Real>& diameters) {
  // Sorted, with the running volume: O(N log N + sieves log N) (a million spheres, a thousand sieves).
  std::sort(r.begin(), r.end());
  std::vector<double> cum(r.size() + 1, 0);
  for (size_t i = 0; i < r.size(); ++i) cum[i + 1] = cum[i] + double(r[i]) * r[i] * r[i];
  std::vector<Real> out(diameters.size(), 0);
  for (size_t k = 0; k < diameters.size(); ++k) {
    const size_t n = size_t(std::upper_bound(r.begin(), r.end(), diameters[k] / 2) - r.begin());
    out[k] = cum.back() > 0 ? Real(100 * cum[n] / cum.back()) : 0;
  }
  return out;
}

GradingIndices grading_indices(const Grading& g) {
  GradingIndices x;
  x.d10 = grading_diameter(g, 10);
  x.d30 = grading_diameter(g, 30);
  x.d50 = grading_diameter(g, 50);
  x.d60 = grading_diameter(g, 60);
  x.cu = x.d60 / x.d10;
  x.cc = x.d30 * x.d30 / (x.d10 * x.d60);
  return x;
}

GradingIndices grading_indices(std::vector<Real> r) {
  // The sample's own curve: each sphere's diameter passes the mass of every sphere up to and including it.
  if (r.empty()) return {};
  std::sort(r.begin(), r.end());
  double total = 0;
  for (Real ri : r) total += double(ri) * ri * ri;
  Grading g;
  double run = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    run += double(r[i]) * r[i] * r[i];
    if (i + 1 < r.size() && r[i + 1] == r[i]) continue;  // one point per distinct diameter
    g.diameter.push_back(2 * r[i]);
    g.passing.push_back(Real(100 * run / total));
  }
  // The curve starts at the smallest diameter with that sphere's share passing: a D_x below it is that diameter.
  return grading_indices(g);
}

namespace {
// The radii of a spec, largest first, drawn from `rng` (the first draws of a packing's generator), with the
// cube they fill at the spec's solid fraction: the part of a packing that is known before any placement.
std::vector<Real> draw_radii(const PackingSpec& s, Rng& rng, Real& L) {
  if (s.count < 1) throw ParameterError("count must be >= 1");
  if (!(s.r_min > 0) || !(s.r_max >= s.r_min)) throw ParameterError("need 0 < r_min <= r_max");
  std::optional<GradingSampler> graded;
  if (!s.grading.empty()) graded.emplace(s.grading);
  if (!(s.solid_fraction > 0 && s.solid_fraction <= 0.45))
    throw ParameterError("solid_fraction must be in (0, 0.45] for random sequential placement");
  std::vector<Real> r(s.count);
  Real vs = 0;
  for (auto& ri : r) {
    ri = graded ? graded->radius(rng.uniform()) : power_law_radius(rng.uniform(), s.D, s.r_min, s.r_max);
    vs += 4.0 / 3.0 * M_PI * ri * ri * ri;
  }
  // The inverse CDF takes r_min^(1 - D) and r_max^(1 - D): an extreme r_min (1e-300 m at D = 3.63: 1e789) overflows
  // and every radius is NaN.
  if (!(std::isfinite(vs) && vs > 0)) {
    std::ostringstream os;
    if (graded)
      os << "sample.grading: diameters " << 2 * s.r_min << " to " << 2 * s.r_max << " m: the inverse CDF's powers "
         << "d^-3, or the spheres' volume, are not finite numbers; use diameters nearer 1 (they are in metres)";
    else
      os << "sample.r_min = " << s.r_min << " m, r_max = " << s.r_max << " m with D = " << s.D << ": the radii "
         << "r_min^(1 - D) and r_max^(1 - D) of the inverse CDF, or the spheres' volume, are not finite numbers; "
         << "use radii nearer 1 (they are in metres)";
    throw ParameterError(os.str());
  }
  // Largest first: the big spheres find room while the box is empty.
  std::sort(r.begin(), r.end(), std::greater<Real>());
  L = std::cbrt(vs / s.solid_fraction);
  if (L <= 2 * r.front()) throw ParameterError("box too small for the largest sphere; raise count or lower r_max");
  return r;
}
// Why a placement failed, and what would place it. Every centre keeps its radius from the walls, so in a small box
// the spheres must fill more of the space their centres can reach than the box's solid fraction says: with r_mean
// the mean radius, X(f) = V_s / (L(f) - 2 r_mean)^3, L(f) = (V_s / f)^(1/3). Random sequential addition of equal
// spheres jams at 0.38 (Torquato et al., Phys. Rev. E 74, 061308, 2006); a spread of sizes placed largest first
// gets further. The suggestion keeps X(f) <= kReach (choice: 0.36, below the jamming limit with room for the
// run's 20 000 tries a sphere).
std::string placement_failure(const PackingSpec& s, const std::vector<Real>& r, Real L, int i, int tries) {
  constexpr double kReach = 0.36;
  double vs = 0, rm = 0;
  for (Real ri : r) {
    vs += 4.0 / 3.0 * M_PI * double(ri) * ri * ri;
    rm += ri;
  }
  rm /= double(r.size());
  const auto reach = [&](double f) {
    const double inner = std::cbrt(vs / f) - 2 * rm;
    return inner > 0 ? vs / (inner * inner * inner) : 1.0;
  };
  std::ostringstream os;
  os << std::setprecision(3) << "could not place sphere " << i + 1 << " of " << s.count << " without overlap ("
     << tries << " random tries) at sample.initial_solid_fraction = " << s.solid_fraction << ": in a box of "
     << L / (2 * rm) << " mean diameters, whose walls keep every centre a radius in, the spheres must fill ";
  if (reach(s.solid_fraction) < 1)
    os << reach(s.solid_fraction) << " of the space their centres can reach";
  else
    os << "more than the space their centres can reach (" << reach(s.solid_fraction) << " times it)";
  os << " (random placement of equal spheres jams at 0.38)";
  double f = s.solid_fraction;
  while (f > 0.01 && reach(f) > kReach) f -= 0.01;
  if (f > 0.01 && f < s.solid_fraction)
    os << "; lower sample.initial_solid_fraction to " << std::floor(f * 100 + 0.5) / 100 << " or below, or raise "
       << "sample.count (a larger box loses less of itself to the walls)";
  else
    os << "; lower sample.initial_solid_fraction";
  return os.str();
}
}  // namespace

std::vector<Real> packing_radii(const PackingSpec& s) {
  Rng rng(s.seed);
  Real L = 0;
  return draw_radii(s, rng, L);
}

Packing generate_packing(const PackingSpec& s, int slots_per_cell) {
  Rng rng(s.seed);
  Packing p;
  Real L = 0;
  p.r = draw_radii(s, rng, L);
  p.lo = {0, 0, 0};
  p.hi = {L, L, L};
  const Real rmax = p.r.front();
  const Real h = 2 * rmax;
  // Cells of at least 2 r_max (a sphere's overlaps lie in its 27 cells), and at most ~4 N of them: a dilute sample
  // (initial_solid_fraction 1e-6 is in range) would otherwise ask for cells by the hundred million (bad_alloc).
  // Every sample of a shipped config or test has fewer (equal spheres at 0.2: 2.6 N), so their packings are as before.
  const int nc = std::max(1, int(std::min<double>(L / h, std::cbrt(4.0 * double(s.count)))));
  const Real cell = L / nc;
  // Each cell keeps its spheres' centres and radii itself (x, y, z, r), in place: K slots a cell in one flat array, a
  // cell's spheres past K in its overflow list (a wide grading's small spheres crowding a cell of 2 r_max). A try
  // reads 27 cells whose x-neighbours are adjacent in memory; with a heap block per cell, perf put two thirds of
  // the placement on the stalls of loading each cell's header and its first sphere. Whether a try overlaps does
  // not depend on the order a cell's spheres are read in, so the packing is the same bit for bit as any layout's
  // (Packing.PlacedSpheresAreApartInsideTheBoxAndInCellOrder; and five specs' positions equal to session 42's).
  // With the try's own cell read first and the cell order read off the cells (no sort): 2e5 spheres placed in
  // 0.52-0.77 s against 1.15-1.74 s for session 42's heap blocks, a 1e6-sphere run started in 7.0 s against 14.9
  // (perf/startup.sh placement / start, medians of 3-7 on the noisy 2-core VM, both builds in the same minutes).
  const size_t ncell = size_t(nc) * nc * nc;
  using Sphere = std::array<Real, 4>;
  // Slots for 1.5 times the mean final occupancy, plus 4: the Poisson-like scatter of a cell's count rarely
  // overflows, and the memory stays ~50 bytes a sphere (transient). The tests set fewer to force the overflow path.
  const int K = slots_per_cell > 0 ? slots_per_cell : int(std::ceil(1.5 * double(s.count) / double(ncell))) + 4;
  std::vector<Sphere> slots(ncell * size_t(K));
  std::vector<int> count(ncell, 0);
  std::vector<std::vector<Sphere>> overflow;  // per cell, sized at its first use
  long q_overflowed = 0;
  auto cidx = [&](Real v) { return std::min(nc - 1, std::max(0, int(v / cell))); };
  auto overlaps = [](const Sphere* o, const Sphere* end, const Vec3d& c, Real r) {
    for (; o != end; ++o) {
      Real d2 = 0;
      for (int d = 0; d < 3; ++d) d2 += (c[d] - (*o)[d]) * (c[d] - (*o)[d]);
      if (d2 < (r + (*o)[3]) * (r + (*o)[3])) return true;
    }
    return false;
  };
  const int max_tries = 20000;
  for (int i = 0; i < s.count; ++i) {
    const Real r = p.r[i];
    bool placed = false;
    for (int t = 0; t < max_tries && !placed; ++t) {
      Vec3d c;
      for (int d = 0; d < 3; ++d) c[d] = r + rng.uniform() * (L - 2 * r);
      const int cx = cidx(c[0]), cy = cidx(c[1]), cz = cidx(c[2]);
      auto free_in = [&](size_t k) {
        const Sphere* in = slots.data() + k * size_t(K);
        return !overlaps(in, in + std::min(count[k], K), c, r) &&
               (count[k] <= K || !overlaps(overflow[k].data(), overflow[k].data() + overflow[k].size(), c, r));
      };
      // The try's own cell first: most rejected tries overlap a sphere there, and are then rejected after one cell.
      const size_t own = (size_t(cz) * nc + cy) * nc + cx;
      bool ok = free_in(own);
      for (int Z = std::max(0, cz - 1); Z <= std::min(nc - 1, cz + 1) && ok; ++Z)
        for (int Y = std::max(0, cy - 1); Y <= std::min(nc - 1, cy + 1) && ok; ++Y)
          for (int X = std::max(0, cx - 1); X <= std::min(nc - 1, cx + 1) && ok; ++X) {
            const size_t k = (size_t(Z) * nc + Y) * nc + X;
            if (k != own) ok = free_in(k);
          }
      if (ok) {
        const size_t k = own;
        const Sphere sp{c[0], c[1], c[2], r};
        if (count[k] < K) {
          slots[k * size_t(K) + size_t(count[k])] = sp;
        } else {
          if (overflow.empty()) overflow.resize(ncell);
          overflow[k].push_back(sp);
          ++q_overflowed;
        }
        ++count[k];
        placed = true;
      }
    }
    if (!placed) throw ParameterError(placement_failure(s, p.r, L, i, max_tries));
  }
  // Particles in cell order (z, y, x) so that neighbours are close in memory (better cache use in the kernels), in
  // the order they were placed within a cell: the cells read in turn, a pure function of the seed.
  Packing q = p;
  q.x.resize(size_t(s.count));
  q.overflowed = q_overflowed;
  size_t n = 0;
  for (size_t k = 0; k < ncell; ++k)
    for (int j = 0; j < count[k]; ++j) {
      const Sphere& sp = j < K ? slots[k * size_t(K) + size_t(j)] : overflow[k][size_t(j - K)];
      q.x[n] = {sp[0], sp[1], sp[2]};
      q.r[n++] = sp[3];
    }
  return q;
}

std::vector<int> spatial_order(const std::vector<Vec3d>& x, Real cell) {
  if (!(cell > 0)) throw ParameterError("spatial_order: cell edge must be > 0");
  Vec3d lo = x.empty() ? Vec3d{0, 0, 0} : x[0];
  for (const auto& p : x)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]);
  // Interleave the bits of the three 21-bit cell coordinates.
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  std::vector<std::uint64_t> key(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    std::uint64_t c[3];
    for (int k = 0; k < 3; ++k) c[k] = std::uint64_t(std::min((x[i][k] - lo[k]) / cell, Real(0x1fffff)));
    key[i] = spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2;
  }
  std::vector<int> order(x.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  return order;
}

}  // namespace grainlab
